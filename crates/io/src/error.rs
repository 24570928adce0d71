//! The errors of reading and processing recorded data: one line each,
//! naming the file and the place in it when the cause is the input.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in an input file something went wrong.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Location {
    /// 1-based line number, if known.
    pub line: Option<usize>,
    /// 1-based column (field number for whitespace-separated text files,
    /// character column for TOML), if known.
    pub column: Option<usize>,
    /// The configuration key (dotted path, e.g. `filters[1].gamma`), if the
    /// cause is a key.
    pub key: Option<String>,
}

/// A problem with an input file: what is wrong, where, and what was expected.
///
/// Displayed as `file:line:column: message` (parts that are unknown are left
/// out), with `key `…`: ` before the message when a key is known.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InputError {
    /// The file.
    pub file: PathBuf,
    /// The place in it.
    pub at: Location,
    /// What is wrong and what was expected.
    pub message: String,
}

impl InputError {
    /// An error about the whole `file`.
    pub fn file(file: &Path, message: impl Into<String>) -> Self {
        Self {
            file: file.to_path_buf(),
            at: Location::default(),
            message: message.into(),
        }
    }

    /// An error at `line` (1-based) of `file`.
    pub fn line(file: &Path, line: usize, message: impl Into<String>) -> Self {
        Self {
            at: Location {
                line: Some(line),
                ..Location::default()
            },
            ..Self::file(file, message)
        }
    }

    /// An error at `line` and `column` (both 1-based) of `file`.
    pub fn at(file: &Path, line: usize, column: usize, message: impl Into<String>) -> Self {
        Self {
            at: Location {
                line: Some(line),
                column: Some(column),
                key: None,
            },
            ..Self::file(file, message)
        }
    }

    /// The same error, also naming the configuration `key`.
    pub fn with_key(mut self, key: impl Into<String>) -> Self {
        self.at.key = Some(key.into());
        self
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.at.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.at.column {
                write!(f, ":{column}")?;
            }
        }
        write!(f, ": ")?;
        if let Some(key) = &self.at.key {
            write!(f, "key `{key}`: ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for InputError {}

/// Everything reading or processing can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input data or configuration.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Any other failure, as one line.
    #[error("{0}")]
    Failed(String),
    /// The run was stopped before it finished (a signal, or a caller's
    /// cancellation); nothing it would have written was published.
    #[error("stopped before the end: nothing was written")]
    Cancelled,
    /// A device ran out of space writing `path`.
    #[error("{}: no space left on the device ({free} bytes free); nothing was written", path.display())]
    DiskFull {
        /// The file being written.
        path: PathBuf,
        /// Bytes free on its device when the write failed.
        free: u64,
    },
}

impl Error {
    /// An I/O error on `path`; a full device becomes [`Error::DiskFull`]
    /// with the free space.
    ///
    /// ```
    /// use kestrel_io::Error;
    /// let e = Error::io("x.txt".as_ref(), std::io::Error::from_raw_os_error(28));
    /// assert!(matches!(e, Error::DiskFull { .. }));
    /// assert!(e.to_string().starts_with("x.txt: no space left on the device ("));
    /// ```
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        // ENOSPC (Linux, macOS: 28); EDQUOT (Linux: 122), a quota full.
        if matches!(source.raw_os_error(), Some(28 | 122)) {
            let dir = path
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            return Self::DiskFull {
                path: path.to_path_buf(),
                free: fs4::available_space(dir).unwrap_or(0),
            };
        }
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_line_column_and_key() {
        let p = Path::new("imu.txt");
        assert_eq!(
            InputError::at(p, 12, 3, "expected a number, found `x`").to_string(),
            "imu.txt:12:3: expected a number, found `x`"
        );
        assert_eq!(
            InputError::line(p, 4, "time goes backwards").to_string(),
            "imu.txt:4: time goes backwards"
        );
        assert_eq!(
            InputError::file(Path::new("a.toml"), "must be ≥ 1")
                .with_key("filters[1].gamma")
                .to_string(),
            "a.toml: key `filters[1].gamma`: must be ≥ 1"
        );
    }
}
