//! The time of a file's last data line, read from its end.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// The first column of the last data line of the text file at `path`
/// (blank lines and `#` comments skipped), read from at most its last
/// 64 KiB; `None` if there is none, it is not a number, or `path` is not a
/// regular file (a pipe or a device). Used for the total of a progress bar
/// without reading the file: a bounded look at a regular file's end, not a
/// second pass over the input.
///
/// ```
/// let p = std::env::temp_dir().join(format!("kestrel-tail-doc-{}.txt", std::process::id()));
/// std::fs::write(&p, "1 0\n2.5 0\n\n# end\n").unwrap();
/// assert_eq!(kestrel_io::gins::last_time(&p), Some(2.5));
/// std::fs::remove_file(&p).unwrap();
/// ```
pub fn last_time(path: &Path) -> Option<f64> {
    let mut f = File::open(path).ok()?;
    // A pipe, a FIFO or a device has no end to read back from (and
    // `/dev/zero` no end at all): unknown.
    if !f.metadata().ok()?.is_file() {
        return None;
    }
    let len = f.seek(SeekFrom::End(0)).ok()?;
    let start = len.saturating_sub(1 << 16);
    f.seek(SeekFrom::Start(start)).ok()?;
    let mut bytes = Vec::new();
    f.take(1 << 16).read_to_end(&mut bytes).ok()?;
    let text = String::from_utf8_lossy(&bytes);
    text.lines()
        .rev()
        .map(|l| l.split('#').next().unwrap_or(""))
        .find(|l| !l.trim().is_empty())
        .and_then(|l| l.split_ascii_whitespace().next())
        .and_then(|t| t.parse().ok())
}
