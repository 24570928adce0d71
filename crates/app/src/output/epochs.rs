//! The per-epoch CSV layout and a streaming writer for it.

use std::fmt::Write as _;
use std::io;

use crate::experiment::{EpochRecord, PositionAxes};

/// The column names of the per-epoch CSV, units in the names: time, the
/// position error in `axes`, the velocity and attitude errors north, east,
/// down, then what the update did.
///
/// ```
/// use kestrel_app::output::epoch_columns;
/// use kestrel_app::experiment::PositionAxes;
/// let c = epoch_columns(PositionAxes::NorthEastDown);
/// assert_eq!(c[..4], ["time_s", "pos_north_m", "pos_east_m", "pos_down_m"]);
/// assert_eq!(c.len(), 19);
/// assert_eq!(c[18], "nees");
/// ```
pub fn epoch_columns(axes: PositionAxes) -> [&'static str; 19] {
    let position = match axes {
        PositionAxes::NorthEastDown => ["pos_north_m", "pos_east_m", "pos_down_m"],
        PositionAxes::EastNorthUp => ["pos_east_m", "pos_north_m", "pos_up_m"],
    };
    [
        "time_s",
        position[0],
        position[1],
        position[2],
        "vel_north_mps",
        "vel_east_mps",
        "vel_down_mps",
        "att_north_deg",
        "att_east_deg",
        "att_down_deg",
        "nis",
        "rejected",
        "fade",
        "inflation",
        "inflated",
        "compression",
        "alpha1",
        "noise_trace",
        "nees",
    ]
}

/// Writes epoch records as CSV rows one at a time, so a long run can be
/// streamed to disk instead of kept in memory.
///
/// ```
/// use kestrel_app::output::EpochCsvWriter;
/// use kestrel_app::experiment::{Adaptation, EpochRecord, PositionAxes};
/// use kestrel::nav::nalgebra::Vector3;
/// let mut w = EpochCsvWriter::new(Vec::new(), PositionAxes::NorthEastDown).unwrap();
/// let r = EpochRecord { time: 0.1, position: Vector3::zeros(), velocity: Vector3::zeros(),
///     attitude: Vector3::zeros(), adaptation: Adaptation { rejected: true, ..Adaptation::default() },
///     position_nees: None };
/// w.write(&r).unwrap();
/// let text = String::from_utf8(w.finish_into_inner().unwrap()).unwrap();
/// assert_eq!(text.lines().nth(1), Some("0.1,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,1,1.0,1.0,0,1.0,1.0,0.0,"));
/// ```
pub struct EpochCsvWriter<W: io::Write> {
    csv: Rows<W>,
    axes: PositionAxes,
    field: String,
}

/// CSV rows of fields that never need quoting (numbers, fixed names): each
/// row is assembled in a reused buffer and written in one call.
struct Rows<W: io::Write> {
    out: W,
    row: Vec<u8>,
    fields: usize,
}

impl<W: io::Write> Rows<W> {
    fn from_writer(out: W) -> Self {
        Self {
            out,
            row: Vec::with_capacity(512),
            fields: 0,
        }
    }

    fn write_field(&mut self, field: &str) -> io::Result<()> {
        debug_assert!(!field.contains([',', '"', '\n', '\r']), "{field}");
        if self.fields > 0 {
            self.row.push(b',');
        }
        self.row.extend_from_slice(field.as_bytes());
        self.fields += 1;
        Ok(())
    }

    fn write_record<I: IntoIterator<Item = T>, T: AsRef<str>>(
        &mut self,
        fields: I,
    ) -> io::Result<()> {
        for f in fields {
            self.write_field(f.as_ref())?;
        }
        self.end_record()
    }

    fn end_record(&mut self) -> io::Result<()> {
        self.row.push(b'\n');
        self.out.write_all(&self.row)?;
        self.row.clear();
        self.fields = 0;
        Ok(())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    fn into_inner(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// The column after the attitude errors in the every-epoch layout
/// ([`EpochCsvWriter::with_update_column`]): 1 at an aiding epoch.
pub const UPDATE_COLUMN: &str = "update";

impl<W: io::Write> EpochCsvWriter<W> {
    /// A writer to `out` that has written the header.
    ///
    /// # Errors
    /// The I/O error of writing the header.
    pub fn new(out: W, axes: PositionAxes) -> io::Result<Self> {
        let mut csv = Rows::from_writer(out);
        csv.write_record(epoch_columns(axes))?;
        Ok(Self {
            csv,
            axes,
            field: String::with_capacity(32),
        })
    }

    /// A writer of rows at every compared epoch, aiding or not: after the
    /// attitude errors an `update` column (1 at an aiding epoch, else 0),
    /// and the update's columns are empty where there was none.
    ///
    /// # Errors
    /// The I/O error of writing the header.
    ///
    /// ```
    /// use kestrel_app::output::EpochCsvWriter;
    /// use kestrel_app::experiment::{EpochRecord, PositionAxes};
    /// use kestrel::nav::nalgebra::Vector3;
    /// let mut w = EpochCsvWriter::with_update_column(Vec::new(), PositionAxes::NorthEastDown).unwrap();
    /// let r = EpochRecord { time: 0.5, position: Vector3::new(1.0, 0.0, 0.0),
    ///     velocity: Vector3::zeros(), attitude: Vector3::zeros(), adaptation: Default::default(), position_nees: None };
    /// w.write_compared(&r, false, false).unwrap();
    /// let text = String::from_utf8(w.finish_into_inner().unwrap()).unwrap();
    /// assert!(text.starts_with("time_s,pos_north_m,pos_east_m,pos_down_m,vel_north_mps,"));
    /// assert!(text.lines().next().unwrap().contains(",att_down_deg,update,nis,"));
    /// assert_eq!(text.lines().nth(1), Some("0.5,1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0,,,,,,,,,"));
    /// ```
    pub fn with_update_column(out: W, axes: PositionAxes) -> io::Result<Self> {
        let mut csv = Rows::from_writer(out);
        let columns = epoch_columns(axes);
        let header = columns[..10]
            .iter()
            .chain(&[UPDATE_COLUMN])
            .chain(&columns[10..]);
        csv.write_record(header)?;
        Ok(Self {
            csv,
            axes,
            field: String::with_capacity(32),
        })
    }

    /// Writes one row of the every-epoch layout; `update`: whether an
    /// aiding update was made at this epoch (its columns are empty if not);
    /// `position_only`: the reference has no velocity or attitude (their
    /// columns are empty).
    ///
    /// # Errors
    /// The I/O error of writing it.
    pub fn write_compared(
        &mut self,
        r: &EpochRecord,
        update: bool,
        position_only: bool,
    ) -> io::Result<()> {
        if position_only {
            let p = self.axes.from_ned(&r.position);
            self.number(r.time)?;
            for v in p.iter() {
                self.number(*v)?;
            }
            for _ in 0..6 {
                self.text("")?;
            }
        } else {
            self.errors(r)?;
        }
        if update {
            self.text("1")?;
            self.adaptation(&r.adaptation)?;
        } else {
            self.text("0")?;
            for _ in 0..8 {
                self.text("")?;
            }
        }
        self.nees(r.position_nees)?;
        self.csv.end_record()
    }

    /// The NEES column: the value, or empty without one.
    fn nees(&mut self, nees: Option<f64>) -> io::Result<()> {
        match nees {
            Some(v) => self.number(v),
            None => self.text(""),
        }
    }

    /// Flushes what is buffered, keeping the writer.
    ///
    /// # Errors
    /// The I/O error of flushing.
    pub fn flush(&mut self) -> io::Result<()> {
        self.csv.flush()
    }

    fn errors(&mut self, r: &EpochRecord) -> io::Result<()> {
        let to_deg = 180.0 / std::f64::consts::PI;
        let p = self.axes.from_ned(&r.position);
        self.number(r.time)?;
        for v in p.iter().chain(r.velocity.iter()) {
            self.number(*v)?;
        }
        for v in r.attitude.iter() {
            self.number(v * to_deg)?;
        }
        Ok(())
    }

    fn adaptation(&mut self, a: &crate::experiment::Adaptation) -> io::Result<()> {
        self.number(a.nis)?;
        self.text(if a.rejected { "1" } else { "0" })?;
        self.number(a.fade)?;
        self.number(a.inflation)?;
        self.field.clear();
        let _ = write!(self.field, "{}", a.inflated);
        self.csv.write_field(&self.field)?;
        self.number(a.compression)?;
        self.number(a.alpha1)?;
        self.number(a.noise_trace)
    }

    /// Writes one row.
    ///
    /// # Errors
    /// The I/O error of writing it.
    pub fn write(&mut self, r: &EpochRecord) -> io::Result<()> {
        self.errors(r)?;
        self.adaptation(&r.adaptation)?;
        self.nees(r.position_nees)?;
        self.csv.end_record()
    }

    /// Flushes what is buffered.
    ///
    /// # Errors
    /// The I/O error of flushing.
    pub fn finish(mut self) -> io::Result<()> {
        self.csv.flush()
    }

    /// Flushes and returns the underlying writer.
    ///
    /// # Errors
    /// The I/O error of flushing.
    pub fn finish_into_inner(self) -> io::Result<W> {
        self.csv.into_inner()
    }

    /// The shortest digits that parse back to the same `f64`; `Debug`
    /// rather than `Display` so that tiny and huge values get an exponent
    /// instead of hundreds of zeros.
    fn number(&mut self, v: f64) -> io::Result<()> {
        if v.is_finite() {
            // Ryū: the same shortest round-trip digits as `{v:?}`, at about
            // twice the speed (this is the hot loop of `process --truth`).
            let mut buffer = ryu::Buffer::new();
            return self.csv.write_field(buffer.format_finite(v));
        }
        self.field.clear();
        let _ = write!(self.field, "{v:?}");
        self.csv.write_field(&self.field)
    }

    fn text(&mut self, s: &str) -> io::Result<()> {
        self.csv.write_field(s)
    }
}
