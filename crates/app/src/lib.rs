//! # kestrel-app
//!
//! The kestrel application: what the command line (and any other front
//! end) runs, as library calls that take options and return results.
//!
//! - [`config`]: the one configuration model: the `process` configuration
//!   ([`config::process`]) and the scenario file format
//!   ([`config::scenario`]), read and written through the same types,
//!   units and checks.
//! - [`process`]: recorded IMU / GNSS (/ odometer) logs through the
//!   loosely coupled engine: alignment, the streaming pipeline, the RTS
//!   smoothing pass, the evaluation against a reference (errors, drift per
//!   outage, NEES).
//! - [`scenario`]: the papers' experiments as data (the built-in scenarios,
//!   the tuned baselines, the sensitivity study's variants).
//! - [`experiment`]: running a scenario's filters on its simulation.
//! - [`reproduce`]: Monte Carlo runs of a scenario's filters, the
//!   consistency check, the sensitivity study, tables beside the papers'.
//! - [`simulate`]: a scenario's sensors written as log files;
//!   [`import`]: other tools' configurations (KF-GINS) as `process` ones;
//!   [`output`]: the per-epoch error CSV; [`demo`]: the radar tracking demo;
//!   [`progress`]: how a long call reports its progress.
//!
//! Processing a log takes a few lines (the files are those of
//! `examples/data`, 5 s of a simulated drive):
//!
//! ```
//! use kestrel_app::process::{process, summary, Inputs, Silent};
//! let data = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data");
//! let out = std::env::temp_dir().join(format!("kestrel-app-doc-{}", std::process::id()));
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

pub mod config;
pub mod demo;
pub mod experiment;
pub mod fuzz;
pub mod import;
pub mod output;
pub mod process;
pub mod progress;
pub mod reproduce;
pub mod scenario;

pub mod simulate;
pub mod transaction;

pub use kestrel_io::{Error, InputError, Location};

/// The README's Rust examples, compiled and run as doc tests here: this
/// crate sees `kestrel`, `kestrel_io` and `kestrel_app`, which the
/// examples use.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;

/// The Rust example of `docs/processing.md`, compiled as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/processing.md")]
pub struct ProcessingDoctests;
