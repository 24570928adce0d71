//! The library behind the `kestrel` command-line tool: each command maps
//! its arguments to a call of `kestrel-app` and presents the result
//! (printing, progress bars, figures).
//!
//! It exists so the binary stays a thin argument parser and the commands can
//! be tested directly; it is not a stable API.

pub mod demo;
pub mod import;
pub mod out;
pub mod plot;
pub mod process;
pub mod progress;
pub mod reproduce;
pub mod signals;
pub mod simulate;

/// What every command gets from the process it runs in: the cancellation
/// token the signal handlers set, and the command line (for manifests).
#[derive(Clone, Debug, Default)]
pub struct Context {
    /// Set by SIGINT / SIGTERM.
    pub cancel: kestrel_app::transaction::Cancel,
    /// The command line.
    pub command: Vec<String>,
}

/// Everything a command can fail with: the error of `kestrel-app`.
pub type CliError = kestrel_app::Error;
pub use kestrel_app::{InputError, Location};
