//! The library behind the `kestrel` command-line tool: the commands, the
//! open GINS text formats, scenario files, tables, CSV and plots.
//!
//! It exists so the binary stays a thin argument parser and the commands can
//! be tested directly; it is not a stable API.

pub mod demo;
pub mod error;
pub mod gins;
pub mod import;
pub mod output;
pub mod plot;
pub mod process;
pub mod reproduce;
pub mod scenario_file;
pub mod simulate;

pub use error::{CliError, InputError, Location};
