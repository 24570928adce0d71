//! Which file a path names: device and inode, compared instead of the
//! path's text, so `dir/../dir/x`, a hard link and a symbolic link to an
//! input are all the input.

use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// A file's identity: its device and inode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FileId {
    /// The device.
    pub dev: u64,
    /// The inode.
    pub ino: u64,
}

impl FileId {
    /// The identity of the file `path` names (following links), if it
    /// exists.
    ///
    /// ```
    /// use kestrel_app::transaction::FileId;
    /// let here = FileId::of(".".as_ref()).unwrap();
    /// assert_eq!(FileId::of("./.".as_ref()), Some(here));
    /// assert_eq!(FileId::of("no/such/file".as_ref()), None);
    /// ```
    pub fn of(path: &Path) -> Option<Self> {
        std::fs::metadata(path).ok().map(|m| Self {
            dev: m.dev(),
            ino: m.ino(),
        })
    }
}

/// An input of a run: the flag that named it, its path, and what it is.
#[derive(Clone, Debug)]
pub(super) struct Input {
    pub flag: String,
    pub path: PathBuf,
    canonical: Option<PathBuf>,
    id: Option<FileId>,
}

impl Input {
    pub(super) fn new(flag: &str, path: &Path) -> Self {
        Self {
            flag: flag.to_owned(),
            path: path.to_path_buf(),
            canonical: std::fs::canonicalize(path).ok(),
            id: FileId::of(path),
        }
    }

    /// Whether `path` names this input: the same file (identity), or the
    /// same canonical path (a file that does not exist yet), or a link to
    /// it.
    pub(super) fn is(&self, path: &Path) -> bool {
        let same_file = self.id.is_some() && FileId::of(path) == self.id;
        let same_name =
            self.canonical.is_some() && std::fs::canonicalize(path).ok() == self.canonical;
        same_file || same_name
    }

    /// Whether this input lies inside the folder `dir`.
    pub(super) fn is_inside(&self, dir: &Path) -> bool {
        let Ok(dir) = std::fs::canonicalize(dir) else {
            return false;
        };
        self.canonical.as_ref().is_some_and(|c| c.starts_with(&dir))
    }
}
