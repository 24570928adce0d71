//! Opening an input once: every file a run reads is opened here, read as a
//! stream by one reader, and tallied as it is read (bytes and SHA-256), so
//! a run can record what it read without reading anything twice. Pipes
//! and FIFOs work like files.

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;
use std::sync::{Arc, Mutex};

use sha2::{Digest, Sha256};

use crate::InputError;

/// What has been read of one input: its bytes and their SHA-256, and
/// whether the end was reached. Cheap to clone; every clone sees the same
/// count.
#[derive(Clone, Debug, Default)]
pub struct Tally(Arc<Mutex<TallyState>>);

#[derive(Debug, Default)]
struct TallyState {
    bytes: u64,
    hash: Sha256,
    end: bool,
}

impl Tally {
    /// Bytes read so far.
    pub fn bytes(&self) -> u64 {
        self.0.lock().map_or(0, |s| s.bytes)
    }

    /// Whether the reader reached the end of the input.
    pub fn reached_end(&self) -> bool {
        self.0.lock().is_ok_and(|s| s.end)
    }

    /// The SHA-256 of the bytes read so far, in hexadecimal.
    ///
    /// ```
    /// use std::io::Read;
    /// let p = std::env::temp_dir().join(format!("kestrel-tally-doc-{}", std::process::id()));
    /// std::fs::write(&p, "abc").unwrap();
    /// let (mut r, tally) = kestrel_io::input::open(&p).unwrap();
    /// let mut s = String::new();
    /// r.read_to_string(&mut s).unwrap();
    /// assert_eq!((tally.bytes(), tally.reached_end()), (3, true));
    /// assert_eq!(tally.sha256(),
    ///     "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    /// # std::fs::remove_file(&p).unwrap();
    /// ```
    pub fn sha256(&self) -> String {
        self.0.lock().map_or_else(
            |_| String::new(),
            |s| {
                s.hash
                    .clone()
                    .finalize()
                    .iter()
                    .map(|b| format!("{b:02x}"))
                    .collect()
            },
        )
    }

    fn update(&self, bytes: &[u8]) {
        if let Ok(mut s) = self.0.lock() {
            if bytes.is_empty() {
                s.end = true;
            } else {
                s.bytes += bytes.len() as u64;
                s.hash.update(bytes);
            }
        }
    }
}

/// A reader that tallies what passes through it.
#[derive(Debug)]
pub struct Tapped<R> {
    inner: R,
    tally: Tally,
}

impl<R: Read> Read for Tapped<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.tally.update(&buf[..n]);
        Ok(n)
    }
}

/// An input opened by [`open`]: buffered, tallied.
pub type Input = BufReader<Tapped<File>>;

/// Opens the input `path` once, for one reader: a regular file, a pipe, a
/// FIFO or a device (a folder is refused). Returns the reader and its
/// [`Tally`].
///
/// # Errors
/// [`InputError`] naming the file if it cannot be opened or is a folder.
pub fn open(path: &Path) -> Result<(Input, Tally), InputError> {
    let file = File::open(path)
        .map_err(|e| InputError::file(path, format!("cannot read the file: {e}")))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(InputError::file(path, "is a folder, not a file"));
    }
    let tally = Tally::default();
    let tapped = Tapped {
        inner: file,
        tally: tally.clone(),
    };
    Ok((BufReader::with_capacity(1 << 16, tapped), tally))
}
