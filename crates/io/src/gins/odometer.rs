//! Odometer speeds in their own file: `sow speed` (GPS seconds of week,
//! m/s), one reading per line.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use super::line::{open, Lines};
use super::stream::Stream;
use crate::InputError;

const NAMES: &[&str] = &["time, s of week", "speed, m/s"];
const LAYOUT: &str = "time, speed";

/// One odometer reading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedRecord {
    /// GPS seconds of week (continued across a rollover).
    pub time: f64,
    /// Forward speed, m/s.
    pub speed: f64,
    /// Line in the file.
    pub line: usize,
}

/// Streams [`SpeedRecord`]s; times must increase, speeds lie within
/// ±[`WHEEL_SPEED`](super::physical::WHEEL_SPEED) (200 m/s).
///
/// ```
/// use kestrel_io::gins::OdometerReader;
/// let r: Vec<_> = OdometerReader::new("0.1 5.5\n0.2 5.6\n".as_bytes(), "odo.txt".as_ref()).collect();
/// assert_eq!(r[1].as_ref().unwrap().speed, 5.6);
/// let e = OdometerReader::new("0.1 1e9\n".as_bytes(), "odo.txt".as_ref()).next().unwrap();
/// assert!(e.unwrap_err().to_string().starts_with("odo.txt:1:2: expected an odometer speed"));
/// ```
#[derive(Debug)]
pub struct OdometerReader<R> {
    stream: Stream<R>,
}

impl OdometerReader<BufReader<File>> {
    /// Opens the odometer file at `path`.
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open(path: &Path) -> Result<Self, InputError> {
        Ok(Self::new(open(path)?, path))
    }
}

impl<R: BufRead> OdometerReader<R> {
    /// Reads odometer lines from `reader`, calling it `path` in errors.
    pub fn new(reader: R, path: &Path) -> Self {
        Self {
            stream: Stream::new(Lines::new(reader, path, NAMES, &[2], LAYOUT)),
        }
    }

    /// The file's name.
    pub fn path(&self) -> &Path {
        self.stream.path()
    }
}

impl<R: BufRead> Iterator for OdometerReader<R> {
    type Item = Result<SpeedRecord, InputError>;

    /// The next reading; after an error the reader ends.
    fn next(&mut self) -> Option<Self::Item> {
        self.stream.next(|s, f| {
            let time = s.advance_seconds(f)?;
            s.wheel_speeds(f, &[1])?;
            Ok(SpeedRecord {
                time,
                speed: f.get(1),
                line: f.line,
            })
        })
    }
}
