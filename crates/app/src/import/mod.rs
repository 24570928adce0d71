//! `kestrel import kf-gins FILE.yaml`: a KF-GINS configuration as the
//! equivalent, commented `process` configuration.
//!
//! KF-GINS (i2Nav, Wuhan University) states its initial accelerometer bias
//! and bias noise in mGal, correlation times in hours and scale factors in
//! ppm; kestrel's configuration takes µg and seconds. Every value is
//! converted so that kestrel's own conversion to SI gives exactly the SI
//! value KF-GINS uses (1 mGal = 1e-5 m/s² = 10 / 9.806 65 µg ≈ 1.0197 µg —
//! taking mGal for µg is a 2 % error). What kestrel cannot express yet is
//! refused with the reason, or — for KF-GINS's scale-factor states, which
//! kestrel's error models do not have — left out with a warning in the
//! file and on stderr.

mod kf_gins;
mod yaml;

use std::path::Path;

use crate::config::read::read_config;
use crate::transaction::{publish_file, Begin};
use crate::Error;

pub use kf_gins::kf_gins;

/// The TOML and the warnings of an import.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// The `process` configuration, commented.
    pub toml: String,
    /// What was left out, one line each.
    pub warnings: Vec<String>,
    /// The `kestrel process` command for the files the YAML names.
    pub command: String,
}

/// Imports the KF-GINS configuration `file`: [`kf_gins`] on its text (read
/// once, at most
/// [`MAX_CONFIG_BYTES`](crate::config::read::MAX_CONFIG_BYTES) of it), and the TOML written to
/// `out` when given, through [`publish_file`]: whole or not at all, never
/// onto the input by any spelling of its path, an existing `out` replaced
/// only with `force` (a symbolic link replaced itself, never written
/// through).
///
/// # Errors
/// [`Error`] naming the file and key of what cannot be imported, or the
/// output that cannot be written.
pub fn import_kf_gins(file: &Path, out: Option<&Path>, force: bool) -> Result<Imported, Error> {
    let (text, _) = read_config(file)?;
    let imported = kf_gins(&text, file, out)?;
    if let Some(out) = out {
        let begin = Begin {
            force,
            ..Begin::default().input("KF-GINS configuration", file)
        };
        publish_file(out, imported.toml.as_bytes(), &begin)?;
    }
    Ok(imported)
}
