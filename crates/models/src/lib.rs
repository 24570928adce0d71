//! # kestrel-models
//!
//! Reusable process and measurement models for kestrel filters, `no_std`,
//! allocation-free and generic over `f32` / `f64`.
//!
//! - Kinematics: [`ConstantVelocity`], [`ConstantAcceleration`], the
//!   [`Singer`] manoeuvre model (1 to 3 axes, per-axis states interleaved)
//!   and the [`CoordinatedTurn`] with unknown turn rate.
//! - Sensor errors: [`RandomWalk`], [`GaussMarkov`].
//! - Continuous linear systems: [`Lti`], discretised with [`expm`] and
//!   [`van_loan`]; fixed matrices: [`LinearProcess`].
//! - Composition: [`Stack`] places two process models side by side.
//! - Measurements: [`Selection`], [`LinearMeasurement`], [`RangeBearing`].
//! - Jacobians: [`check_process_jacobian`] / [`check_measurement_jacobian`]
//!   compare a hand-written Jacobian with central differences;
//!   `AutoJacobian` (feature `autodiff`, on in the `kestrel` crate) derives
//!   one by automatic differentiation for models generic over the scalar.
//!
//! - Simulation: [`Gaussian`] draws from `N(μ, P)`.
//!
//! Constructors that take a parameter with a valid range (a density, a
//! time constant, an index) return `Result<Self, FilterError>` whose error
//! names the parameter and states the range. Plain matrices
//! ([`LinearProcess`], [`LinearMeasurement`], [`Lti`]) are taken as given:
//! the filter's input contract checks `Q` and `R` at every predict and
//! update.
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
#[cfg(feature = "autodiff")]
mod auto_jacobian;
mod axes;
mod constant_acceleration;
mod constant_velocity;
mod coordinated_turn;
mod expm;
mod gauss_markov;
mod gaussian;
mod jacobian_check;
mod linear;
mod lti;
mod lu;
mod pade;
mod random_walk;
mod range_bearing;
mod selection;
mod singer;
mod sizes;
mod stack;
mod van_loan;

pub use angle::wrap_angle;
#[cfg(feature = "autodiff")]
pub use auto_jacobian::{AutoDiffScalar, AutoJacobian};
pub use constant_acceleration::{
    ConstantAcceleration, ConstantAcceleration1d, ConstantAcceleration2d, ConstantAcceleration3d,
};
pub use constant_velocity::{
    ConstantVelocity, ConstantVelocity1d, ConstantVelocity2d, ConstantVelocity3d,
};
pub use coordinated_turn::CoordinatedTurn;
pub use expm::expm;
pub use gauss_markov::GaussMarkov;
pub use gaussian::Gaussian;
pub use jacobian_check::{
    check_measurement_jacobian, check_process_jacobian, finite_difference_jacobian, JacobianCheck,
};
pub use linear::{LinearMeasurement, LinearProcess};
pub use lti::Lti;
pub use random_walk::RandomWalk;
pub use range_bearing::RangeBearing;
pub use selection::Selection;
pub use singer::Singer;
pub use sizes::{AccelerationAxes, Size, SumOf, VelocityAxes};
pub use stack::Stack;
pub use van_loan::van_loan;
