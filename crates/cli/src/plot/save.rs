//! Writing a figure as PNG and SVG.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::ensure_font;
use crate::CliError;

/// A figure that can draw itself on any plotters backend.
pub(crate) trait Drawing {
    /// Draws the whole figure on `root`; errors as text.
    fn draw_on<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Writes `drawing` of `size` pixels as `<dir>/<stem>.png` and
/// `<dir>/<stem>.svg` and returns both paths.
///
/// # Errors
/// [`CliError::Failed`] naming the file that could not be drawn or written.
pub(crate) fn save_png_and_svg(
    drawing: &impl Drawing,
    dir: &Path,
    stem: &str,
    size: (u32, u32),
) -> Result<Vec<PathBuf>, CliError> {
    ensure_font()?;
    let failed = |p: &Path, e: String| CliError::Failed(format!("{}: {e}", p.display()));
    let png = dir.join(format!("{stem}.png"));
    drawing
        .draw_on(BitMapBackend::new(&png, size).into_drawing_area())
        .map_err(|e| failed(&png, e))?;
    let svg = dir.join(format!("{stem}.svg"));
    drawing
        .draw_on(SVGBackend::new(&svg, size).into_drawing_area())
        .map_err(|e| failed(&svg, e))?;
    Ok(vec![png, svg])
}
