//! Recorded data through kestrel's navigation filters: the readers of IMU,
//! GNSS, odometer and reference files, the processing configuration, and
//! the streaming INS/GNSS(/odometer) pipeline behind `kestrel process`.
//!
//! - [`gins`]: readers and writers of the open GINS text formats, RTKLIB
//!   `.pos` and configurable IMU columns, units, axes and time bases. Every
//!   problem is an [`InputError`] naming the file, line and column.
//! - [`process`]: the configuration ([`process::config`]), the pipeline
//!   ([`process::process`]) and its report, the evaluation against a
//!   reference (errors at every reference epoch, drift per outage).
//! - [`output`]: the per-epoch error CSV.
//!
//! Processing a log takes a few lines (the files are those of
//! `examples/data`, 5 s of a simulated drive):
//!
//! ```
//! use kestrel_io::process::{process, summary, Inputs, Silent};
//! let data = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data");
//! let out = std::env::temp_dir().join(format!("kestrel-io-doc-{}", std::process::id()));
//! let mut inputs = Inputs::new(format!("{data}/imu.txt"), format!("{data}/process.toml"), &out);
//! inputs.gnss = Some(format!("{data}/gnss.txt").into());
//! inputs.truth = Some(format!("{data}/truth.nav").into());
//! let run = process(&inputs, &mut Silent)?;
//! print!("{}", summary(&run.report));
//! assert_eq!(run.report.samples, 250);
//! # std::fs::remove_dir_all(&out)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The file shapes, the configuration keys and the outputs are described in
//! the repository's `docs/processing.md`.

#![deny(missing_docs)]

pub mod error;
pub mod gins;
pub mod output;
pub mod process;

pub use error::{Error, InputError, Location};

/// The README's Rust examples, compiled and run as doc tests here: this
/// crate sees both `kestrel` and `kestrel_io`, which the examples use.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;

/// The Rust example of `docs/processing.md`, compiled as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/processing.md")]
pub struct ProcessingDoctests;
