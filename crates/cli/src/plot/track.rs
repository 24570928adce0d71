//! The track figure: north against east with equal scales, the fixes, and
//! the outage stretches of the forward solution marked.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::WIDTH;
use super::font::FAMILY;
use super::legend::draw_legend;
use super::palette::colour;
use super::save::{save_png_and_svg, Drawing};
use super::ticks::linear_ticks;
use crate::CliError;
use kestrel_app::process::Track;

/// Height of the track figure, px.
const HEIGHT: u32 = 1000;
/// Points drawn per line at most.
const MAX_POINTS: usize = 4000;

/// A legend entry and its pieces of line, (east, north) in metres.
type Layer = (String, Vec<Vec<(f64, f64)>>);

/// A titled track figure.
pub(crate) struct TrackFigure<'a> {
    pub title: String,
    pub track: &'a Track,
}

impl TrackFigure<'_> {
    /// Writes `<dir>/<stem>.png` and `<dir>/<stem>.svg`.
    pub(crate) fn save(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, CliError> {
        save_png_and_svg(self, dir, stem, (WIDTH, HEIGHT))
    }

    /// The legend entries and their line sets: forward, smoothed, fixes,
    /// forward in the outages.
    fn layers(&self) -> Vec<Layer> {
        let t = self.track;
        // (east, north) for the x-y axes, every k-th point (the records
        // are already thinned evenly in time; this bounds what is drawn).
        let xy = |points: &[(f64, f64, f64)]| -> Vec<(f64, f64)> {
            let stride = points.len().div_ceil(MAX_POINTS).max(1);
            points.iter().step_by(stride).map(|p| (p.2, p.1)).collect()
        };
        let inside = |time: f64| t.outages.iter().any(|&(a, b)| time >= a && time < b);
        let mut outage_pieces: Vec<Vec<(f64, f64)>> = Vec::new();
        let mut open = false;
        for p in &t.forward {
            if inside(p.0) {
                if !open {
                    outage_pieces.push(Vec::new());
                    open = true;
                }
                if let Some(piece) = outage_pieces.last_mut() {
                    piece.push((p.2, p.1));
                }
            } else {
                open = false;
            }
        }
        // Fixes first, so the lines are drawn over them.
        let mut layers = Vec::new();
        if !t.fixes.is_empty() {
            layers.push(("GNSS fixes used".to_owned(), vec![xy(&t.fixes)]));
        }
        layers.push(("forward".to_owned(), vec![xy(&t.forward)]));
        if !t.smoothed.is_empty() {
            layers.push(("smoothed".to_owned(), vec![xy(&t.smoothed)]));
        }
        if !outage_pieces.is_empty() {
            layers.push(("forward in the outages".to_owned(), outage_pieces));
        }
        layers
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let body = root.titled(&self.title, (FAMILY, 22)).map_err(e)?;
        let layers = self.layers();
        let labels: Vec<String> = layers.iter().map(|l| l.0.clone()).collect();
        let body = draw_legend(&body, &labels).map_err(e)?;
        let all = layers.iter().flat_map(|l| l.1.iter().flatten());
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for &(x, y) in all.filter(|p| p.0.is_finite() && p.1.is_finite()) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            return root.present().map_err(e);
        }
        // Equal scales: widen the narrower extent to the area's aspect.
        let (w, h) = body.dim_in_pixel();
        let (pw, ph) = (
            f64::from(w.saturating_sub(110)),
            f64::from(h.saturating_sub(70)),
        );
        let span = ((x1 - x0) / pw).max((y1 - y0) / ph).max(1e-3) * 1.05;
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let (x0, x1) = (cx - span * pw / 2.0, cx + span * pw / 2.0);
        let (y0, y1) = (cy - span * ph / 2.0, cy + span * ph / 2.0);
        let x_ticks = linear_ticks(x0, x1);
        let y_ticks = linear_ticks(y0, y1);
        let mut chart = ChartBuilder::on(&body)
            .margin(10)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("east (m)")
            .y_desc("north (m)")
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 15))
            .light_line_style(RGBColor(238, 238, 238))
            .bold_line_style(RGBColor(210, 210, 210))
            .x_label_formatter(&x_ticks)
            .y_label_formatter(&y_ticks)
            .draw()
            .map_err(e)?;
        for (i, (label, pieces)) in layers.iter().enumerate() {
            let c = colour(i);
            for piece in pieces {
                if label.starts_with("GNSS") {
                    chart
                        .draw_series(piece.iter().map(|p| Circle::new(*p, 2, c.filled())))
                        .map_err(e)?;
                } else {
                    let width = if label.contains("outages") { 3 } else { 1 };
                    chart
                        .draw_series(LineSeries::new(
                            piece.iter().copied(),
                            c.stroke_width(width),
                        ))
                        .map_err(e)?;
                }
            }
        }
        root.present().map_err(e)
    }
}

impl Drawing for TrackFigure<'_> {
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        self.draw(root)
    }
}
