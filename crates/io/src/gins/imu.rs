//! IMU increments: `sow Δθx Δθy Δθz Δvx Δvy Δvz [odometer]`.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use kestrel_nav::nalgebra::{Matrix3, Vector3};
use kestrel_nav::ImuIncrement;

use super::imu_format::{ImuFormat, Measures, Sample, TimeBase};
use super::line::{open, Fields, Lines};
use super::physical;
use super::stream::Stream;
use crate::{Error, InputError};

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
/// use kestrel_io::gins::ImuRecord;
/// use kestrel_nav::nalgebra::Vector3;
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
/// use kestrel_io::gins::ImuReader;
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
    /// A configured layout (`None`: the GINS format).
    configured: Option<Configured>,
    /// The time of the previous record, for the rates its increments mean.
    previous: Option<f64>,
}

/// What a reader of a configured layout keeps.
#[derive(Debug)]
struct Configured {
    format: ImuFormat,
    to_vehicle: Matrix3<f64>,
    week0: u32,
    /// The time before the first sample (the initial time), s.
    start: f64,
    /// The previous sample's time and rates (rates only).
    previous: Option<(f64, Vector3<f64>, Vector3<f64>)>,
}

impl ImuReader<BufReader<File>> {
    /// Opens the IMU file at `path`.
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open(path: &Path) -> Result<Self, InputError> {
        Ok(Self::new(open(path)?, path))
    }

    /// Opens the IMU file at `path` laid out as `format` (see
    /// [`ImuReader::with_format`]).
    ///
    /// # Errors
    /// [`InputError`] naming the file if it cannot be opened.
    pub fn open_with_format(
        path: &Path,
        format: &ImuFormat,
        week0: u32,
        start: f64,
    ) -> Result<Self, InputError> {
        Ok(Self::with_format(open(path)?, path, format, week0, start))
    }
}

impl<R: BufRead> ImuReader<R> {
    /// Reads IMU lines from `reader`, calling it `path` in errors. Gaps
    /// (dropouts) are not the reader's business: `process` bridges or
    /// refuses them by its configured timing rule.
    pub fn new(reader: R, path: &Path) -> Self {
        Self {
            stream: Stream::new(Lines::new(reader, path, NAMES, &[7, 8], LAYOUT)),
            configured: None,
            previous: None,
        }
    }

    /// Reads IMU lines laid out as `format` says; times become seconds of
    /// GPS week `week0` (continuing past its end); rates are integrated
    /// from `start` (the initial time) on.
    pub fn with_format(reader: R, path: &Path, format: &ImuFormat, week0: u32, start: f64) -> Self {
        if format.is_gins() {
            return Self::new(reader, path);
        }
        Self {
            stream: Stream::new(Lines::selected(reader, path, format.selection())),
            configured: Some(Configured {
                format: format.clone(),
                to_vehicle: format.to_vehicle(),
                week0,
                start,
                previous: None,
            }),
            previous: None,
        }
    }

    /// Whether the records hold increments already integrated over their
    /// actual intervals (rates), so a dropout needs no rescaling.
    pub fn integrated(&self) -> bool {
        self.configured
            .as_ref()
            .is_some_and(|c| c.format.measures == Measures::Rates)
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
        let record = self.read()?;
        Some(record.and_then(|r| {
            let checked = plausible(&r, self.previous, self.stream.path());
            self.previous = Some(r.time);
            checked.map(|()| r)
        }))
    }
}

/// Refuses a record whose increments mean a rotation rate or a specific
/// force beyond any IMU's range ([`ROTATION_RATE`](physical::ROTATION_RATE),
/// [`SPECIFIC_FORCE`](physical::SPECIFIC_FORCE)) over the interval since
/// the `previous` record (the first record has none and is not judged).
fn plausible(r: &ImuRecord, previous: Option<f64>, path: &Path) -> Result<(), InputError> {
    let Some(t0) = previous else { return Ok(()) };
    let dt = r.time - t0;
    if dt <= 0.0 {
        return Ok(());
    }
    let checks = [
        (
            r.dtheta,
            2,
            "a rotation",
            "rad",
            "rad/s",
            physical::ROTATION_RATE,
            "125.7 rad/s, 20 turns a second",
        ),
        (
            r.dvel,
            5,
            "a velocity increment",
            "m/s",
            "m/s²",
            physical::SPECIFIC_FORCE,
            "9806.65 m/s², 1000 g",
        ),
    ];
    for (v, column, what, unit, per_s, max, bound) in checks {
        for k in 0..3 {
            let rate = v[k].abs() / dt;
            if rate.is_nan() || rate > max {
                return Err(InputError::at(
                    path,
                    r.line,
                    column + k,
                    format!(
                        "{what} of {} {unit} in {} s is {} {per_s}, beyond any IMU's range \
                         (at most {bound}; is the column in the right unit?)",
                        physical::show(v[k]),
                        physical::show((dt * 1e9).round() / 1e9),
                        physical::show(rate),
                    ),
                ));
            }
        }
    }
    Ok(())
}

impl<R: BufRead> ImuReader<R> {
    /// The next record as the file has it.
    fn read(&mut self) -> Option<Result<ImuRecord, InputError>> {
        if let Some(c) = self.configured.as_mut() {
            return self.stream.next(|s, f| configured_record(c, s, f));
        }
        self.stream.next(|s, f| {
            let v = &f.values;
            let time = s.advance_seconds(f)?;
            s.wheel_speeds(f, &[7])?;
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

/// The record of a line of a configured layout.
fn configured_record<R: BufRead>(
    c: &mut Configured,
    s: &mut Stream<R>,
    f: &Fields,
) -> Result<ImuRecord, InputError> {
    let v = &f.values[..f.count];
    let time = match c.format.time_base {
        TimeBase::SecondsOfWeek => s.advance_seconds(f)?,
        _ => {
            let week = c.format.week.map(|_| v[1]);
            if let Some(w) = week.filter(|w| *w < 0.0 || w.fract() != 0.0) {
                return Err(s.at(f, 2, format!("expected a whole GPS week, found {w}")));
            }
            let t = c.format.time_of(v[0], week, c.week0);
            s.advance(t, f).map_err(|(t0, l0)| {
                s.at(
                    f,
                    1,
                    format!("time does not increase: not after line {l0} ({t0} s of the week)"),
                )
            })?;
            t
        }
    };
    let sample = Sample::from_values(&c.format, v, &c.to_vehicle);
    if c.format.odometer.is_some() {
        s.wheel_speeds(f, &[f.count - 1])?;
    }
    let (dtheta, dvel) = match c.format.measures {
        Measures::Increments => (sample.gyro, sample.accel),
        Measures::Rates => {
            let (gyro, accel) = match c.previous {
                Some((_, g, a)) => ((g + sample.gyro) * 0.5, (a + sample.accel) * 0.5),
                None => (sample.gyro, sample.accel),
            };
            let from = c.previous.map_or(c.start, |p| p.0.max(c.start));
            c.previous = Some((time, sample.gyro, sample.accel));
            let dt = (time - from).max(0.0);
            (gyro * dt, accel * dt)
        }
    };
    Ok(ImuRecord {
        time,
        dtheta,
        dvel,
        odometer: sample.odometer,
        line: f.line,
    })
}

/// Writes IMU lines.
///
/// ```
/// use kestrel_io::gins::{ImuReader, ImuRecord, ImuWriter};
/// use kestrel_nav::nalgebra::Vector3;
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
    /// [`Error::Io`] if it cannot be created.
    pub fn create(path: &Path) -> Result<Self, Error> {
        let f = File::create(path).map_err(|e| Error::io(path, e))?;
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
