//! Writing to standard output and standard error: every write is checked,
//! so a full device or a closed pipe ends the command with an error (a
//! closed pipe quietly: `kestrel … | head`), never a panic.

use std::io::Write;
use std::path::Path;

use crate::CliError;

/// Writes `text` to standard output.
///
/// # Errors
/// [`CliError::Io`] on "standard output" when the write fails.
pub fn print(text: &str) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| CliError::io(Path::new("standard output"), e))
}

/// Writes `text` and a line end to standard error.
///
/// # Errors
/// [`CliError::Io`] on "standard error" when the write fails.
pub fn warn(text: &str) -> Result<(), CliError> {
    let mut err = std::io::stderr().lock();
    writeln!(err, "{text}").map_err(|e| CliError::io(Path::new("standard error"), e))
}

/// Whether `e` is a write to a closed pipe (the reader went away: a quiet
/// end, not an error to report).
pub fn is_closed_pipe(e: &CliError) -> bool {
    matches!(e, CliError::Io { source, .. } if source.kind() == std::io::ErrorKind::BrokenPipe)
}

/// `println!` through [`print`]: `outln!("{x}")?`.
#[macro_export]
macro_rules! outln {
    ($($t:tt)*) => {
        $crate::out::print(&format!("{}\n", format_args!($($t)*)))
    };
}

/// `eprintln!` through [`warn`]: `errln!("{x}")?`.
#[macro_export]
macro_rules! errln {
    ($($t:tt)*) => {
        $crate::out::warn(&format!($($t)*))
    };
}
