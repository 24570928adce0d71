//! A figure of stacked panels sharing the time axis, drawn the same way to
//! PNG and SVG.

use std::path::{Path, PathBuf};

use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::FAMILY;
use super::legend::{draw_legend, LEFT};
use super::palette::colour;
use super::range::{linear_range, log_range, x_range, YRange};
use super::save::{save_png_and_svg, Drawing};
use super::thin::{split_at_gaps, thin};
use super::ticks::{compact, linear_ticks};
use crate::CliError;

/// Figure width, px.
pub(crate) const WIDTH: u32 = 1200;
/// Height of one panel, px.
pub(crate) const PANEL_HEIGHT: u32 = 260;
/// Height of the title and legend, px, assuming one legend row (the
/// panels get what a shorter legend leaves).
pub(crate) const HEADER_HEIGHT: u32 = 120;
/// Points drawn per series at most: two per pixel column.
const MAX_POINTS: usize = 2 * WIDTH as usize;

/// How a panel's y axis is scaled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Scale {
    Linear,
    Log,
}

/// One filter's line in a panel.
#[derive(Clone, Debug)]
pub(crate) struct Series {
    /// Index of the filter (its colour and legend entry).
    pub filter: usize,
    /// (time s, value), possibly with non-finite values, which are skipped.
    pub points: Vec<(f64, f64)>,
    /// Points marked with a cross (rejected updates).
    pub marks: Vec<(f64, f64)>,
}

/// A horizontal reference line.
#[derive(Clone, Debug)]
pub(crate) struct Reference {
    pub value: f64,
    pub label: String,
}

/// One panel.
#[derive(Clone, Debug)]
pub(crate) struct Panel {
    /// What is plotted, shown above the panel.
    pub caption: String,
    /// The y axis label with its unit.
    pub y_label: String,
    pub scale: Scale,
    pub series: Vec<Series>,
    pub reference: Option<Reference>,
}

/// A titled stack of panels with a legend of filter labels.
#[derive(Clone, Debug)]
pub(crate) struct Figure {
    pub title: String,
    /// Filter labels, in filter index order.
    pub filters: Vec<String>,
    pub panels: Vec<Panel>,
}

impl Figure {
    /// The figure's height: header plus one band per panel.
    pub(crate) fn height(&self) -> u32 {
        HEADER_HEIGHT + PANEL_HEIGHT * self.panels.len().max(1) as u32
    }

    /// Writes `<dir>/<stem>.png` and `<dir>/<stem>.svg`.
    pub(crate) fn save(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, CliError> {
        save_png_and_svg(self, dir, stem, (WIDTH, self.height()))
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let (title, size) = fit_title(&root, &self.title).map_err(e)?;
        let body = root.titled(&title, (FAMILY, size)).map_err(e)?;
        let body = draw_legend(&body, &self.filters).map_err(e)?;
        let x = x_range(
            self.panels
                .iter()
                .flat_map(|p| p.series.iter().map(|s| s.points.as_slice())),
        );
        if self.panels.is_empty() {
            let style = TextStyle::from((FAMILY, 20).into_font()).color(&BLACK);
            body.draw_text(
                "no data",
                &style,
                (WIDTH as i32 / 2 - 40, PANEL_HEIGHT as i32 / 2),
            )
            .map_err(e)?;
        }
        let areas = body.split_evenly((self.panels.len().max(1), 1));
        let last = self.panels.len().saturating_sub(1);
        for (i, (panel, area)) in self.panels.iter().zip(&areas).enumerate() {
            self.draw_panel(panel, area, x, i == last)?;
        }
        root.present().map_err(e)
    }

    fn draw_panel<DB: DrawingBackend>(
        &self,
        panel: &Panel,
        area: &DrawingArea<DB, Shift>,
        x: (f64, f64),
        last: bool,
    ) -> Result<(), String> {
        let series: Vec<&[(f64, f64)]> = panel.series.iter().map(|s| s.points.as_slice()).collect();
        let extra: Vec<f64> = panel.reference.iter().map(|r| r.value).collect();
        let range = match panel.scale {
            Scale::Linear => linear_range(&series, &extra),
            Scale::Log => log_range(&series, &extra),
        };
        let caption = caption(panel, &range, &self.filters);
        let drawn = Drawn::new(panel, &range);
        let x_ticks = linear_ticks(x.0, x.1);
        let y_ticks = linear_ticks(range.lo, range.hi);
        let ticks: [&dyn Fn(&f64) -> String; 2] = match panel.scale {
            Scale::Linear => [&x_ticks, &y_ticks],
            Scale::Log => [&x_ticks, &compact],
        };
        let c = Chart {
            caption: &caption,
            panel,
            x,
            ticks,
            drawn: &drawn,
            last,
        };
        match panel.scale {
            Scale::Linear => c.draw(area, range.lo..range.hi),
            Scale::Log => c.draw(area, (range.lo..range.hi).log_scale()),
        }
    }
}

impl Drawing for Figure {
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        self.draw(root)
    }
}

/// The title and its font size: 24 px, smaller down to 14 px if it is too
/// wide, then shortened with an ellipsis.
fn fit_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<(String, f64), DrawingAreaErrorKind<DB::ErrorType>> {
    let room = WIDTH - 20;
    let width = |text: &str, size: f64| {
        area.estimate_text_size(text, &TextStyle::from((FAMILY, size).into_font()))
            .map(|s| s.0)
    };
    let mut size = 24.0;
    while size > 14.0 && width(title, size)? > room {
        size -= 1.0;
    }
    let mut text = title.to_string();
    while width(&text, size)? > room && text.chars().count() > 1 {
        text.pop();
        text.pop();
        text.push('…');
    }
    Ok((text, size))
}

/// The panel caption, naming the series drawn off scale and their peaks.
fn caption(panel: &Panel, range: &YRange, filters: &[String]) -> String {
    let mut caption = panel.caption.clone();
    if let Some(r) = &panel.reference {
        caption.push_str(&format!("; grey line: {}", r.label));
    }
    if !range.off_scale.is_empty() {
        let names: Vec<String> = range
            .off_scale
            .iter()
            .map(|&(i, peak)| {
                let f = panel.series[i].filter;
                let name = filters.get(f).map_or("?", String::as_str);
                format!("{name} (peak {})", compact(&peak))
            })
            .collect();
        caption.push_str(&format!("; clipped, off scale: {}", names.join(", ")));
    }
    caption
}

/// A panel's series cut at gaps, thinned, and clamped into the range so an
/// off-scale line runs along the edge instead of leaving the panel.
struct Drawn {
    /// (filter, pieces of its line).
    lines: Vec<(usize, Vec<Line>)>,
    marks: Vec<(usize, Line)>,
}

/// Points of a line, (time s, value).
type Line = Vec<(f64, f64)>;

impl Drawn {
    fn new(panel: &Panel, range: &YRange) -> Self {
        let log = panel.scale == Scale::Log;
        let visible = |points: &[(f64, f64)]| -> Vec<(f64, f64)> {
            points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite() && (!log || p.1 > 0.0))
                .collect()
        };
        let clamp = |p: (f64, f64)| (p.0, p.1.clamp(range.lo, range.hi));
        let pieces = |points: &[(f64, f64)]| -> Vec<Line> {
            let points = visible(points);
            split_at_gaps(&points)
                .into_iter()
                .map(|part| {
                    // Each piece gets its share of the point budget.
                    let budget = MAX_POINTS * part.len() / points.len().max(1);
                    thin(part, budget).into_iter().map(clamp).collect()
                })
                .collect()
        };
        Self {
            lines: panel
                .series
                .iter()
                .map(|s| (s.filter, pieces(&s.points)))
                .collect(),
            marks: panel
                .series
                .iter()
                .map(|s| {
                    let marks = thin(&visible(&s.marks), MAX_POINTS);
                    (s.filter, marks.into_iter().map(clamp).collect())
                })
                .collect(),
        }
    }
}

/// One panel's chart: what to draw and how to label it.
struct Chart<'a> {
    caption: &'a str,
    panel: &'a Panel,
    /// The time range, s.
    x: (f64, f64),
    /// Tick label formats of the x and y axes.
    ticks: [&'a dyn Fn(&f64) -> String; 2],
    drawn: &'a Drawn,
    /// Whether this is the bottom panel, which carries the time label.
    last: bool,
}

impl Chart<'_> {
    fn draw<DB, Y>(&self, area: &DrawingArea<DB, Shift>, y: Y) -> Result<(), String>
    where
        DB: DrawingBackend,
        Y: AsRangedCoord<Value = f64>,
        Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let x = self.x;
        let mut chart = ChartBuilder::on(area)
            .caption(self.caption, (FAMILY, 16))
            .margin_left(10)
            .margin_right(24)
            .margin_top(4)
            .margin_bottom(4)
            .x_label_area_size(if self.last { 44 } else { 24 })
            .y_label_area_size(LEFT as u32 - 10)
            .build_cartesian_2d(x.0..x.1, y)
            .map_err(e)?;
        let mut mesh = chart.configure_mesh();
        mesh.y_desc(self.panel.y_label.as_str())
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 15))
            .light_line_style(RGBColor(238, 238, 238))
            .bold_line_style(RGBColor(210, 210, 210))
            .y_labels(6)
            .x_labels(12)
            .x_label_formatter(self.ticks[0])
            .y_label_formatter(self.ticks[1]);
        if self.last {
            mesh.x_desc("time (s)");
        }
        mesh.draw().map_err(e)?;
        if let Some(r) = &self.panel.reference {
            let grey = RGBColor(120, 120, 120);
            let line = [(x.0, r.value), (x.1, r.value)];
            chart
                .draw_series(LineSeries::new(line, grey.stroke_width(2)))
                .map_err(e)?;
        }
        for (filter, pieces) in &self.drawn.lines {
            let style = colour(*filter).stroke_width(1);
            for piece in pieces {
                if let [point] = piece.as_slice() {
                    // A lone epoch between gaps has no line: show it as a dot.
                    let dot = Circle::new(*point, 2, colour(*filter).filled());
                    chart.draw_series([dot]).map_err(e)?;
                } else {
                    chart
                        .draw_series(LineSeries::new(piece.iter().copied(), style))
                        .map_err(e)?;
                }
            }
        }
        for (filter, points) in &self.drawn.marks {
            let c = colour(*filter);
            chart
                .draw_series(points.iter().map(|p| Cross::new(*p, 4, c.stroke_width(1))))
                .map_err(e)?;
        }
        Ok(())
    }
}
