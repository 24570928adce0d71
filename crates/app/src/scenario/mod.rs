//! The papers' experiments as data.
//!
//! A [`Scenario`] holds everything a run needs: the trajectory, the true
//! sensor errors and faults, the filter's initial errors, P0, R, its
//! assumed IMU model and the filters the paper compares. Every field is
//! public plain data, so scenarios can also be written by hand (or read
//! from a file by a front end). The five built-in ones reproduce papers
//! 000–004; each one's documentation lists what the paper states and what
//! was chosen where it is silent.

mod aircraft_outliers;
mod fast_aircraft;
mod filters;
mod odometer_faults;
mod setup;
mod study;
mod uav_manoeuvres;
mod urban_multipath;

use kestrel::nalgebra::Vector3;

pub use aircraft_outliers::scenario_000;
pub use fast_aircraft::scenario_001;
pub use filters::{FadeBlock, FilterKind, Param, ParamValue};
pub use odometer_faults::scenario_003;
pub use setup::{
    ErrorModelKind, FilterSetup, InitialErrors, InitialUncertainty, MeasurementKind,
    MeasurementNoise,
};
pub use study::{
    fault_free, tuned, variants, Variant, PROTECTED_000, STUDY_SEEDS_FROM, TEST_SEEDS_FROM,
    TUNED_003_THRESHOLD, TUNING_SEEDS,
};
pub use uav_manoeuvres::scenario_004;
pub use urban_multipath::scenario_002;

use kestrel::nav::attitude::correct_attitude;
use kestrel::nav::earth::Ellipsoid;
use kestrel::nav::state::NavState;
use kestrel::sim::{
    AttitudeConfig, AttitudeSensor, GnssConfig, GnssSensor, ImuErrors, ImuSensor, OdometerConfig,
    OdometerSensor, Trajectory, TrajectoryError, TrajectorySpec,
};

/// One simulation experiment.
///
/// ```
/// let s = kestrel_app::scenario::by_name("003").unwrap();
/// assert_eq!(s.trajectory().unwrap().duration(), 3600.0);
/// assert!(s.odometer.is_some() && s.gnss.is_none());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Short name ("000" … "004" for the built-ins).
    pub name: String,
    /// One line saying what it is.
    pub description: String,
    /// Earth model of the truth, the sensors and the navigation.
    pub earth: Ellipsoid,
    /// The motion.
    pub trajectory: TrajectorySpec,
    /// IMU sampling rate, Hz.
    pub imu_rate: f64,
    /// The simulated IMU's true errors.
    pub imu_errors: ImuErrors,
    /// GNSS receiver, if any.
    pub gnss: Option<GnssConfig>,
    /// Odometer, if any.
    pub odometer: Option<OdometerConfig>,
    /// Attitude reference, if any.
    pub attitude: Option<AttitudeConfig>,
    /// Errors of the navigation's initial state.
    pub initial_errors: InitialErrors,
    /// What the filters share (model, measurement, P0, R, assumed IMU).
    pub filter: FilterSetup,
    /// The filters the experiment compares, baseline first.
    pub filters: Vec<FilterKind>,
    /// Default random seed.
    pub seed: u64,
}

/// The five built-in scenarios, in order 000 … 004.
///
/// ```
/// let all = kestrel_app::scenario::builtin();
/// assert_eq!(all.map(|s| s.name), ["000", "001", "002", "003", "004"].map(String::from));
/// ```
pub fn builtin() -> [Scenario; 5] {
    [
        scenario_000(),
        scenario_001(),
        scenario_002(),
        scenario_003(),
        scenario_004(),
    ]
}

/// The built-in scenario called `name`.
///
/// ```
/// assert!(kestrel_app::scenario::by_name("002").is_some());
/// assert!(kestrel_app::scenario::by_name("999").is_none());
/// ```
pub fn by_name(name: &str) -> Option<Scenario> {
    builtin().into_iter().find(|s| s.name == name)
}

impl Scenario {
    /// The compiled trajectory.
    ///
    /// ```
    /// let t = kestrel_app::scenario::by_name("000").unwrap().trajectory().unwrap();
    /// assert_eq!(t.duration(), 500.0);
    /// ```
    pub fn trajectory(&self) -> Result<Trajectory, TrajectoryError> {
        Trajectory::new(&self.trajectory, self.earth)
    }

    /// The simulated IMU with noise from `seed`.
    ///
    /// ```
    /// let s = kestrel_app::scenario::by_name("002").unwrap();
    /// assert_eq!(s.imu_sensor(1).errors(), &s.imu_errors);
    /// ```
    pub fn imu_sensor(&self, seed: u64) -> ImuSensor {
        ImuSensor::new(self.imu_errors, seed)
    }

    /// The simulated GNSS receiver with noise from `seed`, if any.
    ///
    /// ```
    /// assert!(kestrel_app::scenario::by_name("003").unwrap().gnss_sensor(1).is_none());
    /// ```
    pub fn gnss_sensor(&self, seed: u64) -> Option<GnssSensor> {
        self.gnss
            .as_ref()
            .map(|c: &GnssConfig| GnssSensor::new(c.clone(), self.earth, seed))
    }

    /// The simulated odometer with noise from `seed`, if any.
    ///
    /// ```
    /// assert!(kestrel_app::scenario::by_name("003").unwrap().odometer_sensor(1).is_some());
    /// ```
    pub fn odometer_sensor(&self, seed: u64) -> Option<OdometerSensor> {
        self.odometer
            .as_ref()
            .map(|c: &OdometerConfig| OdometerSensor::new(c.clone(), self.earth, seed))
    }

    /// The simulated attitude reference with noise from `seed`, if any.
    ///
    /// ```
    /// assert!(kestrel_app::scenario::by_name("004").unwrap().attitude_sensor(1).is_some());
    /// ```
    pub fn attitude_sensor(&self, seed: u64) -> Option<AttitudeSensor> {
        self.attitude
            .map(|c: AttitudeConfig| AttitudeSensor::new(c, seed))
    }

    /// The navigation's initial state: `truth` with the scenario's initial
    /// errors applied.
    ///
    /// ```
    /// let s = kestrel_app::scenario::by_name("002").unwrap();
    /// let truth = s.trajectory().unwrap().initial_state();
    /// let init = s.initial_state(&truth);
    /// let d = s.earth.ned_offset(&truth.pos, &init.pos);
    /// assert!((d - s.initial_errors.position).norm() < 1e-6);
    /// ```
    pub fn initial_state(&self, truth: &NavState) -> NavState {
        let e = &self.initial_errors;
        NavState {
            time: truth.time,
            pos: self.earth.displace(&truth.pos, &e.position),
            vel: truth.vel + e.velocity,
            // (I − [φ×]) C is exp(−[φ×]) C to first order; use the exact
            // rotation so the error is exactly φ.
            att: correct_attitude(&truth.att, &(-e.attitude)),
        }
    }
}

/// `[a, b, c]` as a vector (keeps the scenario tables short).
fn v3(a: f64, b: f64, c: f64) -> Vector3<f64> {
    Vector3::new(a, b, c)
}
