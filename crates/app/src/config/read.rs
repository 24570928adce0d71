//! Reading a TOML configuration with serde, and reporting any problem at
//! its place: the file, the line and column, the key path and what was
//! expected. Both the `process` configuration and the scenario file read
//! through this.

use std::path::Path;

use serde::de::DeserializeOwned;

use crate::config::check::Bad;
use crate::config::locate::{line_column, Places};
use crate::InputError;

/// The most bytes a configuration or scenario file may hold: a file
/// beyond it is refused before it is parsed.
pub const MAX_CONFIG_BYTES: u64 = 1 << 20;

/// The text of the configuration file `path`, read once through the input
/// layer (its tally, for the manifest) and at most [`MAX_CONFIG_BYTES`]
/// long.
///
/// # Errors
/// An [`InputError`] naming the file: it cannot be read, it is longer than
/// the limit (saying so), or it is not UTF-8 text.
pub fn read_config(path: &Path) -> Result<(String, kestrel_io::input::Tally), InputError> {
    use std::io::Read;
    let (reader, tally) = kestrel_io::input::open(path)?;
    let mut bytes = Vec::new();
    reader
        .take(MAX_CONFIG_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| InputError::file(path, format!("cannot read the file: {e}")))?;
    if bytes.len() as u64 > MAX_CONFIG_BYTES {
        return Err(InputError::file(
            path,
            format!(
                "larger than {} KiB, the limit of a configuration file (is this the right file?)",
                MAX_CONFIG_BYTES >> 10
            ),
        ));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        InputError::file(
            path,
            format!(
                "byte {} is not UTF-8 text",
                e.utf8_error().valid_up_to() + 1
            ),
        )
    })?;
    Ok((text, tally))
}

/// A configuration's text, its file name and where each key is in it.
pub(crate) struct Source<'a> {
    file: &'a Path,
    text: &'a str,
    places: Places,
}

impl<'a> Source<'a> {
    /// The text of the file `file`.
    pub(crate) fn new(text: &'a str, file: &'a Path) -> Self {
        Self {
            file,
            text,
            places: Places::new(text),
        }
    }

    /// The file's tables as `T`.
    ///
    /// # Errors
    /// An [`InputError`] at the line and column of the problem (syntax, an
    /// unknown or missing key, a wrong type), naming the key.
    pub(crate) fn parse<T: DeserializeOwned>(&self) -> Result<T, InputError> {
        toml::from_str(self.text).map_err(|e| {
            let message = rephrase(e.message());
            match e.span() {
                Some(span) => {
                    let (line, column) = line_column(self.text, span.start);
                    let err = InputError::at(self.file, line, column, message);
                    match self.places.path_at(span.start) {
                        Some(key) => err.with_key(key),
                        None => err,
                    }
                }
                None => InputError::file(self.file, message),
            }
        })
    }

    /// The error `message` about `key`, at the key's line and column (at
    /// its nearest enclosing table's when the key is absent).
    pub(crate) fn error(&self, key: &str, message: impl Into<String>) -> InputError {
        let err = match self.places.span_of(key) {
            Some(span) => {
                let (line, column) = line_column(self.text, span.start);
                InputError::at(self.file, line, column, message)
            }
            None => InputError::file(self.file, message),
        };
        err.with_key(key)
    }

    /// [`error`](Self::error) for a [`Bad`] value.
    pub(crate) fn bad(&self, b: Bad) -> InputError {
        self.error(&b.key, b.message)
    }
}

/// The TOML reader's message in the files' vocabulary, on one line.
fn rephrase(message: &str) -> String {
    let one_line = message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    one_line
        .replace("unknown field", "unknown key")
        .replace("missing field", "missing key")
        .replace("unknown variant", "unknown value")
        .replace("there are no fields", "this table takes no keys")
        .replace("expected f64", "expected a number")
        .replace("expected u64", "expected a non-negative integer")
        .replace("expected i64", "expected an integer")
        .replace("expected a string", "expected a quoted string")
}
