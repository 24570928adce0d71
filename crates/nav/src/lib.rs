//! # kestrel-nav
//!
//! Strapdown inertial navigation and its GNSS / odometer aiding on kestrel
//! filters: the GPS/SINS and SINS/odometer systems of the project's five
//! papers. Simulated drives come from `kestrel-sim`; the papers'
//! experiments and the processing of recorded logs from `kestrel-app`.
//!
//! Conventions: navigation frame NED; body frame forward-right-down;
//! attitude `C_b^n` as a unit quaternion; Euler angles ZYX (roll, pitch,
//! yaw, yaw from north towards east); radians and SI units inside the API.
//! The navigation solution is `f64` (latitude in `f32` resolves only about
//! a metre); error-state and measurement models are generic over the filter
//! scalar, so `f32` filters run on the error state.
//!
//! | module | what it holds |
//! |---|---|
//! | [`earth`], [`geodetic`], [`attitude`] | ellipsoids, radii, gravity, Earth and transport rate; positions; quaternion / DCM / Euler / rotation vector |
//! | [`mechanisation`], [`imu`], [`state`] | the strapdown algorithm on angle and velocity increments |
//! | [`imu_spec`], [`error_model`], [`correction`] | sensor specifications, the 15- and 18-state error models (`F`, `Φ`, `Q_d`), feedback |
//! | [`measurement`] | GNSS position(+velocity) with lever arm, attitude+velocity+position, odometer and non-holonomic constraint |
//! | [`engine`], [`odometer`] | the loosely coupled engine; paper 003's 16-state odometer system and fault processing |
//!
//! A stationary INS with perfect sensors stays put:
//!
//! ```
//! use kestrel_nav::nalgebra::Vector3;
//! use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState, Strapdown};
//!
//! let earth = Ellipsoid::wgs84();
//! let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 50.0), Vector3::zeros(),
//!     Euler::default());
//! let g = earth.gravity(start.pos.lat, start.pos.h);
//! let mut ins = Strapdown::new(earth, start);
//! for k in 1..=6000 {
//!     // A body at rest, level and facing north, senses Earth rate and −g.
//!     ins.step(&ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
//!         earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g)));
//! }
//! let drift = earth.ned_offset(&start.pos, &ins.state().pos);
//! assert!(drift.norm() < 1e-4, "{drift:?}");
//! ```
#![deny(missing_docs)]

pub mod attitude;
pub mod correction;
pub mod earth;
pub mod engine;
pub mod error_model;
pub mod geodetic;
pub mod imu;
pub mod imu_spec;
pub mod measurement;
pub mod mechanisation;
pub mod odometer;
pub mod standstill;
pub mod state;

pub use attitude::{
    attitude_error, correct_attitude, error_rotation, quaternion_to_rotation_vector,
    rotation_vector_to_quaternion, skew, Euler,
};
pub use correction::{feedback_ins15, feedback_ins18, ImuBiases, NavError};
pub use earth::{Ellipsoid, NormalGravity};
pub use geodetic::Geodetic;
pub use imu::ImuIncrement;
pub use imu_spec::ImuSpec;
pub use mechanisation::Strapdown;
pub use nalgebra;
pub use state::NavState;
