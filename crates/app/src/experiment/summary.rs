//! The summary of a run: RMS errors per axis.

use kestrel::nalgebra::Vector3;

use super::health::HealthSummary;
use super::options::PositionAxes;
use super::record::EpochRecord;

/// RMS errors of a run over its aiding epochs (from
/// [`RunOptions::rms_from`](super::RunOptions::rms_from) on), and counts.
///
/// ```
/// use kestrel_app::experiment::{run, RunOptions};
/// let s = kestrel_app::scenario::by_name("000").unwrap();
/// let r = run(&s, &s.filters[0], 0, &RunOptions::default().with_duration(5.0)).unwrap();
/// assert_eq!(r.summary.epochs, 50); // 10 Hz GNSS
/// assert!(r.summary.rms_position.norm() < 20.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSummary {
    /// The filter's label.
    pub filter: &'static str,
    /// Aiding epochs (updates attempted).
    pub epochs: usize,
    /// Epochs counted in the RMS.
    pub rms_epochs: usize,
    /// Updates rejected by an adapter.
    pub rejected: usize,
    /// The axes of `rms_position` and `final_position`.
    pub axes: PositionAxes,
    /// Position RMS per axis of `axes`, m.
    pub rms_position: Vector3<f64>,
    /// Velocity RMS, north, east, down, m/s.
    pub rms_velocity: Vector3<f64>,
    /// Attitude RMS, north, east, down, rad.
    pub rms_attitude: Vector3<f64>,
    /// Largest 3-D position error over all epochs, m.
    pub max_position: f64,
    /// Position error at the last epoch, in `axes`, m.
    pub final_position: Vector3<f64>,
    /// Time of the last IMU sample processed, s.
    pub end_time: f64,
    /// Fingerprint of the sensor data the filter consumed (equal for runs
    /// on identical data).
    pub data_digest: u64,
    /// What the health monitor found ([`Health`](super::Health)).
    pub health: HealthSummary,
    /// The odometer scale-factor estimate at the last odometer update
    /// (16-state filters on simulated data; `None` otherwise).
    pub odometer_scale: Option<ScaleEstimate>,
}

/// A filter's odometer scale-factor estimate against the truth.
///
/// ```
/// use kestrel_app::experiment::ScaleEstimate;
/// let s = ScaleEstimate { estimate: 0.0052, sigma: 4e-4, truth: 0.005 };
/// assert!((s.z() - 0.5).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaleEstimate {
    /// The estimate `k̂` (ratio).
    pub estimate: f64,
    /// Its σ from the filter's covariance.
    pub sigma: f64,
    /// The simulated odometer's scale-factor error (constant plus Markov).
    pub truth: f64,
}

impl ScaleEstimate {
    /// The normalised error `(k̂ − k)/σ`.
    pub fn z(&self) -> f64 {
        (self.estimate - self.truth) / self.sigma
    }
}

impl RunSummary {
    /// The horizontal position RMS, m.
    ///
    /// ```
    /// # use kestrel_app::experiment::{run, RunOptions};
    /// # let s = kestrel_app::scenario::by_name("000").unwrap();
    /// # let r = run(&s, &s.filters[0], 0, &RunOptions::default().with_duration(3.0)).unwrap();
    /// let h = r.summary.horizontal_rms();
    /// assert!(h <= r.summary.rms_position.norm());
    /// ```
    pub fn horizontal_rms(&self) -> f64 {
        // Both axis orders put the horizontal axes first.
        self.rms_position.xy().norm()
    }

    /// The 3-D velocity RMS, m/s.
    ///
    /// ```
    /// # use kestrel_app::experiment::{run, RunOptions};
    /// # let s = kestrel_app::scenario::by_name("000").unwrap();
    /// # let r = run(&s, &s.filters[0], 0, &RunOptions::default().with_duration(3.0)).unwrap();
    /// assert_eq!(r.summary.velocity_rms(), r.summary.rms_velocity.norm());
    /// ```
    pub fn velocity_rms(&self) -> f64 {
        self.rms_velocity.norm()
    }
}

/// Sums of squares while the run goes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Accumulator {
    axes: PositionAxes,
    from: f64,
    epochs: usize,
    counted: usize,
    rejected: usize,
    pos: Vector3<f64>,
    vel: Vector3<f64>,
    att: Vector3<f64>,
    max_position: f64,
    last: Vector3<f64>,
}

impl Accumulator {
    pub(crate) fn new(axes: PositionAxes, from: f64) -> Self {
        Self {
            axes,
            from,
            epochs: 0,
            counted: 0,
            rejected: 0,
            pos: Vector3::zeros(),
            vel: Vector3::zeros(),
            att: Vector3::zeros(),
            max_position: 0.0,
            last: Vector3::zeros(),
        }
    }

    pub(crate) fn add(&mut self, r: &EpochRecord) {
        self.epochs += 1;
        self.rejected += r.adaptation.rejected as usize;
        self.max_position = self.max_position.max(r.position.norm());
        self.last = self.axes.from_ned(&r.position);
        if r.time >= self.from {
            self.counted += 1;
            self.pos += self.last.component_mul(&self.last);
            self.vel += r.velocity.component_mul(&r.velocity);
            self.att += r.attitude.component_mul(&r.attitude);
        }
    }

    pub(crate) fn finish(&self, filter: &'static str, end_time: f64, digest: u64) -> RunSummary {
        let n = self.counted.max(1) as f64;
        let rms = |s: &Vector3<f64>| (s / n).map(f64::sqrt);
        RunSummary {
            filter,
            epochs: self.epochs,
            rms_epochs: self.counted,
            rejected: self.rejected,
            axes: self.axes,
            rms_position: rms(&self.pos),
            rms_velocity: rms(&self.vel),
            rms_attitude: rms(&self.att),
            max_position: self.max_position,
            final_position: self.last,
            end_time,
            data_digest: digest,
            health: HealthSummary::default(),
            odometer_scale: None,
        }
    }
}
