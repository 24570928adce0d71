//! The legend: a line sample and the label of each filter in rows under
//! the title, where it can never hide data.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::WIDTH;
use super::font::FAMILY;
use super::palette::colour;

/// Height of a legend row, px.
const ROW: i32 = 24;
/// Left edge of the legend, px (the plots' left edge).
pub(crate) const LEFT: i32 = 85;
/// Length of a line sample, px.
const SAMPLE: i32 = 28;

fn style() -> TextStyle<'static> {
    TextStyle::from((FAMILY, 16).into_font()).color(&BLACK)
}

/// Where each entry goes, (x px, row), given the label widths: wrapped at
/// the figure's width.
fn layout(widths: &[u32]) -> Vec<(i32, i32)> {
    let (mut x, mut row) = (LEFT, 0);
    let mut out = Vec::with_capacity(widths.len());
    for &w in widths {
        let item = SAMPLE + 6 + w as i32 + 30;
        if x + item > WIDTH as i32 - 10 && x > LEFT {
            x = LEFT;
            row += 1;
        }
        out.push((x, row));
        x += item;
    }
    out
}

/// Draws the legend of `labels` at the top of `area`; returns the part of
/// `area` below it.
pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    labels: &[String],
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let style = style();
    let mut widths = Vec::with_capacity(labels.len());
    for label in labels {
        widths.push(area.estimate_text_size(label, &style)?.0);
    }
    let places = layout(&widths);
    let rows = places.last().map_or(0, |p| p.1 + 1);
    let (legend, rest) = area.split_vertically((ROW * rows + 6) as u32);
    for (i, (label, &(x, row))) in labels.iter().zip(&places).enumerate() {
        let y = ROW * row + ROW / 2;
        let line = PathElement::new(vec![(x, y), (x + SAMPLE, y)], colour(i).stroke_width(3));
        legend.draw(&line)?;
        legend.draw_text(label, &style, (x + SAMPLE + 6, y - 9))?;
    }
    Ok(rest)
}
