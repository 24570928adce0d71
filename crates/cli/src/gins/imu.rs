//! IMU increments: `sow Δθx Δθy Δθz Δvx Δvy Δvz [odometer]`.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::ImuIncrement;

use super::line::{open, Lines};
use super::stream::Stream;
use crate::{CliError, InputError};

const NAMES: &[&str] = &[
    "time, s of week",
    "Δθ x, rad",
    "Δθ y, rad",
    "Δθ z, rad",
    "Δv x, m/s",
    "Δv y, m/s",
    "Δv z, m/s",
    "odometer speed, m/s",
];
const LAYOUT: &str = "time, Δθ xyz, Δv xyz, optional odometer speed";

/// One IMU line: increments over the interval ending at `time`.
///
/// ```
/// use kestrel_cli::gins::ImuRecord;
/// use kestrel::nav::nalgebra::Vector3;
/// let r = ImuRecord { time: 0.01, dtheta: Vector3::zeros(), dvel: Vector3::zeros(),
///     odometer: None, line: 1 };
/// assert_eq!(r.increment(0.005).dt, 0.005);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuRecord {
    /// End of the interval, GNSS seconds of week.
    pub time: f64,
    /// Angle increment, rad, forward-right-down.
    pub dtheta: Vector3<f64>,
    /// Velocity increment, m/s, forward-right-down.
    pub dvel: Vector3<f64>,
    /// Odometer speed, m/s (the optional 8th column).
    pub odometer: Option<f64>,
    /// Line number in the file (0 when not read from one).
    pub line: usize,
}

impl ImuRecord {
    /// The increment of this record, the previous sample being at `previous` s.
    pub fn increment(&self, previous: f64) -> ImuIncrement {
        ImuIncrement {
            time: self.time,
            dt: self.time - previous,
            dtheta: self.dtheta,
            dvel: self.dvel,
        }
    }
}

/// Streams [`ImuRecord`]s from an IMU file, checking the time line.
///
/// ```
/// use kestrel_cli::gins::ImuReader;
/// let text = "# t dθ dv\n0.01 1e-5 0 0 0 0 -0.098\n\n0.02 1e-5 0 0 0 0 -0.098\n";
/// let r: Vec<_> = ImuReader::new(text.as_bytes(), "imu.txt".as_ref()).collect();
/// assert_eq!(r.len(), 2);
/// assert_eq!(r[1].as_ref().unwrap().line, 4);
/// let bad = "0.01 1 0 0 0 0 0\n0.01 1 0 0 0 0 0\n";
/// let e = ImuReader::new(bad.as_bytes(), "imu.txt".as_ref()).nth(1).unwrap().unwrap_err();
/// assert!(e.to_string().starts_with("imu.txt:2:1: time does not increase"));
/// ```
#[derive(Debug)]
pub struct ImuReader<R> {
    stream: Stream<R>,
}

impl ImuReader<BufReader<File>> {
    /// Opens the IMU file at `path`.
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open(path: &Path) -> Result<Self, InputError> {
        Ok(Self::new(open(path)?, path))
    }
}

impl<R: BufRead> ImuReader<R> {
    /// Reads IMU lines from `reader`, calling it `path` in errors. Gaps
    /// (dropouts) are not the reader's business: `process` bridges or
    /// refuses them by its configured timing rule.
    pub fn new(reader: R, path: &Path) -> Self {
        Self {
            stream: Stream::new(Lines::new(reader, path, NAMES, &[7, 8], LAYOUT)),
        }
    }

    /// The file's name.
    pub fn path(&self) -> &Path {
        self.stream.path()
    }
}

impl<R: BufRead> Iterator for ImuReader<R> {
    type Item = Result<ImuRecord, InputError>;

    /// The next record; after an error the reader ends.
    fn next(&mut self) -> Option<Self::Item> {
        self.stream.next(|s, f| {
            let v = &f.values;
            let time = s.advance_seconds(f)?;
            s.speeds(f, &[7])?;
            Ok(ImuRecord {
                time,
                dtheta: Vector3::new(v[1], v[2], v[3]),
                dvel: Vector3::new(v[4], v[5], v[6]),
                odometer: (f.count == 8).then_some(v[7]),
                line: f.line,
            })
        })
    }
}

/// Writes IMU lines.
///
/// ```
/// use kestrel_cli::gins::{ImuReader, ImuRecord, ImuWriter};
/// use kestrel::nav::nalgebra::Vector3;
/// let r = ImuRecord { time: 0.1 + 0.2, dtheta: Vector3::new(1e-7, -3.3e-6, 0.1),
///     dvel: Vector3::new(0.1, 0.2, -0.098), odometer: Some(12.3), line: 0 };
/// let mut w = ImuWriter::new(Vec::new());
/// w.write(&r).unwrap();
/// let bytes = w.into_inner().unwrap();
/// let back = ImuReader::new(&bytes[..], "imu.txt".as_ref()).next().unwrap().unwrap();
/// assert_eq!(back, ImuRecord { line: 1, ..r });
/// ```
#[derive(Debug)]
pub struct ImuWriter<W: Write> {
    out: W,
}

impl ImuWriter<BufWriter<File>> {
    /// Creates the IMU file at `path`.
    ///
    /// # Errors
    /// [`CliError::Io`] if it cannot be created.
    pub fn create(path: &Path) -> Result<Self, CliError> {
        let f = File::create(path).map_err(|e| CliError::io(path, e))?;
        Ok(Self::new(BufWriter::with_capacity(1 << 16, f)))
    }
}

impl<W: Write> ImuWriter<W> {
    /// Writes IMU lines to `out`.
    pub fn new(out: W) -> Self {
        Self { out }
    }

    /// Writes a `#` comment line.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn comment(&mut self, text: &str) -> std::io::Result<()> {
        writeln!(self.out, "# {text}")
    }

    /// Writes one record (7 columns, 8 with an odometer speed).
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn write(&mut self, r: &ImuRecord) -> std::io::Result<()> {
        let (a, b) = (&r.dtheta, &r.dvel);
        write!(
            self.out,
            "{} {} {} {} {} {} {}",
            r.time, a.x, a.y, a.z, b.x, b.y, b.z
        )?;
        match r.odometer {
            Some(s) => writeln!(self.out, " {s}"),
            None => writeln!(self.out),
        }
    }

    /// Flushes and returns the underlying writer.
    ///
    /// # Errors
    /// The flush error.
    pub fn into_inner(mut self) -> std::io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}
