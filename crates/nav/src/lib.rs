//! # kestrel-nav
//!
//! Strapdown inertial navigation and its GNSS / odometer aiding on kestrel
//! filters.
//!
//! Conventions: navigation frame NED; body frame forward-right-down;
//! attitude `C_b^n` as a unit quaternion; Euler angles ZYX (roll, pitch,
//! yaw, yaw from north towards east); radians and SI units inside the API.
//! The navigation solution is `f64`; error-state models are generic over
//! the filter scalar.
#![deny(missing_docs)]

pub mod attitude;
pub mod correction;
pub mod earth;
pub mod engine;
pub mod error_model;
pub mod experiment;
pub mod geodetic;
pub mod imu;
pub mod imu_spec;
pub mod measurement;
pub mod mechanisation;
pub mod odometer;
pub mod scenario;
pub mod sim;
pub mod state;

pub use attitude::{
    attitude_error, correct_attitude, error_rotation, quaternion_to_rotation_vector,
    rotation_vector_to_quaternion, skew, Euler,
};
pub use correction::{feedback15, feedback18, ImuBiases, NavError};
pub use earth::{Ellipsoid, NormalGravity};
pub use geodetic::Geodetic;
pub use imu::ImuIncrement;
pub use imu_spec::ImuSpec;
pub use mechanisation::Strapdown;
pub use nalgebra;
pub use state::NavState;
