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

use crate::{Error, InputError};

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

/// Imports the KF-GINS configuration `file`: [`kf_gins`] on its text, and
/// the TOML written to `out` when given (an existing `out` is replaced only
/// with `force`; `out` must not be the input).
///
/// # Errors
/// [`Error`] naming the file and key of what cannot be imported, or the
/// output that cannot be written.
pub fn import_kf_gins(file: &Path, out: Option<&Path>, force: bool) -> Result<Imported, Error> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| InputError::file(file, format!("cannot read the file: {e}")))?;
    let imported = kf_gins(&text, file, out)?;
    if let Some(out) = out {
        if std::fs::symlink_metadata(out).is_ok() && !force {
            return Err(Error::Failed(format!(
                "refusing to overwrite {}: it exists (pass --force to replace it)",
                out.display()
            )));
        }
        if out == file {
            return Err(Error::Failed(format!(
                "refusing to write {}: it is the input",
                out.display()
            )));
        }
        std::fs::write(out, &imported.toml).map_err(|e| Error::io(out, e))?;
    }
    Ok(imported)
}
