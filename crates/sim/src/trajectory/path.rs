//! A compiled trajectory: the exact motion as a function of time.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use super::compile::{compile, Channels};
use super::error::{TrajectoryError, TrajectoryErrorKind};
use super::motion::Motion;
use super::segment::Vehicle;
use super::spec::TrajectorySpec;
use super::stream::ImuStream;
use kestrel_nav::attitude::Euler;
use kestrel_nav::earth::Ellipsoid;
use kestrel_nav::geodetic::Geodetic;
use kestrel_nav::state::NavState;

/// A trajectory ready to be flown: closed-form speed, track, path angle
/// and side-slip profiles on an Earth model. It is immutable and `Sync`,
/// so Monte-Carlo runs can share it; [`stream`](Self::stream) produces the
/// truth and the exact IMU increments epoch by epoch.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Geodetic};
/// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
/// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::from_degrees(34.0, 120.0, 200.0), 0.0, 0.0)
///     .then(Segment::Accelerate { accel: 2.0, duration: 10.0 })
///     .then(Segment::Cruise { duration: 5.0 });
/// let traj = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
/// assert_eq!(traj.duration(), 15.0);
/// let (truth, imu) = traj.stream(100.0).unwrap().last().unwrap();
/// assert!((truth.vel.x - 20.0).abs() < 1e-12 && (imu.time - 15.0).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    pub(crate) earth: Ellipsoid,
    pub(crate) vehicle: Vehicle,
    pub(crate) start: Geodetic,
    pub(crate) mounting: Euler,
    /// `C_v^b` of the mounting.
    pub(crate) c_vb: Matrix3<f64>,
    /// `C_b^v` of the mounting as a quaternion.
    pub(crate) q_bv: UnitQuaternion<f64>,
    pub(crate) channels: Channels,
    /// Sorted times where some channel changes its closed form: the
    /// quadrature never integrates across one.
    pub(crate) breakpoints: Vec<f64>,
    pub(crate) duration: f64,
}

impl Trajectory {
    /// Compiles `spec` on the Earth model `earth` (whose gravity and rates
    /// the IMU increments include, so use the ellipsoid the mechanisation
    /// uses).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Aircraft, Geodetic::from_degrees(30.0, 120.0, 1e4), 0.0, 300.0);
    /// assert!(Trajectory::new(&spec, Ellipsoid::wgs84()).is_ok());
    /// ```
    pub fn new(spec: &TrajectorySpec, earth: Ellipsoid) -> Result<Self, TrajectoryError> {
        let (channels, duration) = compile(spec)?;
        let mut breakpoints: Vec<f64> = [
            &channels.speed,
            &channels.track,
            &channels.path,
            &channels.slip,
        ]
        .iter()
        .flat_map(|c| c.breakpoints())
        .filter(|&t| t > 0.0 && t < duration)
        .collect();
        breakpoints.sort_by(f64::total_cmp);
        breakpoints.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        Ok(Self {
            earth,
            vehicle: spec.vehicle,
            start: spec.start,
            mounting: spec.mounting,
            c_vb: spec.mounting.to_dcm(),
            q_bv: spec.mounting.to_quaternion().inverse(),
            channels,
            breakpoints,
            duration,
        })
    }

    /// Total duration, s.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 4.0)
    ///     .then(Segment::turn_radius_deg(10.0, 90.0)); // 0.4 rad/s, 1 s edges
    /// let t = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().duration();
    /// assert!((t - (std::f64::consts::FRAC_PI_2 / 0.4 + 1.0)).abs() < 1e-12);
    /// ```
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The Earth model.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0);
    /// let t = Trajectory::new(&spec, Ellipsoid::krasovsky()).unwrap();
    /// assert_eq!(t.earth().a, 6_378_245.0);
    /// ```
    pub fn earth(&self) -> &Ellipsoid {
        &self.earth
    }

    /// The vehicle kind.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0);
    /// assert_eq!(Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().vehicle(), Vehicle::Ground);
    /// ```
    pub fn vehicle(&self) -> Vehicle {
        self.vehicle
    }

    /// The IMU mounting: the vehicle frame in body axes (see
    /// [`TrajectorySpec::mounting`]).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .with_mounting(Euler::new(0.0, 0.01, 0.02));
    /// assert_eq!(Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().mounting().yaw, 0.02);
    /// ```
    pub fn mounting(&self) -> Euler {
        self.mounting
    }

    /// The times (s) where the closed form of a profile changes (segment
    /// boundaries and the ends of their edges), sorted.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .then(Segment::Accelerate { accel: 1.0, duration: 10.0 })
    ///     .then(Segment::Cruise { duration: 5.0 });
    /// let t = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    /// assert_eq!(t.breakpoints(), &[1.0, 9.0, 10.0]);
    /// ```
    pub fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    /// The exact velocity, acceleration, vehicle and body attitude and body
    /// rate at `t` (s).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .then(Segment::Accelerate { accel: 1.0, duration: 10.0 })
    ///     .with_mounting(Euler::from_degrees(0.0, 0.0, 90.0));
    /// let m = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().motion_at(5.0);
    /// // Mid-way the speed is exactly half the change (symmetric edges).
    /// assert!((m.vel.x - 5.0).abs() < 1e-12);
    /// // Heading north, the IMU's y axis points forward: its x axis west.
    /// assert!((m.c_bn.column(0) + kestrel_nav::nalgebra::Vector3::y()).norm() < 1e-15);
    /// ```
    pub fn motion_at(&self, t: f64) -> Motion {
        self.channels
            .motion(t, self.vehicle, &self.c_vb, &mut [0; 4])
    }

    /// The IMU body attitude `C_b^n = C_v^n C_b^v` of `motion`.
    pub(crate) fn body_attitude(&self, motion: &Motion) -> UnitQuaternion<f64> {
        motion.euler.to_quaternion() * self.q_bv
    }

    /// The true state (of the IMU body) at time 0.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Aircraft, Geodetic::from_degrees(32.3, 118.5, 1000.0), 45f64.to_radians(), 250.0);
    /// let s = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().initial_state();
    /// assert!((s.euler().yaw.to_degrees() - 45.0).abs() < 1e-12 && s.time == 0.0);
    /// ```
    pub fn initial_state(&self) -> NavState {
        let m = self.motion_at(0.0);
        NavState {
            time: 0.0,
            pos: self.start,
            vel: m.vel,
            att: self.body_attitude(&m),
        }
    }

    /// A stream of `(truth, exact IMU increment)` at `rate_hz` (Hz) from
    /// time 0 to the end, over a copy of this trajectory. Fails when the
    /// rate is not finite and positive.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .then(Segment::Stationary { duration: 1.0 });
    /// let t = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    /// assert_eq!(t.stream(200.0).unwrap().len(), 200);
    /// assert!(t.stream(0.0).is_err());
    /// ```
    pub fn stream(&self, rate_hz: f64) -> Result<ImuStream, TrajectoryError> {
        self.clone().into_stream(rate_hz)
    }

    /// As [`stream`](Self::stream), consuming the trajectory.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 1.0)
    ///     .then(Segment::Cruise { duration: 2.0 });
    /// let t = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    /// assert_eq!(t.into_stream(100.0).unwrap().count(), 200);
    /// ```
    pub fn into_stream(self, rate_hz: f64) -> Result<ImuStream, TrajectoryError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(TrajectoryError {
                segment: usize::MAX,
                kind: TrajectoryErrorKind::InvalidParameter,
            });
        }
        Ok(ImuStream::new(self, rate_hz))
    }

    /// The NED velocity at `t` (s), m/s.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 90f64.to_radians(), 3.0);
    /// let v = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().velocity_at(0.0);
    /// assert!((v.y - 3.0).abs() < 1e-15 && v.x.abs() < 1e-15);
    /// ```
    pub fn velocity_at(&self, t: f64) -> Vector3<f64> {
        self.motion_at(t).vel
    }
}
