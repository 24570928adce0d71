//! Navigation results and truth:
//! `week sow lat lon h vN vE vD roll pitch yaw`.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Euler, Geodetic, NavState};

use super::angle::{degrees_exact, degrees_to_radians};
use super::line::{open, Lines};
use super::stream::Stream;
use crate::{Error, InputError};

const NAMES: &[&str] = &[
    "GNSS week",
    "time, s of week",
    "latitude, deg",
    "longitude, deg",
    "height, m",
    "velocity north, m/s",
    "velocity east, m/s",
    "velocity down, m/s",
    "roll, deg",
    "pitch, deg",
    "yaw, deg",
];
const LAYOUT: &str = "week, time, lat, lon, h, velocity NED, roll, pitch, yaw";
/// Seconds in a GNSS week.
pub const WEEK_SECONDS: f64 = 604_800.0;

/// One navigation line: the GNSS week and the state (its `time` in seconds
/// of week).
///
/// ```
/// use kestrel_io::gins::NavRecord;
/// use kestrel_nav::{NavState, Geodetic, Euler, nalgebra::Vector3};
/// let r = NavRecord { week: 2300, state: NavState::new(10.0, Geodetic::new(0.5, 2.0, 0.0),
///     Vector3::zeros(), Euler::default()), line: 0 };
/// assert_eq!(r.state.time, 10.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct NavRecord {
    /// GNSS week.
    pub week: u32,
    /// Position, velocity, attitude at `state.time` (seconds of week).
    pub state: NavState,
    /// Line number in the file (0 when not read from one).
    pub line: usize,
}

/// Streams [`NavRecord`]s; week and time together must increase.
///
/// ```
/// use kestrel_io::gins::NavReader;
/// let text = "2300 1 30 114 20 1 0 0 0 0 90\n";
/// let r = NavReader::new(text.as_bytes(), "truth.nav".as_ref()).next().unwrap().unwrap();
/// assert_eq!((r.week, r.state.time), (2300, 1.0));
/// assert!((r.state.euler().yaw - 90f64.to_radians()).abs() < 1e-12);
/// ```
#[derive(Debug)]
pub struct NavReader<R> {
    stream: Stream<R>,
}

impl NavReader<BufReader<File>> {
    /// Opens the navigation file at `path`.
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open(path: &Path) -> Result<Self, InputError> {
        Ok(Self::new(open(path)?, path))
    }
}

impl<R: BufRead> NavReader<R> {
    /// Reads navigation lines from `reader`, calling it `path` in errors.
    pub fn new(reader: R, path: &Path) -> Self {
        Self {
            stream: Stream::new(Lines::new(reader, path, NAMES, &[11], LAYOUT)),
        }
    }
}

impl<R: BufRead> Iterator for NavReader<R> {
    type Item = Result<NavRecord, InputError>;

    /// The next record; after an error the reader ends.
    fn next(&mut self) -> Option<Self::Item> {
        self.stream.next(|s, f| {
            let v = &f.values;
            if v[0] < 0.0 || v[0].fract() != 0.0 || v[0] > f64::from(u32::MAX) {
                return Err(s.at(f, 1, format!("expected a whole GNSS week, found {}", v[0])));
            }
            s.position(f, 2)?;
            s.speeds(f, &[5, 6, 7])?;
            s.advance(v[0] * WEEK_SECONDS + v[1], f)
                .map_err(|(_, l0)| {
                    s.at(
                        f,
                        2,
                        format!(
                            "time does not increase: not after line {l0} (expected increasing \
                         week and seconds of week)"
                        ),
                    )
                })?;
            let pos = Geodetic::new(degrees_to_radians(v[2]), degrees_to_radians(v[3]), v[4]);
            let euler = Euler::from_degrees(v[8], v[9], v[10]);
            Ok(NavRecord {
                week: v[0] as u32,
                state: NavState::new(v[1], pos, Vector3::new(v[5], v[6], v[7]), euler),
                line: f.line,
            })
        })
    }
}

/// Writes navigation lines.
///
/// ```
/// use kestrel_io::gins::{NavReader, NavWriter};
/// use kestrel_nav::{NavState, Geodetic, Euler, nalgebra::Vector3};
/// let s = NavState::new(0.3, Geodetic::from_degrees(30.5, 114.2, 21.3), Vector3::new(1.0, 2.0, 0.1),
///     Euler::from_degrees(1.0, -2.0, 350.0));
/// let mut w = NavWriter::new(Vec::new());
/// w.write(2300, &s).unwrap();
/// let bytes = w.into_inner().unwrap();
/// let back = NavReader::new(&bytes[..], "n".as_ref()).next().unwrap().unwrap();
/// assert_eq!((back.state.time, back.state.pos, back.state.vel), (s.time, s.pos, s.vel));
/// assert!(back.state.att.angle_to(&s.att) < 1e-15);
/// ```
#[derive(Debug)]
pub struct NavWriter<W: Write> {
    out: W,
    line: String,
}

impl NavWriter<BufWriter<File>> {
    /// Creates the navigation file at `path`.
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be created.
    pub fn create(path: &Path) -> Result<Self, Error> {
        let f = File::create(path).map_err(|e| Error::io(path, e))?;
        Ok(Self::new(BufWriter::with_capacity(1 << 16, f)))
    }
}

impl<W: Write> NavWriter<W> {
    /// Writes navigation lines to `out`.
    pub fn new(out: W) -> Self {
        Self {
            out,
            line: String::with_capacity(256),
        }
    }

    /// Writes a `#` comment line.
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn comment(&mut self, text: &str) -> std::io::Result<()> {
        writeln!(self.out, "# {text}")
    }

    /// Writes `state` (its time in seconds of `week`).
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn write(&mut self, week: u32, state: &NavState) -> std::io::Result<()> {
        self.line.clear();
        nav_line(week, state, &mut self.line);
        self.out.write_all(self.line.as_bytes())
    }

    /// Flushes the underlying writer.
    ///
    /// # Errors
    /// The flush error.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
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

/// Appends the navigation line of `state` in `week` (with its newline) to
/// `out`: the columns separated by single spaces, numbers as shortest
/// round-trip decimals, latitude and longitude by
/// [`degrees_exact`](super::degrees_exact).
///
/// ```
/// use kestrel_nav::{NavState, Geodetic, Euler, nalgebra::Vector3};
/// let s = NavState::new(1.5, Geodetic::new(0.5, 2.0, 20.0), Vector3::new(1.0, 0.0, 0.0),
///     Euler::default());
/// let mut line = String::new();
/// kestrel_io::gins::nav_line(2300, &s, &mut line);
/// assert!(line.starts_with("2300 1.5 28.64788975654116 114.59155902616465 20.0 1.0 0.0 0.0 "));
/// assert_eq!(line.split(' ').count(), 11);
/// ```
pub fn nav_line(week: u32, state: &NavState, out: &mut String) {
    use std::fmt::Write as _;
    let [roll, pitch, yaw] = state.euler().to_degrees();
    let v = &state.vel;
    // Times continued across a week rollover (≥ 604 800 s) go out as the
    // next week.
    let weeks = (state.time / WEEK_SECONDS).floor().max(0.0);
    let (week, time) = (week + weeks as u32, state.time - weeks * WEEK_SECONDS);
    // Writing into a String cannot fail.
    let _ = write!(out, "{week}");
    let p = &state.pos;
    let columns = [
        time,
        degrees_exact(p.lat),
        degrees_exact(p.lon),
        p.h,
        v.x,
        v.y,
        v.z,
        roll,
        pitch,
        yaw,
    ];
    // Ryū: shortest round-trip digits, at about twice the speed of `{}`
    // (a 200 Hz result is the hot loop of `process`).
    let mut buffer = ryu::Buffer::new();
    for x in columns {
        out.push(' ');
        if x.is_finite() {
            out.push_str(buffer.format_finite(x));
        } else {
            let _ = write!(out, "{x}");
        }
    }
    out.push('\n');
}
