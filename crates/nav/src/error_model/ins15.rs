//! The 15-state INS error model: attitude, velocity, position, gyro bias,
//! accelerometer bias.

use super::discrete::ErrorStateModel;
use super::inertial::InertialLayout;
pub use super::inertial::{ATT, POS, VEL};

/// First index of the gyro bias (body, rad/s).
pub const GYRO_BIAS: usize = 9;
/// First index of the accelerometer bias (body, m/s²).
pub const ACCEL_BIAS: usize = 12;

/// The 15-state error model `[φ, δv, δr, b_g, b_a]` (indices [`ATT`],
/// [`VEL`], [`POS`], [`GYRO_BIAS`], [`ACCEL_BIAS`]).
///
/// Each bias is a first-order Gauss-Markov process when the spec has one,
/// otherwise a random constant. Built by
/// [`new`](ErrorStateModel::new), [`from_mean`](ErrorStateModel::from_mean)
/// and [`continuous`](ErrorStateModel::continuous).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
/// use kestrel_nav::error_model::{Ins15Model, ins15::{ACCEL_BIAS, GYRO_BIAS}};
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let spec = ImuSpec::perfect().with_gyro_markov_deg_per_h(0.005, 3600.0);
/// let (f, _) = Ins15Model::continuous(&Ellipsoid::wgs84(), &spec, &nav, &Vector3::zeros());
/// assert!((f[(GYRO_BIAS, GYRO_BIAS)] + 1.0 / 3600.0).abs() < 1e-18);
/// assert_eq!(f[(ACCEL_BIAS, ACCEL_BIAS)], 0.0);
/// ```
pub type Ins15Model = ErrorStateModel<15>;

impl InertialLayout for Ins15Model {
    const GYRO_BIAS: usize = GYRO_BIAS;
    const GYRO_CONST: Option<usize> = None;
    const ACCEL_BIAS: usize = ACCEL_BIAS;
}
