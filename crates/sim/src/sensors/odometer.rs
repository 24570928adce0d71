//! An odometer (wheel speed sensor) with scale errors and faults.

use nalgebra::Vector3;

use super::markov::GaussMarkov;
use super::rng::{normal, sensor_rng, uniform, SensorStream, SimRng};
use super::schedule::Schedule;
use super::simulated::Simulated;
use super::window::TimeWindow;
use crate::Motion;
use kestrel_nav::earth::Ellipsoid;
use kestrel_nav::measurement::OdometerReading;
use kestrel_nav::state::NavState;

/// How a fault changes the reading inside its window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OdometerFaultKind {
    /// Reads `factor` times the true speed: wheel spin (`factor ≫ 1`), or
    /// a skid with locked wheels (`factor ≪ 1`).
    Factor(f64),
    /// Rolling with slipping: each reading is the true speed times a factor
    /// drawn uniformly in `[min, max]` (e.g. 1–1.3 on a slippery slope).
    RandomFactor {
        /// Smallest factor.
        min: f64,
        /// Largest factor.
        max: f64,
    },
    /// Adds `offset` m/s.
    Offset(f64),
}

/// A fault episode. Side-slip (the vehicle moving sideways, which a wheel
/// sensor cannot see) is not a sensor fault but motion: make it with
/// [`Segment::SideSlip`](crate::Segment::SideSlip); the odometer
/// measures only the vehicle-forward component of the true velocity.
///
/// ```
/// use kestrel_sim::{OdometerFault, OdometerFaultKind, TimeWindow};
/// let f = OdometerFault::wheel_spin(TimeWindow::starting(600.0, 3.0), 1.5);
/// assert_eq!(f.kind, OdometerFaultKind::Factor(1.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometerFault {
    /// When it happens.
    pub window: TimeWindow,
    /// What happens.
    pub kind: OdometerFaultKind,
}

impl OdometerFault {
    /// Wheel spin: the odometer reads `factor` (> 1) times the true speed.
    ///
    /// ```
    /// let f = kestrel_sim::OdometerFault::wheel_spin(kestrel_sim::TimeWindow::new(0.0, 1.0), 2.0);
    /// assert_eq!(f.window.end, 1.0);
    /// ```
    pub fn wheel_spin(window: TimeWindow, factor: f64) -> Self {
        Self {
            window,
            kind: OdometerFaultKind::Factor(factor),
        }
    }

    /// Skid: the odometer reads `factor` (< 1) times the true speed.
    ///
    /// ```
    /// use kestrel_sim::{OdometerFault, OdometerFaultKind, TimeWindow};
    /// let f = OdometerFault::skid(TimeWindow::new(0.0, 1.0), 0.2);
    /// assert_eq!(f.kind, OdometerFaultKind::Factor(0.2));
    /// ```
    pub fn skid(window: TimeWindow, factor: f64) -> Self {
        Self {
            window,
            kind: OdometerFaultKind::Factor(factor),
        }
    }

    /// Rolling with slipping: factors uniform in `[min, max]`.
    ///
    /// ```
    /// use kestrel_sim::{OdometerFault, OdometerFaultKind, TimeWindow};
    /// let f = OdometerFault::roll_slip(TimeWindow::new(2000.0, 2100.0), 1.0, 1.3);
    /// assert!(matches!(f.kind, OdometerFaultKind::RandomFactor { .. }));
    /// ```
    pub fn roll_slip(window: TimeWindow, min: f64, max: f64) -> Self {
        Self {
            window,
            kind: OdometerFaultKind::RandomFactor { min, max },
        }
    }
}

/// An odometer: the speed of the wheel point along the vehicle's forward
/// axis, at `rate` Hz,
///
/// ```text
/// speed = (1 + k + m(t)) · fault(e₁ᵀ C_n^v (v^n + C_b^n (ω_eb^b × l))) + n
/// ```
///
/// `C_n^v` is the vehicle attitude of the trajectory (the IMU body `b` is
/// mounted on the vehicle by the trajectory's
/// [`mounting`](crate::TrajectorySpec::mounting)), `l` the lever arm
/// from the IMU to the wheel in body axes, `ω_eb^b` the body rate over the
/// Earth, `k` the constant scale error, `m` a first-order Gauss–Markov
/// scale error, `n` white noise.
///
/// ```
/// let c = kestrel_sim::OdometerConfig::new(10.0);
/// assert_eq!((c.rate, c.scale_error), (10.0, 0.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct OdometerConfig {
    /// Reading rate, Hz; readings fall at multiples of `1/rate` s (not at 0).
    pub rate: f64,
    /// Constant scale-factor error, ratio.
    pub scale_error: f64,
    /// Gauss–Markov scale-factor error steady-state σ, ratio.
    pub scale_markov_sigma: f64,
    /// Gauss–Markov correlation time, s.
    pub scale_markov_tau: f64,
    /// White noise σ per reading, m/s.
    pub noise_std: f64,
    /// Position of the measuring wheel relative to the IMU, body axes, m.
    /// The trajectory moves the IMU point along the vehicle's forward axis,
    /// so the non-holonomic constraint holds there and at points beside or
    /// below it; a wheel ahead of or behind the IMU slides sideways by
    /// `ω × l` in turns (its reading has the forward part exactly).
    pub lever_arm: Vector3<f64>,
    /// Fault episodes (the first matching one applies).
    pub faults: Vec<OdometerFault>,
}

impl OdometerConfig {
    /// A perfect odometer read at `rate` Hz.
    ///
    /// ```
    /// assert!(kestrel_sim::OdometerConfig::new(1.0).faults.is_empty());
    /// ```
    pub fn new(rate: f64) -> Self {
        Self {
            rate,
            scale_error: 0.0,
            scale_markov_sigma: 0.0,
            scale_markov_tau: f64::INFINITY,
            noise_std: 0.0,
            lever_arm: Vector3::zeros(),
            faults: Vec::new(),
        }
    }
}

/// Samples an [`OdometerConfig`] along a trajectory; call
/// [`sample`](Self::sample) at every truth epoch with the stream's
/// [`motion`](crate::ImuStream::motion). White noise and the Markov
/// scale error use [`SensorStream::Odometer`], fault draws
/// [`SensorStream::OdometerFaults`].
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic};
/// use kestrel_sim::{OdometerConfig, OdometerSensor, Segment, Trajectory, TrajectorySpec, Vehicle};
/// // Driving east at 20 m/s with the IMU turned by 0.2° pitch, −0.3° yaw.
/// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::from_degrees(34.0, 120.0, 200.0),
///     90f64.to_radians(), 20.0)
///     .then(Segment::Cruise { duration: 1.0 })
///     .with_mounting(Euler::from_degrees(0.0, 0.2, -0.3));
/// let mut stream = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(100.0).unwrap();
/// let mut c = OdometerConfig::new(1.0);
/// c.scale_error = 0.005;
/// let mut odo = OdometerSensor::new(c, Ellipsoid::wgs84(), 3);
/// let (truth, _) = stream.nth(99).unwrap();
/// let r = odo.sample(&truth, stream.motion()).unwrap();
/// // The vehicle's forward speed, 0.5 % fast.
/// assert!((r.value.speed - 20.1).abs() < 1e-9 && !r.faulty);
/// ```
#[derive(Clone, Debug)]
pub struct OdometerSensor {
    config: OdometerConfig,
    earth: Ellipsoid,
    rng: SimRng,
    fault_rng: SimRng,
    markov: GaussMarkov,
    schedule: Schedule,
    last_time: f64,
}

impl OdometerSensor {
    /// An odometer on `earth` with noise from `seed`.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid};
    /// use kestrel_sim::{OdometerConfig, OdometerSensor};
    /// let o = OdometerSensor::new(OdometerConfig::new(10.0), Ellipsoid::wgs84(), 0);
    /// assert_eq!(o.scale_markov(), 0.0);
    /// ```
    pub fn new(config: OdometerConfig, earth: Ellipsoid, seed: u64) -> Self {
        let mut rng = sensor_rng(seed, SensorStream::Odometer);
        let markov = GaussMarkov::new(config.scale_markov_sigma, config.scale_markov_tau, &mut rng);
        Self {
            config,
            earth,
            rng,
            fault_rng: sensor_rng(seed, SensorStream::OdometerFaults),
            markov,
            schedule: Schedule::new(),
            last_time: 0.0,
        }
    }

    /// The configuration.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid};
    /// use kestrel_sim::{OdometerConfig, OdometerSensor};
    /// assert_eq!(OdometerSensor::new(OdometerConfig::new(5.0), Ellipsoid::wgs84(), 0).config().rate, 5.0);
    /// ```
    pub fn config(&self) -> &OdometerConfig {
        &self.config
    }

    /// The current Gauss–Markov scale error, ratio.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid};
    /// use kestrel_sim::{OdometerConfig, OdometerSensor};
    /// let mut c = OdometerConfig::new(5.0);
    /// c.scale_markov_sigma = 5e-4;
    /// c.scale_markov_tau = 3600.0;
    /// assert!(OdometerSensor::new(c, Ellipsoid::wgs84(), 0).scale_markov() != 0.0);
    /// ```
    pub fn scale_markov(&self) -> f64 {
        self.markov.value()
    }

    /// The error-free speed of the wheel along the vehicle's forward axis,
    /// m/s, for the truth `truth` (position, velocity) and the `motion` at
    /// the same instant (vehicle axes, body attitude and rate).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_sim::{OdometerConfig, OdometerSensor, Segment, Trajectory, TrajectorySpec,
    ///     TurnRate, Vehicle};
    /// // Turning right at 0.1 rad/s at 5 m/s: a wheel 1 m to the left rolls
    /// // at 5.1 m/s.
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 5.0)
    ///     .then(Segment::Turn { turn: TurnRate::Rate(0.1), angle: 1.0 });
    /// let t = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    /// let mut c = OdometerConfig::new(1.0);
    /// c.lever_arm = Vector3::new(0.0, -1.0, 0.0);
    /// let o = OdometerSensor::new(c, Ellipsoid::wgs84(), 0);
    /// let m = t.motion_at(5.0);
    /// let truth = NavState { vel: m.vel, ..t.initial_state() };
    /// assert!((o.true_speed(&truth, &m) - 5.1).abs() < 1e-5);
    /// ```
    pub fn true_speed(&self, truth: &NavState, motion: &Motion) -> f64 {
        let mut v = truth.vel;
        let l = self.config.lever_arm;
        if l != Vector3::zeros() {
            let c_bn = motion.c_bn;
            let w_en = self.earth.transport_rate_ned(&truth.pos, &truth.vel);
            let w_eb = motion.omega_nb + c_bn.transpose() * w_en;
            v += c_bn * w_eb.cross(&l);
        }
        motion.c_vn.column(0).dot(&v)
    }

    /// The reading due at `truth.time`, if any, for the truth `truth` and
    /// the `motion` at the same instant (see [`true_speed`](Self::true_speed)),
    /// flagged faulty inside a fault window.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{OdometerConfig, OdometerFault, OdometerSensor, Segment, TimeWindow,
    ///     Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 8.0)
    ///     .then(Segment::Cruise { duration: 3.0 });
    /// let mut stream = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(10.0).unwrap();
    /// let mut c = OdometerConfig::new(1.0);
    /// c.faults.push(OdometerFault::skid(TimeWindow::new(2.0, 3.0), 0.25));
    /// let mut o = OdometerSensor::new(c, Ellipsoid::wgs84(), 0);
    /// let mut v = vec![];
    /// while let Some((truth, _)) = stream.next() {
    ///     v.extend(o.sample(&truth, stream.motion()).map(|r| (r.value.speed, r.faulty)));
    /// }
    /// assert_eq!(v, vec![(8.0, false), (2.0, true), (8.0, false)]);
    /// ```
    pub fn sample(
        &mut self,
        truth: &NavState,
        motion: &Motion,
    ) -> Option<Simulated<OdometerReading>> {
        let t = truth.time;
        if !self.schedule.due(t, self.config.rate) {
            return None;
        }
        let dt = (t - self.last_time).max(0.0);
        self.last_time = t;
        self.markov.step(dt, &mut self.rng);
        let noise = self.config.noise_std * normal(&mut self.rng);

        let true_speed = self.true_speed(truth, motion);
        let scale = 1.0 + self.config.scale_error + self.markov.value();
        let fault = self.config.faults.iter().find(|f| f.window.contains(t));
        let seen = match fault.map(|f| f.kind) {
            None => true_speed,
            Some(OdometerFaultKind::Factor(k)) => k * true_speed,
            Some(OdometerFaultKind::RandomFactor { min, max }) => {
                uniform(&mut self.fault_rng, min, max) * true_speed
            }
            Some(OdometerFaultKind::Offset(o)) => true_speed + o,
        };
        Some(Simulated {
            value: OdometerReading::new(t, scale * seen + noise),
            faulty: fault.is_some(),
        })
    }
}
