//! The output transaction: how every command that writes (`process`,
//! `simulate`, `reproduce`, `run`, `import --out`) and every library call
//! that writes puts its files in place.
//!
//! A run writes into a scratch folder of its own inside its output folder
//! (`.kestrel-scratch-<pid>-<nanos>`), holds an exclusive lock on the output
//! folder for the whole run (a second run into it is refused at once,
//! naming the folder and the running process), and publishes at the end:
//! its files renamed into place, then the manifest
//! (`kestrel-manifest.json`) renamed last as the commit record. Until then
//! nothing under a final name has changed; on any error, on cancellation
//! and when the transaction is dropped, the scratch folder is removed. A
//! killed run's scratch (SIGKILL, power loss) is recognised and removed by
//! the next run into the folder.
//!
//! A new run replaces exactly the files the previous manifest lists (the
//! earlier run's set, including files this run does not write); a file
//! under one of the run's names that no manifest lists is the user's and is
//! refused unless the caller forces it. No input of the run is ever
//! created, renamed onto, deleted or written through, whatever its
//! spelling: inputs are compared by file identity (device and inode) and
//! by canonical path, and symbolic links under output names are replaced,
//! never followed.
//!
//! ```
//! use kestrel_app::transaction::{Begin, Transaction};
//! let out = std::env::temp_dir().join(format!("kestrel-doc-tx-{}", std::process::id()));
//! let mut tx = Transaction::begin(&out, Begin::command(["example"]))?;
//! std::fs::write(tx.path("hello.txt")?, "hello\n").map_err(|e| kestrel_app::Error::io(&out, e))?;
//! assert!(!out.join("hello.txt").exists()); // not yet published
//! let files = tx.commit(Default::default())?;
//! assert_eq!(std::fs::read_to_string(&files[0]).unwrap(), "hello\n");
//! assert!(out.join("kestrel-manifest.json").exists());
//! # std::fs::remove_dir_all(&out).unwrap();
//! # Ok::<(), kestrel_app::Error>(())
//! ```

mod cancel;
mod identity;
mod lock;
mod manifest;
mod single_file;

use std::fs;
use std::path::{Path, PathBuf};

pub use cancel::Cancel;
pub use identity::FileId;
pub use manifest::{
    format_of, FileRecord, InputRecord, Manifest, Provenance, MANIFEST, MANIFEST_SCHEMA,
};
pub use single_file::publish_file;

use crate::Error;
use identity::Input;
use lock::FolderLock;

/// The prefix of scratch folders (a reserved name in an output folder).
pub const SCRATCH_PREFIX: &str = ".kestrel-scratch-";

/// How a transaction begins: the command it records and the inputs it
/// must never touch.
#[derive(Clone, Debug, Default)]
pub struct Begin {
    /// The command line (recorded in the manifest and the lock file).
    pub command: Vec<String>,
    /// The run's inputs, by the flag that names them (`--imu`, `--config`,
    /// …) and their path.
    pub inputs: Vec<(String, PathBuf)>,
    /// Replace files under the run's names that no earlier manifest lists
    /// (the user's own); without it such a file is refused.
    pub force: bool,
}

impl Begin {
    /// A transaction recording `command`, with no inputs.
    pub fn command<S: Into<String>>(command: impl IntoIterator<Item = S>) -> Self {
        Self {
            command: command.into_iter().map(Into::into).collect(),
            ..Self::default()
        }
    }

    /// The same with the input `path` given by `flag`.
    pub fn input(mut self, flag: &str, path: impl Into<PathBuf>) -> Self {
        self.inputs.push((flag.to_owned(), path.into()));
        self
    }
}

/// A run's output in progress: see the [module documentation](self).
#[derive(Debug)]
pub struct Transaction {
    /// The output folder as the caller named it (for messages).
    out: PathBuf,
    /// The output folder, canonical.
    dir: PathBuf,
    scratch: PathBuf,
    lock: FolderLock,
    inputs: Vec<Input>,
    files: Vec<String>,
    force: bool,
    command: Vec<String>,
    committed: bool,
    /// Whether this run made the output folder (removed again, if still
    /// empty, when the run does not commit).
    created: bool,
}

impl Transaction {
    /// Creates `out` if missing, locks it, removes a killed run's scratch
    /// and makes this run's own scratch folder.
    ///
    /// # Errors
    /// [`Error::Failed`] when another run holds the folder (naming it and
    /// the process), when `out` is not a folder, or when a reserved name in
    /// it is one of the inputs; [`Error::Io`] when the folder cannot be
    /// made or locked.
    pub fn begin(out: &Path, begin: Begin) -> Result<Self, Error> {
        if fs::symlink_metadata(out).is_ok_and(|m| !m.is_dir() && !m.file_type().is_symlink()) {
            return Err(Error::Failed(format!(
                "{}: the output folder is a file; choose a folder",
                out.display()
            )));
        }
        let created = fs::symlink_metadata(out).is_err();
        fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
        let dir = fs::canonicalize(out).map_err(|e| Error::io(out, e))?;
        if !dir.is_dir() {
            return Err(Error::Failed(format!(
                "{}: the output folder is not a folder",
                out.display()
            )));
        }
        let inputs: Vec<Input> = begin
            .inputs
            .iter()
            .map(|(flag, path)| Input::new(flag, path))
            .collect();
        let lock = FolderLock::acquire(out, &dir, &begin.command, &inputs)?;
        remove_stale_scratch(out, &dir, &inputs)?;
        let scratch = dir.join(format!(
            "{SCRATCH_PREFIX}{}-{}",
            std::process::id(),
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_nanos())
        ));
        fs::create_dir(&scratch).map_err(|e| Error::io(&scratch, e))?;
        Ok(Self {
            out: out.to_path_buf(),
            dir,
            scratch,
            lock,
            inputs,
            files: Vec::new(),
            force: begin.force,
            command: begin.command,
            committed: false,
            created,
        })
    }

    /// The output folder as the caller named it.
    pub fn out(&self) -> &Path {
        &self.out
    }

    /// Where to write the output file `name` (a plain file name) until the
    /// run commits; the file is published under `name` by
    /// [`commit`](Self::commit).
    ///
    /// # Errors
    /// [`Error::Failed`] for a name with a folder, `.`, `..`, a reserved
    /// name, or a name given twice.
    pub fn path(&mut self, name: &str) -> Result<PathBuf, Error> {
        if !is_plain_name(name) || name == MANIFEST || name.starts_with(".kestrel") {
            return Err(Error::Failed(format!(
                "`{name}` cannot be an output file's name (a plain name, not reserved)"
            )));
        }
        if self.files.iter().any(|f| f == name) {
            return Err(Error::Failed(format!(
                "`{name}` is written twice by one run"
            )));
        }
        self.files.push(name.to_owned());
        Ok(self.scratch.join(name))
    }

    /// Records the file `name` already written into the scratch folder (see
    /// [`scratch_dir`](Self::scratch_dir)) so it is published in this order;
    /// returns its final path.
    ///
    /// # Errors
    /// As [`path`](Self::path), and [`Error::Failed`] if no such file was
    /// written.
    pub fn adopt(&mut self, name: &str) -> Result<PathBuf, Error> {
        let path = self.path(name)?;
        if !path.is_file() {
            self.files.pop();
            return Err(Error::Failed(format!(
                "internal error: `{name}` was not written before it was published"
            )));
        }
        Ok(self.out.join(name))
    }

    /// The scratch folder: a file written here under a plain name is
    /// published under that name by [`commit`](Self::commit); names
    /// starting with `.` are working files, never published.
    pub fn scratch_dir(&self) -> &Path {
        &self.scratch
    }

    /// A working file `name` inside the scratch folder: never published,
    /// removed with the scratch folder.
    pub fn scratch_file(&self, name: &str) -> PathBuf {
        self.scratch.join(format!(".work-{name}"))
    }

    /// Publishes the run's files: checks every final name (never an input;
    /// a file no earlier manifest lists only with `force`), removes the
    /// earlier run's files this run does not write, renames the files into
    /// place, then writes the manifest, last. Returns the published paths
    /// (as the caller named the folder), in the order they were asked for.
    ///
    /// # Errors
    /// [`Error::Failed`] naming a final name that is an input or the user's
    /// own file; [`Error::Io`] / [`Error::DiskFull`] for a write that fails.
    /// Nothing is published when the checks fail.
    pub fn commit(mut self, provenance: Provenance) -> Result<Vec<PathBuf>, Error> {
        self.adopt_the_rest()?;
        let previous = Manifest::read(&self.dir).map(|m| m.file_names());
        for name in &self.files {
            let target = self.dir.join(name);
            self.refuse_input(&target, name)?;
            let exists = fs::symlink_metadata(&target).is_ok();
            let ours = previous.as_ref().is_some_and(|p| p.contains(name));
            if exists && !ours && !self.force {
                return Err(Error::Failed(format!(
                    "refusing to replace {}: no earlier kestrel run into this folder wrote it \
                     (no manifest lists it); move it away or pass --force",
                    self.out.join(name).display()
                )));
            }
        }
        for name in &self.files {
            let path = self.scratch.join(name);
            if let Ok(f) = fs::File::open(&path) {
                f.sync_all().map_err(|e| Error::io(&path, e))?;
            }
        }
        let mut manifest = Manifest::new(&self.command, provenance);
        for name in &self.files {
            let bytes = fs::metadata(self.scratch.join(name)).map_or(0, |m| m.len());
            manifest.add_file(name, bytes);
        }
        // The earlier run's files this run does not write go first: a
        // folder never shows a mix of two runs' files under one manifest.
        for old in previous.iter().flatten() {
            if self.files.contains(old) || !is_plain_name(old) {
                continue;
            }
            let target = self.dir.join(old);
            if self.is_input(&target) {
                continue;
            }
            match fs::remove_file(&target) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(Error::io(&self.out.join(old), e)),
            }
        }
        let mut published = Vec::with_capacity(self.files.len());
        for name in &self.files {
            let target = self.dir.join(name);
            fs::rename(self.scratch.join(name), &target)
                .map_err(|e| Error::io(&self.out.join(name), e))?;
            published.push(self.out.join(name));
        }
        manifest.publish(&self.scratch, &self.dir)?;
        let _ = fs::remove_dir_all(&self.scratch);
        self.committed = true;
        Ok(published)
    }

    /// Every file written into the scratch folder and not yet recorded (a
    /// plain, visible name), in name order: nothing written is lost.
    fn adopt_the_rest(&mut self) -> Result<(), Error> {
        let entries = fs::read_dir(&self.scratch).map_err(|e| Error::io(&self.scratch, e))?;
        let mut rest: Vec<String> = entries
            .flatten()
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .filter_map(|e| e.file_name().into_string().ok())
            .filter(|n| !n.starts_with('.') && n != MANIFEST && !self.files.contains(n))
            .collect();
        rest.sort();
        self.files.extend(rest);
        Ok(())
    }

    /// Whether `path` is one of the inputs (by identity or canonical path).
    fn is_input(&self, path: &Path) -> bool {
        self.inputs.iter().any(|i| i.is(path))
    }

    /// Refuses `target` if it is an input.
    fn refuse_input(&self, target: &Path, name: &str) -> Result<(), Error> {
        match self.inputs.iter().find(|i| i.is(target)) {
            Some(input) => Err(Error::Failed(format!(
                "refusing to write {}: it is the {} input {}; choose another output folder",
                self.out.join(name).display(),
                input.flag,
                input.path.display()
            ))),
            None => Ok(()),
        }
    }
}

impl Drop for Transaction {
    /// An uncommitted run leaves nothing: its scratch folder goes, the
    /// lock is released, and a folder the run made is removed if empty.
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.scratch);
        }
        self.lock.release();
        if !self.committed && self.created {
            let _ = fs::remove_dir(&self.dir);
        }
    }
}

/// A plain file name: one normal component.
fn is_plain_name(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    matches!(
        (parts.next(), parts.next()),
        (Some(std::path::Component::Normal(_)), None)
    )
}

/// Removes the scratch folders a killed run left in `dir` (the lock is
/// held, so no running process owns one), unless an input lies inside.
fn remove_stale_scratch(out: &Path, dir: &Path, inputs: &[Input]) -> Result<(), Error> {
    let entries = fs::read_dir(dir).map_err(|e| Error::io(out, e))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        if !name.to_string_lossy().starts_with(SCRATCH_PREFIX) {
            continue;
        }
        let path = entry.path();
        if let Some(input) = inputs.iter().find(|i| i.is_inside(&path)) {
            return Err(Error::Failed(format!(
                "{} is a killed run's scratch folder and holds the {} input {}: move the input \
                 out of it first",
                out.join(&name).display(),
                input.flag,
                input.path.display()
            )));
        }
        let is_link = fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink());
        let removed = if is_link {
            fs::remove_file(&path)
        } else {
            fs::remove_dir_all(&path)
        };
        removed.map_err(|e| Error::io(&out.join(&name), e))?;
    }
    Ok(())
}
