//! IMU files as recorders write them: rates or increments, in degrees or
//! radians, g or m/s, any axes and mounting, any columns, a delimiter, a
//! header, and GPS seconds of week, GPS week + seconds or Unix time — read
//! by configuration (`[imu_file]`) without a conversion script.

use kestrel_nav::nalgebra::{Matrix3, Vector3};
use kestrel_nav::Euler;

use super::line::{Delimiter, Selection};
use super::nav::WEEK_SECONDS;

/// Seconds from the Unix epoch (1970-01-01 UTC) to the GPS epoch
/// (1980-01-06 UTC).
pub const GPS_EPOCH_UNIX: f64 = 315_964_800.0;

/// What the time column holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeBase {
    /// GPS seconds of week (a rollover continues the time).
    SecondsOfWeek,
    /// GPS week in the `week` column, seconds of week in the time column.
    WeekSeconds,
    /// Unix seconds (UTC); GPS time is ahead by `leap_seconds` (18 s since
    /// 2017-01-01).
    Unix {
        /// GPS − UTC, s.
        leap_seconds: f64,
    },
}

/// What the gyro and accelerometer columns hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measures {
    /// Increments over the interval ending at the sample (Δθ, Δv).
    Increments,
    /// Rates at the sample (ω, f): integrated with the trapezoidal rule
    /// between consecutive samples (the first after the initial time by its
    /// own rate), over the actual interval, dropouts included.
    Rates,
}

/// One file axis with its sign: `(index 0..3 of x, y, z, ±1)`.
pub type SignedAxis = (usize, f64);

/// The layout and meaning of an IMU file. [`Default`] is the GINS format:
/// whitespace, `time Δθxyz Δvxyz [odometer]`, rad and m/s,
/// forward-right-down, GPS seconds of week.
#[derive(Clone, Debug, PartialEq)]
pub struct ImuFormat {
    /// What separates the columns.
    pub delimiter: Delimiter,
    /// Lines skipped at the top (a CSV header).
    pub header_lines: usize,
    /// Column (0-based) of the time.
    pub time: usize,
    /// Column of the GPS week ([`TimeBase::WeekSeconds`]).
    pub week: Option<usize>,
    /// Columns of the gyro x, y, z.
    pub gyro: [usize; 3],
    /// Columns of the accelerometer x, y, z.
    pub accel: [usize; 3],
    /// Column of the odometer speed, m/s.
    pub odometer: Option<usize>,
    /// What the time column holds.
    pub time_base: TimeBase,
    /// Increments or rates.
    pub measures: Measures,
    /// Factor from the gyro unit to rad (increments) or rad/s (rates).
    pub gyro_unit: f64,
    /// Factor from the accelerometer unit to m/s (increments) or m/s².
    pub accel_unit: f64,
    /// For the forward, right and down axes: the file axis and its sign.
    pub axes: [SignedAxis; 3],
    /// The IMU's roll, pitch, yaw in the vehicle's forward-right-down axes,
    /// rad (after `axes`); `None`: aligned.
    pub mounting: Option<Euler>,
}

impl Default for ImuFormat {
    fn default() -> Self {
        Self {
            delimiter: Delimiter::Whitespace,
            header_lines: 0,
            time: 0,
            week: None,
            gyro: [1, 2, 3],
            accel: [4, 5, 6],
            odometer: Some(7),
            time_base: TimeBase::SecondsOfWeek,
            measures: Measures::Increments,
            gyro_unit: 1.0,
            accel_unit: 1.0,
            axes: [(0, 1.0), (1, 1.0), (2, 1.0)],
            mounting: None,
        }
    }
}

impl ImuFormat {
    /// Whether this is the GINS format (read by the fixed-layout reader).
    pub fn is_gins(&self) -> bool {
        *self == Self::default()
    }

    /// The columns to read, in the order [`Sample::from_values`] takes them.
    pub(crate) fn selection(&self) -> Selection {
        let unit = |m: Measures, rate: &str, inc: &str| match m {
            Measures::Rates => rate.to_owned(),
            Measures::Increments => inc.to_owned(),
        };
        let g = unit(self.measures, "gyro rate", "Δθ");
        let a = unit(self.measures, "specific force", "Δv");
        let mut columns = vec![(self.time, "time".to_owned())];
        if let Some(w) = self.week {
            columns.push((w, "GPS week".to_owned()));
        }
        for (k, c) in self.gyro.iter().enumerate() {
            columns.push((*c, format!("{g} {}", ["x", "y", "z"][k])));
        }
        for (k, c) in self.accel.iter().enumerate() {
            columns.push((*c, format!("{a} {}", ["x", "y", "z"][k])));
        }
        if let Some(o) = self.odometer {
            columns.push((o, "odometer speed, m/s".to_owned()));
        }
        Selection {
            delimiter: self.delimiter,
            header_lines: self.header_lines,
            columns,
        }
    }

    /// The time of `raw` (the time column's value, and the week's) as
    /// seconds of GPS week `week0`, continuing past its end.
    pub fn time_of(&self, raw: f64, week: Option<f64>, week0: u32) -> f64 {
        let w0 = f64::from(week0) * WEEK_SECONDS;
        match self.time_base {
            TimeBase::SecondsOfWeek => raw,
            TimeBase::WeekSeconds => week.unwrap_or(0.0) * WEEK_SECONDS + raw - w0,
            TimeBase::Unix { leap_seconds } => raw - GPS_EPOCH_UNIX + leap_seconds - w0,
        }
    }

    /// The rotation from the file's axes to the vehicle's
    /// forward-right-down axes, with the units applied by the caller.
    pub fn to_vehicle(&self) -> Matrix3<f64> {
        let mut m = Matrix3::zeros();
        for (row, (axis, sign)) in self.axes.iter().enumerate() {
            m[(row, *axis)] = *sign;
        }
        match self.mounting {
            Some(e) => e.to_dcm() * m,
            None => m,
        }
    }
}

/// One sample of a configured IMU file in SI units and vehicle axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sample {
    pub gyro: Vector3<f64>,
    pub accel: Vector3<f64>,
    pub odometer: Option<f64>,
}

impl Sample {
    /// The sample of the selected `values` (in [`ImuFormat::selection`]
    /// order), rotated by `to_vehicle`.
    pub(crate) fn from_values(
        format: &ImuFormat,
        values: &[f64],
        to_vehicle: &Matrix3<f64>,
    ) -> Self {
        let k = 1 + usize::from(format.week.is_some());
        let gyro = Vector3::new(values[k], values[k + 1], values[k + 2]) * format.gyro_unit;
        let accel = Vector3::new(values[k + 3], values[k + 4], values[k + 5]) * format.accel_unit;
        Self {
            gyro: to_vehicle * gyro,
            accel: to_vehicle * accel,
            odometer: format.odometer.map(|_| values[k + 6]),
        }
    }
}

/// A signed axis name (`x`, `-y`, `+z`) as `(index, sign)`.
///
/// ```
/// use kestrel_io::gins::imu_format::signed_axis;
/// assert_eq!(signed_axis("-z"), Some((2, -1.0)));
/// assert_eq!(signed_axis("y"), Some((1, 1.0)));
/// assert_eq!(signed_axis("w"), None);
/// ```
pub fn signed_axis(name: &str) -> Option<SignedAxis> {
    let (sign, axis) = match name.trim().strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, name.trim().trim_start_matches('+')),
    };
    let index = ["x", "y", "z"].iter().position(|a| *a == axis)?;
    Some((index, sign))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_forward_up_axes_map_to_forward_right_down() {
        let f = ImuFormat {
            axes: [(1, 1.0), (0, 1.0), (2, -1.0)],
            ..ImuFormat::default()
        };
        // x right, y forward, z up: a vector along file y is forward.
        let v = f.to_vehicle() * Vector3::new(0.0, 1.0, 0.0);
        assert_eq!(v, Vector3::new(1.0, 0.0, 0.0));
        // Gravity's reaction (+z up at rest) is −down.
        let v = f.to_vehicle() * Vector3::new(0.0, 0.0, 9.8);
        assert_eq!(v, Vector3::new(0.0, 0.0, -9.8));
        // The rotation is proper (no mirror).
        assert!((f.to_vehicle().determinant() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn time_bases_give_seconds_of_the_initial_week() {
        let f = ImuFormat::default();
        assert_eq!(f.time_of(100.0, None, 2300), 100.0);
        let w = ImuFormat {
            time_base: TimeBase::WeekSeconds,
            ..ImuFormat::default()
        };
        assert_eq!(w.time_of(5.0, Some(2301.0), 2300), WEEK_SECONDS + 5.0);
        let u = ImuFormat {
            time_base: TimeBase::Unix { leap_seconds: 18.0 },
            ..ImuFormat::default()
        };
        // 2024-01-01 00:00:00 UTC is GPS week 2295, 86 418 s (Monday + 18 s).
        assert_eq!(u.time_of(1_704_067_200.0, None, 2295), 86_418.0);
    }
}
