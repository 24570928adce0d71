//! `kestrel import kf-gins FILE.yaml`: a KF-GINS configuration as the
//! equivalent, commented `process` configuration
//! ([`kestrel_app::import`]).

use std::path::PathBuf;

use clap::{Args, Subcommand};
use kestrel_app::import::import_kf_gins;

use crate::CliError;

/// Arguments of `kestrel import`.
#[derive(Clone, Debug, Args)]
pub struct ImportArgs {
    /// The configuration's format.
    #[command(subcommand)]
    pub format: ImportFormat,
}

/// The formats `kestrel import` reads.
#[derive(Clone, Debug, Subcommand)]
pub enum ImportFormat {
    /// A KF-GINS YAML configuration.
    KfGins(KfGinsArgs),
}

/// Arguments of `kestrel import kf-gins`.
#[derive(Clone, Debug, Args)]
pub struct KfGinsArgs {
    /// The KF-GINS configuration (YAML).
    #[arg(value_name = "FILE.yaml")]
    pub file: PathBuf,
    /// Where to write the TOML (default: standard output).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Replace an existing --out file.
    #[arg(long)]
    pub force: bool,
}

/// Runs `kestrel import`: the warnings on stderr, the TOML on stdout or in
/// `--out` (then the command that runs it on stderr).
///
/// # Errors
/// [`CliError`] naming the file and key of what cannot be imported.
pub fn run(args: &ImportArgs) -> Result<(), CliError> {
    let ImportFormat::KfGins(a) = &args.format;
    let imported = import_kf_gins(&a.file, a.out.as_deref(), a.force)?;
    for w in &imported.warnings {
        crate::errln!("warning: {w}")?;
    }
    match &a.out {
        None => crate::out::print(&imported.toml)?,
        Some(out) => crate::errln!(
            "wrote {}; run it with:\n  {}",
            out.display(),
            imported.command
        )?,
    }
    Ok(())
}
