//! # kestrel-sim
//!
//! Simulated drives and flights for testing navigation filters:
//! trajectories with exact truth and IMU increments ([`trajectory`]), and
//! sensor models (IMU errors, GNSS, odometer, attitude) driven by seeded
//! random number generators ([`sensors`]). The sensors deliver the
//! [`measurement`](kestrel_nav::measurement) types the filters use, wrapped in
//! [`Simulated`] where the simulation also knows whether it corrupted them.
//!
//! A drive north at 10 m/s, then a right turn of 90° at 3 °/s:
//!
//! ```
//! use kestrel_nav::{Ellipsoid, Geodetic};
//! use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
//!
//! let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::from_degrees(30.0, 114.0, 20.0), 0.0, 10.0)
//!     .then(Segment::Cruise { duration: 60.0 })
//!     .then(Segment::turn_rate_deg(3.0, 90.0));
//! let t = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
//! let end = t.velocity_at(t.duration());
//! assert!(end.x.abs() < 1e-6 && (end.y - 10.0).abs() < 1e-6, "{end:?}");
//! ```
#![deny(missing_docs)]

pub mod sensors;
pub mod trajectory;

pub use sensors::{
    sensor_rng, AttitudeConfig, AttitudeSensor, GaussMarkov, GaussMarkov3, GnssConfig, GnssSensor,
    ImuErrors, ImuSensor, MultipathBursts, NoiseWindow, OdometerConfig, OdometerFault,
    OdometerFaultKind, OdometerSensor, Outlier, OutlierKind, ReportedStd, SensorStream, SimRng,
    Simulated, TimeWindow,
};
pub use trajectory::{
    ClimbRate, ImuStream, Motion, Segment, Trajectory, TrajectoryError, TrajectoryErrorKind,
    TrajectorySpec, TurnRate, Vehicle,
};
