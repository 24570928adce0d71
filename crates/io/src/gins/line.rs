//! The line layer shared by the readers: one reused buffer, comments and
//! blank lines skipped, fields parsed in place.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use crate::InputError;

/// The most columns any format has (GNSS with velocity).
pub(crate) const MAX_FIELDS: usize = 13;

/// The longest line read, in bytes (data lines are under 300): a longer one
/// is an error, so a binary or runaway file never fills memory.
pub const MAX_LINE_BYTES: usize = 4096;

/// The numbers of one data line.
///
/// ```
/// let f = kestrel_io::gins::Fields { line: 3, count: 2, values: [1.0; 13] };
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

/// What separates the columns of a line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Delimiter {
    /// Any run of spaces and tabs (the GINS formats).
    #[default]
    Whitespace,
    /// One character (`,`, `;`, a tab); spaces around a field are ignored.
    Char(char),
}

/// How a configured file is laid out: what separates columns, how many
/// header lines to skip, and which columns (0-based) to read, with their
/// names for errors; other columns may hold anything.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Selection {
    pub delimiter: Delimiter,
    pub header_lines: usize,
    pub columns: Vec<(usize, String)>,
}

/// Data lines of a text file, parsed one at a time.
#[derive(Debug)]
pub(crate) struct Lines<R> {
    selection: Option<Selection>,
    /// The comment character (`#`; `%` for RTKLIB's header lines, which
    /// the RTKLIB reader reads itself).
    comment: Option<u8>,
    reader: R,
    path: PathBuf,
    bytes: Vec<u8>,
    /// The data part of the current line (before any `#`).
    buf: String,
    line: usize,
    failed: bool,
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
            selection: None,
            comment: Some(b'#'),
            reader,
            path: path.to_path_buf(),
            bytes: Vec::with_capacity(256),
            buf: String::with_capacity(256),
            line: 0,
            failed: false,
            names,
            counts,
            layout,
        }
    }

    /// Lines of `reader` read by `selection`: only its columns are parsed
    /// (as numbers, in the selection's order), after its header lines.
    pub(crate) fn selected(reader: R, path: &Path, selection: Selection) -> Self {
        let mut lines = Self::new(reader, path, &[], &[], "");
        lines.selection = Some(selection);
        lines
    }

    /// Lines of `reader` returned whole by [`next_text`](Self::next_text)
    /// (no comment character): for formats with their own header syntax.
    pub(crate) fn raw(reader: R, path: &Path) -> Self {
        let mut lines = Self::new(reader, path, &[], &[], "");
        lines.comment = None;
        lines
    }

    /// The next non-blank line's number and text (line end removed), `None`
    /// at the end of the file.
    pub(crate) fn next_text(&mut self) -> Option<Result<(usize, &str), InputError>> {
        match self.advance()? {
            Ok(()) => Some(Ok((self.line, self.buf.trim_end()))),
            Err(e) => Some(Err(e)),
        }
    }

    /// Reads up to the next non-blank line after the header lines; `None`
    /// at the end of the file and after an error of the line layer.
    fn advance(&mut self) -> Option<Result<(), InputError>> {
        if self.failed {
            return None;
        }
        loop {
            match self.read_line() {
                Ok(false) => return None,
                Ok(true) => {}
                Err(e) => {
                    self.failed = true;
                    return Some(Err(e));
                }
            }
            let header = self.selection.as_ref().map_or(0, |s| s.header_lines);
            if self.line > header && !self.buf.bytes().all(|b| b.is_ascii_whitespace()) {
                return Some(Ok(()));
            }
        }
    }

    /// The file's name for errors.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// The next data line, `None` at the end of the file (and after an
    /// error of the line layer).
    pub(crate) fn next_fields(&mut self) -> Option<Result<Fields, InputError>> {
        if let Err(e) = self.advance()? {
            return Some(Err(e));
        }
        if let Some(s) = &self.selection {
            return Some(self.parse_selected(s, self.line));
        }
        Some(self.parse(self.line))
    }

    /// Reads the next line into `buf` (its data part: a UTF-8 byte-order
    /// mark at the start of the file, a comment after `#` and the line end
    /// removed; a comment may hold any bytes). `false` at the end.
    fn read_line(&mut self) -> Result<bool, InputError> {
        self.bytes.clear();
        self.buf.clear();
        self.line += 1;
        let limit = MAX_LINE_BYTES as u64 + 1;
        let n = (&mut self.reader)
            .take(limit)
            .read_until(b'\n', &mut self.bytes)
            .map_err(|e| {
                InputError::line(&self.path, self.line, format!("cannot read the line: {e}"))
            })?;
        if n == 0 {
            return Ok(false);
        }
        if self.bytes.len() > MAX_LINE_BYTES {
            let hint = if self.bytes.contains(&b'\r') {
                "; the lines seem to end in CR only (classic Mac): convert them to LF or CR LF"
            } else {
                " (is this a text file in the expected format?)"
            };
            return Err(InputError::line(
                &self.path,
                self.line,
                format!("line longer than {MAX_LINE_BYTES} bytes{hint}"),
            ));
        }
        let mut data = &self.bytes[..];
        if self.line == 1 {
            data = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
        }
        if let Some(i) = self.comment.and_then(|c| data.iter().position(|&b| b == c)) {
            data = &data[..i];
        }
        match std::str::from_utf8(data) {
            Ok(text) => self.buf.push_str(text),
            Err(e) => {
                // The column of the field holding the byte.
                let before = &data[..e.valid_up_to()];
                let tokens =
                    std::str::from_utf8(before).map_or(0, |t| t.split_ascii_whitespace().count());
                // Inside the last token seen, or the start of the next one.
                let inside = before.last().is_some_and(|b| !b.is_ascii_whitespace());
                let column = if inside { tokens } else { tokens + 1 };
                return Err(InputError::at(
                    &self.path,
                    self.line,
                    column,
                    format!(
                        "byte 0x{:02X} at byte {} of the line is not UTF-8 text (only comments \
                         after `#` may hold other bytes)",
                        data[e.valid_up_to()],
                        e.valid_up_to() + 1
                    ),
                ));
            }
        }
        Ok(true)
    }

    /// The selected columns of the current line.
    fn parse_selected(&self, s: &Selection, line: usize) -> Result<Fields, InputError> {
        let text = self.buf.trim_end_matches(['\r', '\n']);
        let mut tokens: Vec<&str> = match s.delimiter {
            Delimiter::Whitespace => text.split_ascii_whitespace().collect(),
            Delimiter::Char(c) => text.split(c).map(str::trim).collect(),
        };
        if s.delimiter != Delimiter::Whitespace && tokens.last() == Some(&"") {
            tokens.pop();
        }
        let mut values = [0.0; MAX_FIELDS];
        for (k, (column, name)) in s.columns.iter().enumerate() {
            let Some(token) = tokens.get(*column) else {
                return Err(InputError::at(
                    &self.path,
                    line,
                    tokens.len() + 1,
                    format!(
                        "expected at least {} columns ({name} is column {}), found {}",
                        column + 1,
                        column + 1,
                        tokens.len()
                    ),
                ));
            };
            values[k] = match token.parse::<f64>() {
                Ok(v) if v.is_finite() => v,
                Ok(_) => {
                    return Err(InputError::at(
                        &self.path,
                        line,
                        column + 1,
                        format!("expected a finite number ({name}), found `{token}`"),
                    ))
                }
                Err(_) => {
                    return Err(InputError::at(
                        &self.path,
                        line,
                        column + 1,
                        format!("expected a number ({name}), found `{token}`"),
                    ))
                }
            };
        }
        Ok(Fields {
            line,
            count: s.columns.len(),
            values,
        })
    }

    fn parse(&self, line: usize) -> Result<Fields, InputError> {
        let text = &self.buf[..];
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
