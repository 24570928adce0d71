//! The sensitivity figure: per variant, the favoured filter's improvement
//! over the baseline (median and interquartile range over seeds) on a
//! logarithmic axis, one row per variant, coloured by paper.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::WIDTH;
use super::font::FAMILY;
use super::palette::colour;
use super::save::{save_png_and_svg, Drawing};
use crate::CliError;
use kestrel_app::reproduce::StudyRow;

/// Height of one variant's row, px.
const ROW: u32 = 30;
/// Title, axis and margins, px.
const FRAME: u32 = 150;
/// Width of the row labels, px.
const LABELS: u32 = 560;

/// Writes `<dir>/<stem>.png` and `<dir>/<stem>.svg`: metric `metric` (an
/// index into [`STUDY_METRICS`](kestrel_app::reproduce::STUDY_METRICS)) of every
/// row. Nothing is written for no rows.
///
/// # Errors
/// [`CliError::Failed`] if a file cannot be drawn or written.
pub fn sensitivity_figure(
    dir: &Path,
    stem: &str,
    rows: &[StudyRow],
    metric: usize,
) -> Result<Vec<PathBuf>, CliError> {
    if rows.is_empty() {
        return Ok(Vec::new());
    }
    let size = (WIDTH, FRAME + ROW * rows.len() as u32);
    save_png_and_svg(&Sensitivity { rows, metric }, dir, stem, size)
}

/// The figure of one metric over the study's rows.
struct Sensitivity<'a> {
    rows: &'a [StudyRow],
    metric: usize,
}

impl Drawing for Sensitivity<'_> {
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(root, self.rows, self.metric)
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[StudyRow],
    metric: usize,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let what = kestrel_app::reproduce::STUDY_METRICS[metric];
    let title = format!(
        "Improvement of each paper's filter over its baseline ({what} RMS ratio), per variant"
    );
    let body = root.titled(&title, (FAMILY, 20)).map_err(e)?;
    // The x range covers every whisker and 1, in whole decades.
    let (mut lo, mut hi) = (1.0f64, 1.0f64);
    for q in rows.iter().filter_map(|r| r.ratios[metric]) {
        for v in [q.q1, q.q3] {
            if v.is_finite() && v > 0.0 {
                (lo, hi) = (lo.min(v), hi.max(v));
            }
        }
    }
    let (lo, hi) = (
        10f64.powf(lo.log10().floor()),
        10f64.powf(hi.log10().ceil()),
    );
    let n = rows.len() as f64;
    let label_of = |y: &f64| -> String {
        let y = *y;
        let i = (n - 1.0 - y).round();
        if (y - y.round()).abs() > 0.01 || i < 0.0 || i >= n {
            return String::new();
        }
        let r = &rows[i as usize];
        let mark = if r.headline { " *" } else { "" };
        format!("{}: {} vs {}{mark}", r.paper, r.variant, r.baseline)
    };
    let mut chart = ChartBuilder::on(&body)
        .margin(15)
        .margin_right(45)
        .x_label_area_size(45)
        .y_label_area_size(LABELS)
        .build_cartesian_2d((lo..hi).log_scale(), -0.5..n - 0.5)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("baseline RMS ÷ favoured filter's RMS (log scale; right of 1: the paper's filter is better; * = as reproduced)")
        .y_labels(rows.len())
        .y_label_formatter(&label_of)
        .label_style((FAMILY, 14))
        .axis_desc_style((FAMILY, 14))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(1.0, -0.5), (1.0, n - 0.5)],
            BLACK.stroke_width(2),
        )))
        .map_err(e)?;
    let mut papers: Vec<&str> = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        let Some(q) = r.ratios[metric] else { continue };
        if !papers.contains(&r.paper.as_str()) {
            papers.push(&r.paper);
        }
        let c = colour(papers.len() - 1);
        let y = n - 1.0 - i as f64;
        let clamp = |v: f64| v.clamp(lo, hi);
        chart
            .draw_series([
                PathElement::new(vec![(clamp(q.q1), y), (clamp(q.q3), y)], c.stroke_width(3)),
                PathElement::new(
                    vec![(clamp(q.q1), y - 0.2), (clamp(q.q1), y + 0.2)],
                    c.stroke_width(2),
                ),
                PathElement::new(
                    vec![(clamp(q.q3), y - 0.2), (clamp(q.q3), y + 0.2)],
                    c.stroke_width(2),
                ),
            ])
            .map_err(e)?;
        let marker = if r.headline {
            c.filled()
        } else {
            WHITE.filled()
        };
        chart
            .draw_series([
                Circle::new((clamp(q.median), y), 6, marker),
                Circle::new((clamp(q.median), y), 6, c.stroke_width(2)),
            ])
            .map_err(e)?;
    }
    root.present().map_err(e)
}
