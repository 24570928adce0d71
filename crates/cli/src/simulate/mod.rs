//! `kestrel simulate` (being written).

use clap::Args;

use crate::CliError;

/// Arguments of `kestrel simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {}

/// Runs `kestrel simulate`.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn run(args: &SimulateArgs) -> Result<(), CliError> {
    let _ = args;
    Err(CliError::Failed("not available yet".into()))
}
