//! The font every figure is drawn with, shipped with the crate.
//!
//! plotters' `ab_glyph` text backend knows no system fonts: a family must be
//! registered before any text is measured or drawn, or every label fails.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle};

use crate::CliError;

/// The family name the figures ask for.
pub(crate) const FAMILY: &str = "sans-serif";

/// DejaVu Sans (see `assets/DejaVuSans-LICENSE.txt`): it has the Greek
/// letters, sub- and superscripts and the prime the labels use.
const DEJAVU_SANS: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Registers the font once per process; later calls return the first
/// outcome.
pub(crate) fn ensure_font() -> Result<(), CliError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok =
        *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok {
        Ok(())
    } else {
        Err(CliError::Failed("the embedded plot font is invalid".into()))
    }
}
