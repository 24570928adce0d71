//! The plain-data description of a trajectory.

use super::segment::{Segment, Vehicle};
use kestrel_nav::attitude::Euler;
use kestrel_nav::geodetic::Geodetic;

/// A trajectory as data: where it starts, how it moves at the start, and
/// the manoeuvres that follow one another.
///
/// The segments move the *vehicle* frame `v`: its x axis points along the
/// velocity (no angle of attack); yaw is the track minus any side-slip,
/// pitch the flight-path angle, roll the coordinated bank of an aircraft
/// (zero for a ground vehicle). The IMU body frame `b` is fixed to the
/// vehicle, turned by [`mounting`](Self::mounting); the truth attitude and
/// the IMU increments are those of the body, while an odometer measures
/// along the vehicle's x axis and the non-holonomic constraint holds in
/// vehicle axes.
///
/// ```
/// use kestrel_nav::{Geodetic};
/// use kestrel_sim::{Segment, TrajectorySpec, Vehicle};
/// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::from_degrees(34.0, 120.0, 200.0), 90f64.to_radians(), 0.0)
///     .then(Segment::Stationary { duration: 10.0 })
///     .then(Segment::Accelerate { accel: 2.0, duration: 10.0 });
/// assert_eq!(spec.segments.len(), 2);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TrajectorySpec {
    /// What moves (decides banking in turns).
    pub vehicle: Vehicle,
    /// Start position.
    pub start: Geodetic,
    /// Track (= yaw) at the start, rad from north towards east.
    pub heading: f64,
    /// Speed at the start, m/s (level, along the heading).
    pub speed: f64,
    /// The manoeuvres, in order.
    pub segments: Vec<Segment>,
    /// Length of the raised-cosine edges of acceleration and turn-rate
    /// changes, s (shortened when a manoeuvre is too short for two).
    pub edge: f64,
    /// Length of the Hann-shaped pitch transitions into and out of a
    /// climb, s (shortened to half the climb when needed).
    pub pitch_transition: f64,
    /// The vehicle frame in IMU body axes as ZYX Euler angles,
    /// `C_v^b = Rz(yaw) Ry(pitch) Rx(roll)`: the vehicle's forward axis is
    /// the body's pitched up by `pitch` and turned right by `yaw` (the
    /// angles of [`Odometer::with_mounting`](kestrel_nav::measurement::Odometer::with_mounting);
    /// roll about the forward axis changes neither the odometer speed nor
    /// the constraint). Zero by default: body and vehicle coincide.
    pub mounting: Euler,
}

impl TrajectorySpec {
    /// Default edge length of speed and turn-rate changes, s.
    pub const DEFAULT_EDGE: f64 = 1.0;
    /// Default pitch transition of climbs, s.
    pub const DEFAULT_PITCH_TRANSITION: f64 = 5.0;

    /// A trajectory starting at `start` with the track `heading` (rad) and
    /// speed `speed` (m/s), no manoeuvres yet, default edges.
    ///
    /// ```
    /// use kestrel_nav::{Geodetic};
    /// use kestrel_sim::{TrajectorySpec, Vehicle};
    /// let s = TrajectorySpec::new(Vehicle::Aircraft, Geodetic::from_degrees(30.0, 120.0, 1e4), 0.0, 300.0);
    /// assert_eq!(s.edge, TrajectorySpec::DEFAULT_EDGE);
    /// ```
    pub fn new(vehicle: Vehicle, start: Geodetic, heading: f64, speed: f64) -> Self {
        Self {
            vehicle,
            start,
            heading,
            speed,
            segments: Vec::new(),
            edge: Self::DEFAULT_EDGE,
            pitch_transition: Self::DEFAULT_PITCH_TRANSITION,
            mounting: Euler::default(),
        }
    }

    /// Appends a manoeuvre.
    ///
    /// ```
    /// use kestrel_nav::{Geodetic};
    /// use kestrel_sim::{Segment, TrajectorySpec, Vehicle};
    /// let s = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 10.0)
    ///     .then(Segment::Cruise { duration: 5.0 });
    /// assert_eq!(s.segments, vec![Segment::Cruise { duration: 5.0 }]);
    /// ```
    pub fn then(mut self, segment: Segment) -> Self {
        self.segments.push(segment);
        self
    }

    /// Sets the edge length of speed and turn-rate changes, s.
    ///
    /// ```
    /// use kestrel_nav::{Geodetic};
    /// use kestrel_sim::{TrajectorySpec, Vehicle};
    /// let s = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0).with_edge(0.5);
    /// assert_eq!(s.edge, 0.5);
    /// ```
    pub fn with_edge(mut self, edge: f64) -> Self {
        self.edge = edge;
        self
    }

    /// Sets the pitch transition length of climbs, s.
    ///
    /// ```
    /// use kestrel_nav::{Geodetic};
    /// use kestrel_sim::{TrajectorySpec, Vehicle};
    /// let s = TrajectorySpec::new(Vehicle::Aircraft, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .with_pitch_transition(10.0);
    /// assert_eq!(s.pitch_transition, 10.0);
    /// ```
    pub fn with_pitch_transition(mut self, seconds: f64) -> Self {
        self.pitch_transition = seconds;
        self
    }

    /// Sets the IMU mounting: the vehicle frame in body axes (see
    /// [`mounting`](Self::mounting)).
    ///
    /// ```
    /// use kestrel_nav::{Euler, Geodetic};
    /// use kestrel_sim::{TrajectorySpec, Vehicle};
    /// let s = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .with_mounting(Euler::from_degrees(0.0, 0.2, -0.3));
    /// assert!((s.mounting.yaw.to_degrees() + 0.3).abs() < 1e-12);
    /// ```
    pub fn with_mounting(mut self, mounting: Euler) -> Self {
        self.mounting = mounting;
        self
    }
}
