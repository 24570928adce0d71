//! The line layer shared by the readers: one reused buffer, comments and
//! blank lines skipped, fields parsed in place.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use crate::InputError;

/// The most columns any format has (GNSS with velocity).
pub(crate) const MAX_FIELDS: usize = 13;

/// The numbers of one data line.
///
/// ```
/// let f = kestrel_cli::gins::Fields { line: 3, count: 2, values: [1.0; 13] };
/// assert_eq!(f.get(1), 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fields {
    /// 1-based line number in the file.
    pub line: usize,
    /// How many columns the line has.
    pub count: usize,
    /// The first `count` (at most 13) values.
    pub values: [f64; MAX_FIELDS],
}

impl Fields {
    /// The value of column `i` (0-based).
    pub fn get(&self, i: usize) -> f64 {
        self.values[i]
    }
}

/// Data lines of a text file, parsed one at a time.
#[derive(Debug)]
pub(crate) struct Lines<R> {
    reader: R,
    path: PathBuf,
    buf: String,
    line: usize,
    names: &'static [&'static str],
    counts: &'static [usize],
    layout: &'static str,
}

/// Opens `path` for reading, an [`InputError`] naming it if it cannot be.
pub(crate) fn open(path: &Path) -> Result<BufReader<File>, InputError> {
    File::open(path)
        .map(|f| BufReader::with_capacity(1 << 16, f))
        .map_err(|e| InputError::file(path, format!("cannot open the file: {e}")))
}

impl<R: BufRead> Lines<R> {
    /// Lines of `reader` (named `path` in errors) whose columns are called
    /// `names` and which may have any of `counts` columns (`layout`
    /// describes them in errors).
    pub(crate) fn new(
        reader: R,
        path: &Path,
        names: &'static [&'static str],
        counts: &'static [usize],
        layout: &'static str,
    ) -> Self {
        Self {
            reader,
            path: path.to_path_buf(),
            buf: String::with_capacity(256),
            line: 0,
            names,
            counts,
            layout,
        }
    }

    /// The file's name for errors.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// The next data line, `None` at the end of the file.
    pub(crate) fn next_fields(&mut self) -> Option<Result<Fields, InputError>> {
        loop {
            self.buf.clear();
            self.line += 1;
            match self.reader.read_line(&mut self.buf) {
                Ok(0) => return None,
                Ok(_) => {}
                Err(e) => {
                    return Some(Err(InputError::line(
                        &self.path,
                        self.line,
                        format!("cannot read the line: {e}"),
                    )))
                }
            }
            let text = match self.buf.find('#') {
                Some(i) => &self.buf[..i],
                None => &self.buf[..],
            };
            if text.bytes().all(|b| b.is_ascii_whitespace()) {
                continue;
            }
            return Some(self.parse(self.line));
        }
    }

    fn parse(&self, line: usize) -> Result<Fields, InputError> {
        let text = match self.buf.find('#') {
            Some(i) => &self.buf[..i],
            None => &self.buf[..],
        };
        let mut values = [0.0; MAX_FIELDS];
        let mut count = 0;
        let mut bad: Option<InputError> = None;
        for token in text.split_ascii_whitespace() {
            if count < MAX_FIELDS && bad.is_none() {
                let name = self.names.get(count).copied().unwrap_or("value");
                match token.parse::<f64>() {
                    Ok(v) if v.is_finite() => values[count] = v,
                    Ok(_) => {
                        bad = Some(InputError::at(
                            &self.path,
                            line,
                            count + 1,
                            format!("expected a finite number ({name}), found `{token}`"),
                        ))
                    }
                    Err(_) => {
                        bad = Some(InputError::at(
                            &self.path,
                            line,
                            count + 1,
                            format!("expected a number ({name}), found `{token}`"),
                        ))
                    }
                }
            }
            count += 1;
        }
        if !self.counts.contains(&count) {
            let expected = self
                .counts
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(" or ");
            // The column is the first one missing or the first extra one.
            let column = if count < self.counts[0] {
                count + 1
            } else {
                self.counts
                    .iter()
                    .copied()
                    .filter(|&c| c < count)
                    .max()
                    .unwrap_or(0)
                    + 1
            };
            return Err(InputError::at(
                &self.path,
                line,
                column,
                format!(
                    "expected {expected} columns ({}), found {count}",
                    self.layout
                ),
            ));
        }
        match bad {
            Some(e) => Err(e),
            None => Ok(Fields {
                line,
                count,
                values,
            }),
        }
    }
}
