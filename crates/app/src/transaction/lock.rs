//! The output folder's lock: `.kestrel.lock`, exclusively locked by the run
//! writing into the folder, holding its process id and command so a second
//! run can say who has it.

use std::fs::{self, File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

use super::identity::Input;
use crate::Error;

/// The lock file's name in an output folder.
pub(super) const LOCK: &str = ".kestrel.lock";

/// A held lock (released when dropped or by [`release`](Self::release)).
#[derive(Debug)]
pub(super) struct FolderLock {
    file: Option<File>,
    path: PathBuf,
}

impl FolderLock {
    /// Locks the folder `dir` (named `out` by the caller) for `command`.
    pub(super) fn acquire(
        out: &Path,
        dir: &Path,
        command: &[String],
        inputs: &[Input],
    ) -> Result<Self, Error> {
        let path = dir.join(LOCK);
        if let Some(input) = inputs.iter().find(|i| i.is(&path)) {
            return Err(Error::Failed(format!(
                "{} is kestrel's lock file for the folder and the {} input {}: move the input",
                out.join(LOCK).display(),
                input.flag,
                input.path.display()
            )));
        }
        // Never through a link: the name is reserved, a link there goes.
        if fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
            fs::remove_file(&path).map_err(|e| Error::io(&out.join(LOCK), e))?;
        }
        // The holder removes the file when it is done, so a lock taken on
        // a file that was removed meanwhile is no lock: take it again.
        let mut tries = 0;
        let mut file = loop {
            let file = open_lock_file(&path).map_err(|e| Error::io(&out.join(LOCK), e))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(fs::TryLockError::WouldBlock) => return Err(busy(out, file)),
                Err(fs::TryLockError::Error(e)) => return Err(Error::io(&out.join(LOCK), e)),
            }
            let held = file.metadata().ok().map(|m| (m.dev(), m.ino()));
            let named = fs::symlink_metadata(&path).ok().map(|m| (m.dev(), m.ino()));
            if held.is_some() && held == named {
                break file;
            }
            tries += 1;
            if tries == 100 {
                return Err(Error::Failed(format!(
                    "{}: the lock file keeps being replaced; is another program writing there?",
                    out.join(LOCK).display()
                )));
            }
        };
        let record = format!("{}\n{}\n", std::process::id(), command.join(" "));
        let _ = file.set_len(0);
        let _ = file.rewind();
        let _ = file.write_all(record.as_bytes());
        Ok(Self {
            file: Some(file),
            path,
        })
    }

    /// Releases the lock (idempotent), removing the lock file while it is
    /// still held: a run waiting on it sees the file gone and takes a new
    /// one.
    pub(super) fn release(&mut self) {
        if let Some(f) = self.file.take() {
            let _ = fs::remove_file(&self.path);
            let _ = f.unlock();
        }
    }
}

/// Opens (or creates) the lock file, never through a symbolic link.
fn open_lock_file(path: &Path) -> std::io::Result<File> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .custom_flags(libc::O_NOFOLLOW)
        .open(path)
}

/// The error of a folder another run holds, naming the folder and, from
/// the lock file, the process and its command.
fn busy(out: &Path, mut file: File) -> Error {
    let mut holder = String::new();
    let _ = file.read_to_string(&mut holder);
    let mut lines = holder.lines();
    let pid = lines.next().unwrap_or("?");
    let cmd = lines.next().unwrap_or("");
    Error::Failed(format!(
        "another kestrel run is writing into {} (process {pid}: `{cmd}`); wait for it to \
         finish or choose another output folder",
        out.display()
    ))
}
