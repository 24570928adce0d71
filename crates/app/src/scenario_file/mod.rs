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

mod check;
mod convert;
mod convert_filter;
mod convert_gnss;
mod convert_sensors;
mod convert_trajectory;
mod emit;
mod emit_filters;
mod emit_sections;
mod emit_sensors;
mod locate;
mod schema;
mod schema_filter;
mod schema_sensors;
mod units;
mod vec3;

use std::path::Path;

use crate::scenario::Scenario;

pub use emit::to_toml;

use crate::{Error, InputError};
use check::Bad;
use locate::{line_column, Places};

/// Reads the scenario file at `path`.
///
/// # Errors
/// [`Error::Input`] naming the file, line, column or key and what was
/// expected.
///
/// ```no_run
/// let s = kestrel_app::scenario_file::load(std::path::Path::new("scenarios/paper-000.toml"))?;
/// assert_eq!(s.name, "000");
/// # Ok::<(), kestrel_app::Error>(())
/// ```
pub fn load(path: &Path) -> Result<Scenario, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::file(path, format!("cannot read the scenario file: {e}")))?;
    Ok(parse(&text, path)?)
}

/// Reads a scenario from the TOML `text`; `file` names it in errors.
///
/// # Errors
/// An [`InputError`] naming `file`, the line and column, the key path
/// (`filters[1].reserve`, arrays counted from 0) and what was expected.
///
/// ```
/// use std::path::Path;
/// let text = kestrel_app::scenario_file::to_toml(&kestrel_app::scenario::scenario_003());
/// let s = kestrel_app::scenario_file::parse(&text, Path::new("003.toml")).unwrap();
/// assert_eq!(s, kestrel_app::scenario::scenario_003());
///
/// let bad = text.replace("window = 20", "window = 30");
/// let e = kestrel_app::scenario_file::parse(&bad, Path::new("003.toml")).unwrap_err();
/// assert!(e.to_string().contains("must be one of 10, 20, 50"));
/// ```
pub fn parse(text: &str, file: &Path) -> Result<Scenario, InputError> {
    let places = Places::new(text);
    let parsed: schema::ScenarioFile = toml::from_str(text).map_err(|e| {
        let message = rephrase(e.message());
        match e.span() {
            Some(span) => {
                let (line, column) = line_column(text, span.start);
                let err = InputError::at(file, line, column, message);
                match places.path_at(span.start) {
                    Some(key) => err.with_key(key),
                    None => err,
                }
            }
            None => InputError::file(file, message),
        }
    })?;
    convert::scenario(parsed).map_err(|Bad { key, message }| {
        let err = match places.span_of(&key) {
            Some(span) => {
                let (line, column) = line_column(text, span.start);
                InputError::at(file, line, column, message)
            }
            None => InputError::file(file, message),
        };
        err.with_key(key)
    })
}

/// The TOML reader's message in the file's vocabulary, on one line.
fn rephrase(message: &str) -> String {
    let one_line = message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    one_line
        .replace("unknown field", "unknown key")
        .replace("missing field", "missing key")
        .replace("unknown variant", "unknown value")
        .replace("there are no fields", "this table takes no keys")
        .replace("expected f64", "expected a number")
        .replace("expected u64", "expected a non-negative integer")
        .replace("expected i64", "expected an integer")
        .replace("expected a string", "expected a quoted string")
}
