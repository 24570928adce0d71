//! The library behind the `kestrel` command-line tool: the commands,
//! scenario files, tables and plots. Reading and processing recorded data
//! lives in `kestrel-io`, which the `process` command drives.
//!
//! It exists so the binary stays a thin argument parser and the commands can
//! be tested directly; it is not a stable API.

pub mod demo;
pub mod import;
pub mod plot;
pub mod process;
pub mod reproduce;
pub mod scenario_file;
pub mod simulate;

/// Everything a command can fail with: the error of `kestrel-io`.
pub type CliError = kestrel_io::Error;
pub use kestrel_io::{InputError, Location};
