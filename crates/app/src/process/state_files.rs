//! The filter's own view per covariance epoch: the IMU error estimates and
//! the standard deviation of every error state, as text and CSV.
//!
//! Rows are written at the covariance epochs (the IMU samples where the
//! covariance was propagated or updated; 10 Hz with the default 0.1 s
//! interval): between them σ and the estimates do not change. With an
//! output interval, at most one row per interval.
//!
//! `NAME_imu_errors.txt` / `.csv` (KF-GINS users know the layout of its
//! `IMU_ERROR.txt`; accelerometer biases here are in mg, not mGal): time
//! (s of week), gyro bias x y z (°/h), accelerometer bias x y z (mg), gyro
//! scale factor x y z (ppm), accelerometer scale factor x y z (ppm), and the
//! odometer scale factor (ppm) with the odometer model. These are the
//! corrections removed from the readings: the configured initial values
//! plus everything fed back; body axes.
//!
//! `NAME_std.txt` / `.csv`: time, then σ of each error state in the
//! state's order: attitude north east down (°), velocity N E D (m/s),
//! position N E D (m), then the sensor states of the error model (°/h, mg,
//! ppm) — the CSV header names each column.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use kestrel::nav::engine::SensorCorrections;
use kestrel::nav::measurement::ErrorLayout;

use super::evaluation::Thinned;
use super::schedule::Schedule;
use super::sink::{create_output, keep_or_discard};
use super::traces::StateRow;
use crate::Error;
use kestrel::nav::imu_spec::G0;

/// One table written twice: space-separated text with a `#` header, and
/// CSV.
struct Table {
    text: (PathBuf, BufWriter<File>),
    csv: (PathBuf, BufWriter<File>),
    line: String,
    csv_line: Vec<u8>,
}

impl Table {
    fn create(out: &Path, name: &str, columns: &[String]) -> Result<Self, Error> {
        let open = |ext: &str| -> Result<(PathBuf, BufWriter<File>), Error> {
            let path = out.join(format!("{name}.{ext}"));
            let file = create_output(&path)?;
            Ok((path, BufWriter::with_capacity(1 << 16, file)))
        };
        let mut t = Self {
            text: open("txt")?,
            csv: open("csv")?,
            line: String::with_capacity(512),
            csv_line: Vec::with_capacity(512),
        };
        let (p, w) = &mut t.text;
        writeln!(w, "# {}", columns.join(" ")).map_err(|e| Error::io(p, e))?;
        let (p, w) = &mut t.csv;
        writeln!(w, "{}", columns.join(",")).map_err(|e| Error::io(p, e))?;
        Ok(t)
    }

    /// Writes `values` as one row (Ryū digits, as the result file).
    fn row(&mut self, values: impl IntoIterator<Item = f64>) -> Result<(), Error> {
        self.line.clear();
        let mut buffer = ryu::Buffer::new();
        for (i, v) in values.into_iter().enumerate() {
            if i > 0 {
                self.line.push(' ');
            }
            self.line.push_str(buffer.format(v));
        }
        self.line.push('\n');
        let (p, w) = &mut self.text;
        w.write_all(self.line.as_bytes())
            .map_err(|e| Error::io(p, e))?;
        // The same text comma-separated (numbers have neither).
        self.csv_line.clear();
        self.csv_line
            .extend(self.line.bytes().map(|b| if b == b' ' { b',' } else { b }));
        let (p, w) = &mut self.csv;
        w.write_all(&self.csv_line).map_err(|e| Error::io(p, e))
    }

    fn finish(mut self, ok: bool) -> Result<Vec<PathBuf>, Error> {
        let mut flushed = Ok(());
        for (p, w) in [&mut self.text, &mut self.csv] {
            if let Err(e) = w.flush() {
                flushed = Err(Error::io(p, e));
            }
        }
        let ok = ok && flushed.is_ok();
        for (p, _) in [&self.text, &self.csv] {
            keep_or_discard(p, ok)?;
        }
        flushed.map(|()| vec![self.text.0, self.csv.0])
    }
}

/// The IMU error estimates and σ files of one solution.
pub(crate) struct StateFiles {
    /// The rows written, thinned for the figures.
    pub rows: Thinned<StateRow>,
    /// The column names (without the time).
    pub estimate_names: Vec<String>,
    pub sigma_names: Vec<String>,
    errors: Table,
    std: Table,
    /// Factors from SI to the σ columns' units.
    scales: Vec<f64>,
    odometer: bool,
    interval: f64,
    schedule: Schedule,
}

/// Factors to the output units.
const DEG_PER_H: f64 = 180.0 / std::f64::consts::PI * 3600.0;
const MG: f64 = 1e3 / G0;
const PPM: f64 = 1e6;

impl StateFiles {
    /// `NAME_imu_errors.*` and `NAME_std.*` in `out` for layout `L`, a row
    /// at most every `interval` s (0: every epoch).
    pub(crate) fn create<const N: usize, L: ErrorLayout<N>>(
        out: &Path,
        name: &str,
        interval: f64,
    ) -> Result<Self, Error> {
        let odometer = L::ODOMETER_SCALE.is_some();
        let mut columns = vec!["time_s".to_owned()];
        for (what, unit) in [
            ("gyro_bias", "deg_per_h"),
            ("accel_bias", "mg"),
            ("gyro_scale", "ppm"),
            ("accel_scale", "ppm"),
        ] {
            columns.extend(["x", "y", "z"].map(|a| format!("{what}_{a}_{unit}")));
        }
        if odometer {
            columns.push("odometer_scale_ppm".to_owned());
        }
        let errors = Table::create(out, &format!("{name}_imu_errors"), &columns)?;
        let states = state_columns::<N, L>();
        let mut std_columns = vec!["time_s".to_owned()];
        std_columns.extend(states.iter().map(|(n, _)| n.clone()));
        let std = Table::create(out, &format!("{name}_std"), &std_columns)?;
        Ok(Self {
            rows: Thinned::default(),
            estimate_names: columns[1..].to_vec(),
            sigma_names: std_columns[1..].to_vec(),
            errors,
            std,
            scales: states.into_iter().map(|(_, s)| s).collect(),
            odometer,
            interval,
            schedule: Schedule::new(),
        })
    }

    /// Whether a row is due at the epoch at `t` (the output interval).
    pub(crate) fn due(&mut self, t: f64) -> bool {
        self.interval == 0.0 || self.schedule.due(t, 1.0 / self.interval)
    }

    /// One row: the corrections in use and the σ of every state (SI).
    pub(crate) fn row<I>(&mut self, t: f64, c: &SensorCorrections, sigma: I) -> Result<(), Error>
    where
        I: IntoIterator<Item = f64>,
        I::IntoIter: Clone,
    {
        let i = &c.imu;
        let estimates = i
            .gyro
            .iter()
            .map(|v| v * DEG_PER_H)
            .chain(i.accel.iter().map(|v| v * MG))
            .chain(i.gyro_scale.iter().map(|v| v * PPM))
            .chain(i.accel_scale.iter().map(|v| v * PPM))
            .chain(self.odometer.then_some(c.odometer_scale * PPM));
        let sigmas = sigma.into_iter().zip(&self.scales).map(|(s, k)| s * k);
        // Rows for the figures are built only when the thinning keeps them.
        if self.rows.wants() {
            self.rows.push(StateRow {
                time: t,
                estimates: estimates.clone().collect(),
                sigmas: sigmas.clone().collect(),
            });
        } else {
            self.rows.skip();
        }
        self.errors.row([t].into_iter().chain(estimates))?;
        self.std.row([t].into_iter().chain(sigmas))
    }

    /// Flushes; puts the files in place when `ok`, else removes them.
    pub(crate) fn finish(self, ok: bool) -> Result<Vec<PathBuf>, Error> {
        let mut files = self.errors.finish(ok)?;
        files.extend(self.std.finish(ok)?);
        Ok(files)
    }
}

/// The σ columns of an `N`-state error layout `L`: name with unit, and the
/// factor from the state's SI unit.
pub(crate) fn state_columns<const N: usize, L: ErrorLayout<N>>() -> Vec<(String, f64)> {
    let deg = 180.0 / std::f64::consts::PI;
    let mut columns: Vec<(String, f64)> = (0..N).map(|i| (format!("state{i}"), 1.0)).collect();
    for (i, a) in ["n", "e", "d"].iter().enumerate() {
        columns[i] = (format!("att_{a}_deg"), deg);
        columns[3 + i] = (format!("vel_{a}_mps"), 1.0);
        columns[6 + i] = (format!("pos_{a}_m"), 1.0);
    }
    let groups = [
        (L::GYRO_BIAS, "gyro", "deg_per_h", DEG_PER_H),
        (L::ACCEL_BIAS, "accel", "mg", MG),
    ];
    for (blocks, sensor, unit, scale) in groups {
        for (k, &first) in blocks.iter().enumerate() {
            let kind = if k == 0 { "bias" } else { "markov" };
            for (i, a) in ["x", "y", "z"].iter().enumerate() {
                columns[first + i] = (format!("{sensor}_{kind}_{a}_{unit}"), scale);
            }
        }
    }
    if let Some(i) = L::ODOMETER_SCALE {
        columns[i] = ("odometer_scale_ppm".to_owned(), PPM);
    }
    for (first, sensor) in [(L::GYRO_SCALE, "gyro"), (L::ACCEL_SCALE, "accel")] {
        if let Some(first) = first {
            for (i, a) in ["x", "y", "z"].iter().enumerate() {
                columns[first + i] = (format!("{sensor}_scale_{a}_ppm"), PPM);
            }
        }
    }
    columns
}
