//! The 18-state INS error model of papers 000 and 004: attitude, velocity,
//! position, gyro constant drift, gyro Markov drift, accelerometer bias.

use super::discrete::ErrorStateModel;
use super::inertial::InertialLayout;
pub use super::inertial::{ATT, POS, VEL};

/// First index of the gyro constant drift ε_c (body, rad/s).
pub const GYRO_CONST: usize = 9;
/// First index of the gyro first-order Markov drift ε_r (body, rad/s).
pub const GYRO_MARKOV: usize = 12;
/// First index of the accelerometer bias ∇ (body, m/s²).
pub const ACCEL_BIAS: usize = 15;

/// The 18-state error model `[φ, δv, δr, ε_c, ε_r, ∇]` (indices [`ATT`],
/// [`VEL`], [`POS`], [`GYRO_CONST`], [`GYRO_MARKOV`], [`ACCEL_BIAS`]).
///
/// The gyro error is `ε_c + ε_r`: `ε_c` a random constant (its size enters
/// through the initial covariance, `spec.gyro_bias`), `ε_r` a first-order
/// Markov process (`spec.gyro_markov_sigma`, `_tau`; a random constant if
/// the spec has none). `∇` is a Markov process when the spec gives an
/// accelerometer one, otherwise a random constant. White noise: `ARW²` on
/// φ, `VRW²` on δv, the Markov driving densities `2σ²/τ` on `ε_r` and `∇`.
/// Built by [`new`](ErrorStateModel::new),
/// [`from_mean`](ErrorStateModel::from_mean) and
/// [`continuous`](ErrorStateModel::continuous).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
/// use kestrel_nav::error_model::{Ins18Model, ins18::GYRO_MARKOV};
/// let nav = NavState::new(0.0, Geodetic::from_degrees(40.1, 118.6, 100.0), Vector3::zeros(),
///     Euler::default());
/// let spec = ImuSpec::perfect().with_gyro_markov_deg_per_h(0.005, 3600.0);
/// let m = Ins18Model::new(&Ellipsoid::krasovsky(), &spec, &nav, &Vector3::zeros(), 1.0);
/// let k = GYRO_MARKOV;
/// assert!((m.f()[(k, k)] + 1.0 / 3600.0).abs() < 1e-18);
/// ```
pub type Ins18Model = ErrorStateModel<18>;

impl InertialLayout for Ins18Model {
    const GYRO_BIAS: usize = GYRO_MARKOV;
    const GYRO_CONST: Option<usize> = Some(GYRO_CONST);
    const ACCEL_BIAS: usize = ACCEL_BIAS;
}
