//! Scenario files (TOML) for `kestrel run` (being written).

use std::path::Path;

use kestrel::nav::scenario::Scenario;

use crate::CliError;

/// Reads the scenario file at `path`.
///
/// # Errors
/// [`CliError::Input`] naming the file, line, column or key and what was
/// expected.
pub fn load(path: &Path) -> Result<Scenario, CliError> {
    Err(crate::InputError::file(path, "not available yet").into())
}
