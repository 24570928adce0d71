//! `kestrel process` (being written).

use clap::Args;

use crate::CliError;

/// Arguments of `kestrel process`.
#[derive(Debug, Args)]
pub struct ProcessArgs {}

/// Runs `kestrel process`.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn run(args: &ProcessArgs) -> Result<(), CliError> {
    let _ = args;
    Err(CliError::Failed("not available yet".into()))
}
