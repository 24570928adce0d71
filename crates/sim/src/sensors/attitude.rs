//! An attitude reference (e.g. a multi-antenna GNSS heading / attitude
//! receiver) measuring the body attitude.

use nalgebra::Vector3;

use super::rng::{normal3, sensor_rng, SensorStream, SimRng};
use super::schedule::Schedule;
use kestrel_nav::attitude::correct_attitude;
use kestrel_nav::measurement::AttitudeFix;
use kestrel_nav::state::NavState;

/// Attitude measurements at `rate` Hz: the true `C_b^n` turned by a white
/// attitude error of σ `std` about north, east and down (rad), the error
/// definition of the filters (for a level body, about roll, pitch and yaw
/// errors when the roll and pitch σ are equal).
///
/// ```
/// use kestrel_nav::{nalgebra::Vector3};
/// use kestrel_sim::AttitudeConfig;
/// let c = AttitudeConfig::from_degrees(1.0, Vector3::new(0.1, 0.1, 0.3));
/// assert!((c.std.z - 0.3f64.to_radians()).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeConfig {
    /// Measurement rate, Hz; at multiples of `1/rate` s (not at 0).
    pub rate: f64,
    /// Noise σ of the attitude error about north, east, down, rad.
    pub std: Vector3<f64>,
}

impl AttitudeConfig {
    /// Rate (Hz) and σ about north, east, down in degrees.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::AttitudeConfig;
    /// assert_eq!(AttitudeConfig::from_degrees(2.0, Vector3::zeros()).rate, 2.0);
    /// ```
    pub fn from_degrees(rate: f64, std_deg: Vector3<f64>) -> Self {
        Self {
            rate,
            std: std_deg.map(f64::to_radians),
        }
    }
}

/// Samples an [`AttitudeConfig`]; call [`sample`](Self::sample) at every
/// truth epoch. Noise uses [`SensorStream::Attitude`].
///
/// ```
/// use kestrel_nav::{Euler, Geodetic, NavState, nalgebra::Vector3};
/// use kestrel_sim::{AttitudeConfig, AttitudeSensor};
/// let mut a = AttitudeSensor::new(AttitudeConfig::from_degrees(1.0, Vector3::zeros()), 0);
/// let s = NavState::new(1.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::new(0.1, 0.2, 0.3));
/// let fix = a.sample(&s).unwrap();
/// assert!(fix.att.angle_to(&s.att) < 1e-12 && fix.time == 1.0);
/// ```
#[derive(Clone, Debug)]
pub struct AttitudeSensor {
    config: AttitudeConfig,
    rng: SimRng,
    schedule: Schedule,
}

impl AttitudeSensor {
    /// A sensor with noise from `seed`.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{AttitudeConfig, AttitudeSensor};
    /// let a = AttitudeSensor::new(AttitudeConfig::from_degrees(1.0, Vector3::zeros()), 0);
    /// assert_eq!(a.config().rate, 1.0);
    /// ```
    pub fn new(config: AttitudeConfig, seed: u64) -> Self {
        Self {
            config,
            rng: sensor_rng(seed, SensorStream::Attitude),
            schedule: Schedule::new(),
        }
    }

    /// The configuration.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{AttitudeConfig, AttitudeSensor};
    /// let a = AttitudeSensor::new(AttitudeConfig::from_degrees(4.0, Vector3::zeros()), 0);
    /// assert_eq!(a.config().std, Vector3::zeros());
    /// ```
    pub fn config(&self) -> &AttitudeConfig {
        &self.config
    }

    /// The measurement due at `truth.time`, if any.
    ///
    /// ```
    /// use kestrel_nav::{Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_sim::{AttitudeConfig, AttitudeSensor};
    /// let mut a = AttitudeSensor::new(AttitudeConfig::from_degrees(1.0, Vector3::repeat(0.1)), 0);
    /// let s = NavState::new(0.5, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// assert!(a.sample(&s).is_none());
    /// ```
    pub fn sample(&mut self, truth: &NavState) -> Option<AttitudeFix> {
        let t = truth.time;
        if !self.schedule.due(t, self.config.rate) {
            return None;
        }
        // Attitude error φ: C_b^n(measured) = exp(−[φ×]) C_b^n(true).
        let phi = self.config.std.component_mul(&normal3(&mut self.rng));
        Some(AttitudeFix::new(
            t,
            correct_attitude(&truth.att, &(-phi)),
            self.config.std,
        ))
    }
}
