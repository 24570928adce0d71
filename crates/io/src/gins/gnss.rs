//! GNSS fixes: `sow lat lon h σN σE σD [vN vE vD σvN σvE σvD]`.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use kestrel_nav::measurement::GnssFix;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::Geodetic;

use super::angle::{degrees_to_radians, PositionColumns};
use super::line::{open, Lines};
use super::stream::Stream;
use crate::{Error, InputError};

const NAMES: &[&str] = &[
    "time, s of week",
    "latitude, deg",
    "longitude, deg",
    "height, m",
    "σ north, m",
    "σ east, m",
    "σ down, m",
    "velocity north, m/s",
    "velocity east, m/s",
    "velocity down, m/s",
    "σ velocity north, m/s",
    "σ velocity east, m/s",
    "σ velocity down, m/s",
];
const LAYOUT: &str = "time, lat, lon, h, σ NED, optional velocity NED and its σ";
const STD_COLUMNS: [usize; 6] = [4, 5, 6, 10, 11, 12];

/// Streams [`GnssFix`]es from a GNSS file; times must increase, gaps are
/// allowed. Every line must have the column count of the first data line.
///
/// ```
/// use kestrel_io::gins::GnssReader;
/// let text = "1 30 114 20 1 1 2\n2 30 114 20 1 1 2\n";
/// let fixes: Vec<_> = GnssReader::new(text.as_bytes(), "gnss.txt".as_ref()).collect();
/// assert_eq!(fixes[1].as_ref().unwrap().time, 2.0);
/// assert!(fixes[0].as_ref().unwrap().vel.is_none());
/// let bad = "1 30 114 20 1 1 0\n";
/// let e = GnssReader::new(bad.as_bytes(), "gnss.txt".as_ref()).next().unwrap().unwrap_err();
/// assert!(e.to_string().starts_with("gnss.txt:1:7: expected a standard deviation"));
/// ```
#[derive(Debug)]
pub struct GnssReader<R> {
    stream: Stream<R>,
}

impl GnssReader<BufReader<File>> {
    /// Opens the GNSS file at `path`.
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open(path: &Path) -> Result<Self, InputError> {
        Ok(Self::new(open(path)?, path))
    }
}

impl<R: BufRead> GnssReader<R> {
    /// Reads GNSS lines from `reader`, calling it `path` in errors.
    pub fn new(reader: R, path: &Path) -> Self {
        Self {
            stream: Stream::new(Lines::new(reader, path, NAMES, &[7, 13], LAYOUT)),
        }
    }
}

impl<R: BufRead> GnssReader<R> {
    /// The file's name.
    pub fn path(&self) -> &Path {
        self.stream.path()
    }

    /// The line of the last fix read (`None` before the first).
    pub fn last_line(&self) -> Option<usize> {
        self.stream.last_line()
    }
}

impl<R: BufRead> Iterator for GnssReader<R> {
    type Item = Result<GnssFix, InputError>;

    /// The next fix; after an error the reader ends.
    fn next(&mut self) -> Option<Self::Item> {
        self.stream.next(|s, f| {
            let v = &f.values;
            let time = s.advance_seconds(f)?;
            s.position(f, 1)?;
            s.sigmas(f, &STD_COLUMNS, NAMES)?;
            s.speeds(f, &[7, 8, 9])?;
            let pos = Geodetic::new(degrees_to_radians(v[1]), degrees_to_radians(v[2]), v[3]);
            let pos_std = Vector3::new(v[4], v[5], v[6]);
            Ok(if f.count == 13 {
                GnssFix::new(time, pos, Vector3::new(v[7], v[8], v[9]))
                    .with_std(pos_std, Vector3::new(v[10], v[11], v[12]))
            } else {
                let p = GnssFix::position_only(time, pos);
                p.with_std(pos_std, p.vel_std)
            })
        })
    }
}

/// Writes GNSS lines: 13 columns for fixes with velocity, 7 without.
///
/// ```
/// use kestrel_io::gins::{GnssReader, GnssWriter};
/// use kestrel_nav::{measurement::GnssFix, nalgebra::Vector3, Geodetic};
/// let fix = GnssFix::new(1.5, Geodetic::from_degrees(30.5, 114.2, 21.3), Vector3::new(1.0, 2.0, 0.1))
///     .with_std(Vector3::new(0.5, 0.5, 1.0), Vector3::repeat(0.05));
/// let mut w = GnssWriter::new(Vec::new());
/// w.write(&fix).unwrap();
/// let bytes = w.into_inner().unwrap();
/// let back = GnssReader::new(&bytes[..], "g".as_ref()).next().unwrap().unwrap();
/// assert_eq!(back, fix);
/// ```
#[derive(Debug)]
pub struct GnssWriter<W: Write> {
    out: W,
}

impl GnssWriter<BufWriter<File>> {
    /// Creates the GNSS file at `path`.
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be created.
    pub fn create(path: &Path) -> Result<Self, Error> {
        let f = File::create(path).map_err(|e| Error::io(path, e))?;
        Ok(Self::new(BufWriter::new(f)))
    }
}

impl<W: Write> GnssWriter<W> {
    /// Writes GNSS lines to `out`.
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

    /// Writes one fix with its σ.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn write(&mut self, fix: &GnssFix) -> std::io::Result<()> {
        let s = &fix.pos_std;
        write!(
            self.out,
            "{} {} {} {} {}",
            fix.time,
            PositionColumns(&fix.pos),
            s.x,
            s.y,
            s.z
        )?;
        if let Some(v) = &fix.vel {
            let s = &fix.vel_std;
            write!(self.out, " {} {} {} {} {} {}", v.x, v.y, v.z, s.x, s.y, s.z)?;
        }
        writeln!(self.out)
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
