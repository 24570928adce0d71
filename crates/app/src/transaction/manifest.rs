//! The manifest: the commit record of a run's output folder
//! (`kestrel-manifest.json`), written last. It lists the run's files, each
//! with its format and that format's schema version, and the run's
//! provenance: kestrel's version, the command line, the resolved
//! configuration, the seeds, the inputs' sizes and SHA-256 hashes, and any
//! limit the run hit. The next run into the folder replaces exactly the
//! files it lists. The formats' versions and their changes are in the
//! repository's `CHANGELOG.md`.

use std::fs;
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::Error;

/// The manifest's file name.
pub const MANIFEST: &str = "kestrel-manifest.json";

/// The version of the manifest's own layout.
pub const MANIFEST_SCHEMA: u32 = 1;

/// One input as read: its flag, path, size and hash.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputRecord {
    /// The flag or key that named it (`--imu`, `--config`, `scenario`).
    pub flag: String,
    /// The path as given.
    pub path: String,
    /// Bytes read.
    pub bytes: u64,
    /// SHA-256 of the bytes read, hexadecimal.
    pub sha256: String,
}

/// What a run records about how its files came to be.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// The inputs as read.
    pub inputs: Vec<InputRecord>,
    /// The configuration as resolved (defaults filled in), if the command
    /// has one.
    pub configuration: Option<serde_json::Value>,
    /// The random seeds the run used.
    pub seeds: Vec<u64>,
    /// The limits the run hit (a thinned trace, a capped count), one line
    /// each.
    pub limits: Vec<String>,
}

/// One file of the run.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileRecord {
    /// Its name in the folder.
    pub name: String,
    /// Its format (`gins-nav`, `kestrel-csv`, `png`, …).
    pub format: String,
    /// The format's schema version.
    pub schema: u32,
    /// Its size.
    pub bytes: u64,
}

/// A run's manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// [`MANIFEST_SCHEMA`].
    pub manifest: u32,
    /// kestrel's version.
    pub kestrel: String,
    /// The command line.
    pub command: Vec<String>,
    /// When the run published, seconds since the Unix epoch.
    pub finished_unix_s: u64,
    /// The run's files.
    pub files: Vec<FileRecord>,
    /// How they came to be.
    pub provenance: Provenance,
}

impl Manifest {
    /// A manifest for `command` with no files yet.
    pub fn new(command: &[String], provenance: Provenance) -> Self {
        Self {
            manifest: MANIFEST_SCHEMA,
            kestrel: env!("CARGO_PKG_VERSION").to_owned(),
            command: command.to_vec(),
            finished_unix_s: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            files: Vec::new(),
            provenance,
        }
    }

    /// Adds the file `name` of `bytes` bytes, with its format.
    pub fn add_file(&mut self, name: &str, bytes: u64) {
        let (format, schema) = format_of(name);
        self.files.push(FileRecord {
            name: name.to_owned(),
            format: format.to_owned(),
            schema,
            bytes,
        });
    }

    /// The manifest in `dir`, if there is a readable one (a link there is
    /// not followed).
    pub fn read(dir: &Path) -> Option<Self> {
        let path = dir.join(MANIFEST);
        let meta = fs::symlink_metadata(&path).ok()?;
        if !meta.is_file() || meta.len() > 16 << 20 {
            return None;
        }
        serde_json::from_slice(&fs::read(&path).ok()?).ok()
    }

    /// The names of its files.
    pub fn file_names(&self) -> Vec<String> {
        self.files.iter().map(|f| f.name.clone()).collect()
    }

    /// Writes the manifest into `scratch`, then renames it into `dir`.
    pub(super) fn publish(&self, scratch: &Path, dir: &Path) -> Result<(), Error> {
        let text = serde_json::to_vec_pretty(self)
            .map_err(|e| Error::Failed(format!("cannot write the manifest: {e}")))?;
        let tmp = scratch.join(MANIFEST);
        let mut f = fs::File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
        f.write_all(&text)
            .and_then(|()| f.write_all(b"\n"))
            .and_then(|()| f.sync_all())
            .map_err(|e| Error::io(&tmp, e))?;
        let target = dir.join(MANIFEST);
        fs::rename(&tmp, &target).map_err(|e| Error::io(&target, e))?;
        // The renames reach the disk in order with the folder's entry.
        if let Ok(d) = fs::File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

/// The format of an output file from its name, and that format's schema
/// version (see `CHANGELOG.md`).
///
/// ```
/// use kestrel_app::transaction::format_of;
/// assert_eq!(format_of("result.nav"), ("gins-nav", 1));
/// assert_eq!(format_of("position.svg"), ("svg", 1));
/// ```
pub fn format_of(name: &str) -> (&'static str, u32) {
    let ext = Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("");
    match (name, ext) {
        (_, "nav") => ("gins-nav", 1),
        ("imu.txt", _) => ("gins-imu", 1),
        ("gnss.txt", _) => ("gins-gnss", 1),
        (n, "txt") if n.ends_with("_imu_errors.txt") || n.ends_with("_std.txt") => {
            ("kestrel-state-text", 1)
        }
        ("report.txt", _) => ("kestrel-report", 1),
        (_, "toml") => ("kestrel-process-config", 1),
        (_, "csv") => ("kestrel-csv", 2),
        (_, "png") => ("png", 1),
        (_, "svg") => ("svg", 1),
        _ => ("other", 1),
    }
}
