//! # kestrel-models
//!
//! Reusable process and measurement models for kestrel filters, `no_std`,
//! allocation-free and generic over `f32` / `f64`.
//!
//! - Kinematics: [`ConstantVelocity`], [`ConstantAcceleration`] (1 to 3
//!   axes, per-axis states interleaved).
//! - Sensor errors: [`RandomWalk`], [`GaussMarkov`].
//! - Continuous linear systems: [`Lti`], discretised with [`expm`] and
//!   [`van_loan`]; fixed matrices: [`LinearProcess`].
//! - Composition: [`Stack`] places two process models side by side.
//! - Measurements: [`Selection`], [`LinearMeasurement`], [`RangeBearing`].
//!
//! ```
//! use kestrel_core::{Ekf, nalgebra::{Matrix2, Vector2, Vector4, SMatrix}};
//! use kestrel_models::{ConstantVelocity2d, Selection};
//!
//! let cv = ConstantVelocity2d::new(0.01).unwrap();
//! let gps = Selection::<f64, 4, 2>::new([0, 2], Matrix2::identity()).unwrap();
//! let mut ekf = Ekf::new(Vector4::zeros(), SMatrix::<f64, 4, 4>::identity() * 100.0).unwrap();
//! for k in 1..=30 {
//!     let t = k as f64;
//!     ekf.predict(&cv, 1.0).unwrap();
//!     ekf.update(&gps, &Vector2::new(3.0 * t, -t)).unwrap();
//! }
//! assert!((ekf.state()[1] - 3.0).abs() < 0.05 && (ekf.state()[3] + 1.0).abs() < 0.05);
//! ```
#![no_std]
#![deny(missing_docs)]

mod angle;
mod axes;
mod constant_acceleration;
mod constant_velocity;
mod expm;
mod gauss_markov;
mod linear;
mod lti;
mod lu;
mod pade;
mod random_walk;
mod range_bearing;
mod selection;
mod sizes;
mod stack;
mod van_loan;

pub use angle::wrap_angle;
pub use constant_acceleration::{
    ConstantAcceleration, ConstantAcceleration1d, ConstantAcceleration2d, ConstantAcceleration3d,
};
pub use constant_velocity::{
    ConstantVelocity, ConstantVelocity1d, ConstantVelocity2d, ConstantVelocity3d,
};
pub use expm::expm;
pub use gauss_markov::GaussMarkov;
pub use linear::{LinearMeasurement, LinearProcess};
pub use lti::Lti;
pub use random_walk::RandomWalk;
pub use range_bearing::RangeBearing;
pub use selection::Selection;
pub use sizes::{AccelerationAxes, Size, SumOf, VelocityAxes};
pub use stack::Stack;
pub use van_loan::van_loan;
