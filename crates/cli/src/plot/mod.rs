//! Error and adapter plots (PNG and SVG) drawn with plotters and a shipped font.
//!
//! [`error_figures`] writes four figures into a directory, each as
//! `<name>.png` (1200 px wide) and `<name>.svg`, names as in [`FIGURES`]:
//!
//! | file | panels |
//! |---|---|
//! | `position.png`, `position.svg` | position error per axis, m, in the run's [`PositionAxes`] |
//! | `velocity.png`, `velocity.svg` | velocity error north, east, down, m/s |
//! | `attitude.png`, `attitude.svg` | attitude error φ north, east, down, arcmin (degrees when some error exceeds 2°) |
//! | `adaptation.png`, `adaptation.svg` | one panel per adapter quantity some filter changed (fading factor λ, R inflation, innovation compression, odometer gain α₁, trace of R), then the NIS of every filter on a log axis |
//!
//! One line per filter in the order given (baseline first), one legend
//! under the title. Lines break where the time step exceeds five times the
//! median step (an outage). Long series are thinned to two points per pixel column
//! keeping each bucket's extremes, so spikes survive. A filter whose error
//! is over ten times the next-worst filter's would flatten the others: it
//! is clipped to the panel's edge and named with its peak in the panel
//! caption. Non-finite values are skipped.

mod figure;
mod font;
mod legend;
mod palette;
mod panels;
mod process_figures;
mod range;
mod save;
mod sensitivity;
mod thin;
mod ticks;
mod track;

use std::path::{Path, PathBuf};

use kestrel_app::experiment::{EpochRecord, PositionAxes};

pub use process_figures::{process_figures, ProcessPlots, SolutionErrors, PROCESS_FIGURES};
pub use sensitivity::sensitivity_figure;
pub use thin::{split_at_gaps, thin};

use crate::CliError;
use figure::{Figure, Reference};

/// The figures [`error_figures`] writes, in order; each is written as
/// `<name>.png` and `<name>.svg`.
///
/// ```
/// assert_eq!(kestrel_cli::plot::FIGURES[0], "position");
/// ```
pub const FIGURES: [&str; 4] = ["position", "velocity", "attitude", "adaptation"];

/// One filter's records to plot, with its label.
#[derive(Clone, Copy, Debug)]
pub struct FilterTrace<'a> {
    /// The filter's name, shown in the legend.
    pub label: &'a str,
    /// Its aiding epochs in time order.
    pub records: &'a [EpochRecord],
}

/// What [`error_figures_with`] can be told besides the traces.
///
/// ```
/// let o = kestrel_cli::plot::FigureOptions::default();
/// assert_eq!((o.nis_dof, o.nis_probability), (None, 0.99));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FigureOptions {
    /// Rows of the measurement, if all updates have the same: the NIS panel
    /// then shows the χ² bound with this many degrees of freedom.
    pub nis_dof: Option<usize>,
    /// Probability of the χ² bound.
    pub nis_probability: f64,
}

impl Default for FigureOptions {
    fn default() -> Self {
        Self {
            nis_dof: None,
            nis_probability: 0.99,
        }
    }
}

/// Draws the position, velocity and attitude error figures and the adapter
/// figure (λ, inflation, α1, NIS) of `traces` into `dir`, each as PNG and
/// SVG; returns the files written.
///
/// # Errors
/// [`CliError`] if a file cannot be written or drawing fails.
///
/// ```
/// use kestrel_cli::plot::{error_figures, FilterTrace};
/// use kestrel_app::experiment::{Adaptation, EpochRecord, PositionAxes};
/// use kestrel::nav::nalgebra::Vector3;
/// let records: Vec<EpochRecord> = (0..50)
///     .map(|i| EpochRecord { time: i as f64, position: Vector3::new(1.0, -1.0, 0.5),
///         velocity: Vector3::zeros(), attitude: Vector3::zeros(),
///         adaptation: Adaptation { nis: 2.0, ..Adaptation::default() }, position_nees: None })
///     .collect();
/// let dir = std::env::temp_dir().join("kestrel-doc-figures");
/// let traces = [FilterTrace { label: "KF", records: &records }];
/// let files = error_figures(&dir, "example", PositionAxes::NorthEastDown, &traces).unwrap();
/// assert_eq!(files.len(), 8);
/// assert!(files[0].ends_with("position.png"));
/// ```
pub fn error_figures(
    dir: &Path,
    title: &str,
    axes: PositionAxes,
    traces: &[FilterTrace<'_>],
) -> Result<Vec<PathBuf>, CliError> {
    error_figures_with(dir, title, axes, traces, &FigureOptions::default())
}

/// As [`error_figures`], with `options`.
///
/// # Errors
/// As [`error_figures`].
///
/// ```
/// use kestrel_cli::plot::{error_figures_with, FigureOptions};
/// use kestrel_app::experiment::PositionAxes;
/// let dir = std::env::temp_dir().join("kestrel-doc-empty-figures");
/// let options = FigureOptions { nis_dof: Some(3), ..FigureOptions::default() };
/// let files = error_figures_with(&dir, "nothing yet", PositionAxes::EastNorthUp, &[], &options);
/// assert_eq!(files.unwrap().len(), 8);
/// ```
pub fn error_figures_with(
    dir: &Path,
    title: &str,
    axes: PositionAxes,
    traces: &[FilterTrace<'_>],
    options: &FigureOptions,
) -> Result<Vec<PathBuf>, CliError> {
    figures_of(dir, title, axes, traces, traces, options)
}

/// As [`error_figures_with`] with the errors drawn from `errors` (say every
/// epoch compared with a reference) and the adapter activity from `aiding`
/// (the aiding epochs), the same filters in the same order.
///
/// # Errors
/// As [`error_figures`].
pub fn figures_of(
    dir: &Path,
    title: &str,
    axes: PositionAxes,
    errors: &[FilterTrace<'_>],
    aiding: &[FilterTrace<'_>],
    options: &FigureOptions,
) -> Result<Vec<PathBuf>, CliError> {
    let traces = errors;
    std::fs::create_dir_all(dir).map_err(|e| CliError::io(dir, e))?;
    let filters: Vec<String> = traces.iter().map(|t| t.label.to_string()).collect();
    let nis_bound = nis_bound(options);
    let figures = [
        ("position error", panels::position(traces, axes)),
        ("velocity error", panels::velocity(traces)),
        ("attitude error", panels::attitude(traces)),
        ("adapter activity", panels::adaptation(aiding, nis_bound)),
    ];
    let mut written = Vec::with_capacity(2 * FIGURES.len());
    for ((what, panels), stem) in figures.into_iter().zip(FIGURES) {
        let figure = Figure {
            title: if title.is_empty() {
                what.to_string()
            } else {
                format!("{title}: {what}")
            },
            filters: filters.clone(),
            panels,
        };
        written.extend(figure.save(dir, stem)?);
    }
    Ok(written)
}

/// The adapter-activity figure alone (`adaptation.png`, `.svg`): λ,
/// inflation, α₁ and the NIS of `aiding`.
///
/// # Errors
/// As [`error_figures`].
pub fn adaptation_figure(
    dir: &Path,
    title: &str,
    aiding: &[FilterTrace<'_>],
    options: &FigureOptions,
) -> Result<Vec<PathBuf>, CliError> {
    std::fs::create_dir_all(dir).map_err(|e| CliError::io(dir, e))?;
    let nis_bound = nis_bound(options);
    let figure = Figure {
        title: if title.is_empty() {
            "adapter activity".to_owned()
        } else {
            format!("{title}: adapter activity")
        },
        filters: aiding.iter().map(|t| t.label.to_string()).collect(),
        panels: panels::adaptation(aiding, nis_bound),
    };
    figure.save(dir, "adaptation")
}

/// The NIS panel's χ² bound line, when the options give its degrees of
/// freedom.
fn nis_bound(options: &FigureOptions) -> Option<Reference> {
    options.nis_dof.and_then(|dof| {
        let value = kestrel::adaptive::chi_square_quantile(options.nis_probability, dof).ok()?;
        Some(Reference {
            value,
            label: format!(
                "χ² bound, {dof} dof, p = {} ({value:.2})",
                options.nis_probability
            ),
        })
    })
}
