//! `kestrel reproduce`, `kestrel run` and `kestrel scenarios` (being written).

use std::path::PathBuf;

use clap::Args;

use crate::CliError;

/// Arguments of `kestrel reproduce`.
#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Which paper: 000, 001, 002, 003, 004 or all.
    pub which: String,
}

/// Arguments of `kestrel run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scenario file (TOML).
    pub scenario: PathBuf,
}

/// Runs `kestrel reproduce`.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn reproduce(args: &ReproduceArgs) -> Result<(), CliError> {
    let _ = args;
    Err(CliError::Failed("not available yet".into()))
}

/// Runs `kestrel run`.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn run_file(args: &RunArgs) -> Result<(), CliError> {
    let _ = args;
    Err(CliError::Failed("not available yet".into()))
}

/// Runs `kestrel scenarios`.
///
/// # Errors
/// Never.
pub fn list_scenarios() -> Result<(), CliError> {
    Ok(())
}
