//! Scenario files (TOML) for `kestrel run`: the format a navigation
//! engineer writes by hand, read into a [`Scenario`].
//!
//! The tables mirror the scenario: `[scenario]`, `[trajectory]` with
//! `[[trajectory.segment]]`, `[imu]`, optional `[gnss]`, `[odometer]`,
//! `[attitude]`, `[initial_errors]`, `[filter]` (with `[filter.imu]`,
//! `[filter.p0]`, `[filter.r]`) and `[[filters]]`. Every key names its unit
//! (`gyro_bias_deg_per_h`, `position_std_m`); per-axis values are one
//! number or an array of three. The shipped `scenarios/paper-00X.toml`
//! files reproduce the built-in scenarios exactly.

mod convert;
mod convert_filter;
mod convert_gnss;
mod convert_sensors;
mod convert_trajectory;
mod emit_filters;
mod emit_sections;
mod emit_sensors;
mod schema;
mod schema_filter;
mod schema_sensors;

use std::path::Path;

use crate::scenario::Scenario;

use crate::config::read::Source;
use crate::config::write::Writer;
use crate::{Error, InputError};

/// Reads the scenario file at `path`.
///
/// # Errors
/// [`Error::Input`] naming the file, line, column or key and what was
/// expected.
///
/// ```no_run
/// let s = kestrel_app::config::scenario::load(std::path::Path::new("scenarios/paper-000.toml"))?;
/// assert_eq!(s.name, "000");
/// # Ok::<(), kestrel_app::Error>(())
/// ```
pub fn load(path: &Path) -> Result<Scenario, Error> {
    load_recorded(path).map(|(s, _)| s)
}

/// As [`load`], with what was read of the file (its size and hash, for a
/// manifest). The file is read once, at most
/// [`MAX_CONFIG_BYTES`](crate::config::read::MAX_CONFIG_BYTES) of it.
///
/// # Errors
/// As [`load`].
pub fn load_recorded(path: &Path) -> Result<(Scenario, kestrel_io::input::Tally), Error> {
    let (text, tally) = crate::config::read::read_config(path)?;
    Ok((parse(&text, path)?, tally))
}

/// Reads a scenario from the TOML `text`; `file` names it in errors.
///
/// # Errors
/// An [`InputError`] naming `file`, the line and column, the key path
/// (`filters[1].reserve`, arrays counted from 0) and what was expected.
///
/// ```
/// use std::path::Path;
/// let text = kestrel_app::config::scenario::to_toml(&kestrel_app::scenario::scenario_003());
/// let s = kestrel_app::config::scenario::parse(&text, Path::new("003.toml")).unwrap();
/// assert_eq!(s, kestrel_app::scenario::scenario_003());
///
/// let bad = text.replace("window = 20", "window = 30");
/// let e = kestrel_app::config::scenario::parse(&bad, Path::new("003.toml")).unwrap_err();
/// assert!(e.to_string().contains("expected 10, 20 or 50"));
/// ```
pub fn parse(text: &str, file: &Path) -> Result<Scenario, InputError> {
    let source = Source::new(text, file);
    let parsed: schema::ScenarioFile = source.parse()?;
    convert::scenario(parsed).map_err(|b| source.bad(b))
}

/// The scenario as a scenario file, every key commented; reading it back
/// gives an equal scenario whenever each value is the conversion of a
/// decimal number of at most 17 digits in one of the key's units (true of
/// everything built from decimal constants).
///
/// ```
/// use std::path::Path;
/// let s = kestrel_app::scenario::scenario_001();
/// let text = kestrel_app::config::scenario::to_toml(&s);
/// assert!(text.contains("[[filters]]"));
/// assert_eq!(kestrel_app::config::scenario::parse(&text, Path::new("x.toml")).unwrap(), s);
/// ```
pub fn to_toml(s: &Scenario) -> String {
    let mut w = Writer::default();
    emit_sections::write(&mut w, s);
    w.out
}
