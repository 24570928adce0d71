//! The 21-state INS error model: the 15 states plus gyro and accelerometer
//! scale-factor errors.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::discrete::ErrorStateModel;
use super::forcing::ForcingMean;
use super::inertial::InertialLayout;
pub use super::inertial::{ATT, POS, VEL};
use crate::earth::Ellipsoid;
use crate::imu_spec::ImuSpec;
use crate::state::NavState;

/// First index of the gyro bias (body, rad/s).
pub const GYRO_BIAS: usize = 9;
/// First index of the accelerometer bias (body, m/s²).
pub const ACCEL_BIAS: usize = 12;
/// First index of the gyro scale-factor error (body axes, ratio).
pub const GYRO_SCALE: usize = 15;
/// First index of the accelerometer scale-factor error (body axes, ratio).
pub const ACCEL_SCALE: usize = 18;

/// The 21-state error model `[φ, δv, δr, b_g, b_a, s_g, s_a]` (indices
/// [`ATT`], [`VEL`], [`POS`], [`GYRO_BIAS`], [`ACCEL_BIAS`],
/// [`GYRO_SCALE`], [`ACCEL_SCALE`]), the state of KF-GINS and of most
/// post-processors for MEMS and tactical IMUs.
///
/// Sensor model, per body axis: `ω̃ = (1 + s_g) ω + b_g + noise`,
/// `f̃ = (1 + s_a) f + b_a + noise`, so to first order the errors of the
/// compensated readings are `δω = b_g + diag(ω) s_g` and
/// `δf = b_a + diag(f) s_a`:
///
/// ```text
/// φ̇  = … − C_b^n (b_g + diag(ω_ib^b) s_g)
/// δv̇ = … + C_b^n (b_a + diag(f^b) s_a)
/// ```
///
/// The biases are as in [`Ins15Model`](super::Ins15Model) (Gauss-Markov
/// when the spec has one, else random constants). The scale factors are
/// random constants for an infinite `scale_tau`, otherwise first-order
/// Gauss-Markov processes with correlation time `scale_tau` and
/// steady-state σ `spec.gyro_scale` / `spec.accel_scale`. Over a
/// propagation interval the inputs `C diag(ω)` and `C diag(f)` are the
/// interval means ([`ForcingMean::gyro_scale_gain`],
/// [`ForcingMean::accel_scale_gain`]).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::{Matrix3, Vector3}};
/// use kestrel_nav::error_model::{Ins21Model, ins21::{ACCEL_SCALE, GYRO_SCALE}};
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let spec = ImuSpec::perfect().with_gyro_scale_ppm(300.0);
/// // Turning at 0.1 rad/s about down, with gravity on the accelerometers.
/// let gw = Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 0.1));
/// let gf = Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, -9.8));
/// let (f, q) = Ins21Model::continuous_scaled(&Ellipsoid::wgs84(), &spec, 3600.0, &nav,
///     &Matrix3::identity(), &Vector3::new(0.0, 0.0, -9.8), &gw, &gf);
/// assert_eq!(f[(2, GYRO_SCALE + 2)], -0.1);   // yaw error from the z scale factor
/// assert_eq!(f[(5, ACCEL_SCALE + 2)], -9.8);  // down velocity from the z accel scale
/// assert_eq!(f[(GYRO_SCALE, GYRO_SCALE)], -1.0 / 3600.0);
/// assert!((q[GYRO_SCALE] - 2.0 * (300e-6f64).powi(2) / 3600.0).abs() < 1e-20);
/// ```
pub type Ins21Model = ErrorStateModel<21>;

impl InertialLayout for Ins21Model {
    const GYRO_BIAS: usize = GYRO_BIAS;
    const GYRO_CONST: Option<usize> = None;
    const ACCEL_BIAS: usize = ACCEL_BIAS;
}

impl Ins21Model {
    /// The model over the interval `mean` summarises, at the solution `nav`
    /// (its end), with scale-factor correlation time `scale_tau` (s;
    /// infinite: random constants).
    pub fn from_mean_scaled(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        scale_tau: f64,
        nav: &NavState,
        mean: &ForcingMean,
    ) -> Self {
        let (f, q) = Self::continuous_scaled(
            earth,
            spec,
            scale_tau,
            nav,
            &mean.c_bn(),
            &mean.f_ned(),
            &mean.gyro_scale_gain(),
            &mean.accel_scale_gain(),
        );
        Self::from_continuous(f, q, mean.dt())
    }

    /// The continuous `F` and white-noise densities `q`, with the inputs of
    /// the scale-factor errors `gyro_gain = C diag(ω_ib^b)` and
    /// `accel_gain = C diag(f^b)`.
    #[allow(clippy::too_many_arguments)]
    pub fn continuous_scaled(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        scale_tau: f64,
        nav: &NavState,
        c_bn: &Matrix3<f64>,
        f_ned: &Vector3<f64>,
        gyro_gain: &Matrix3<f64>,
        accel_gain: &Matrix3<f64>,
    ) -> (SMatrix<f64, 21, 21>, SVector<f64, 21>) {
        let (mut f, mut q) = Self::continuous_with(earth, spec, nav, c_bn, f_ned);
        f.fixed_view_mut::<3, 3>(ATT, GYRO_SCALE)
            .copy_from(&(-gyro_gain));
        f.fixed_view_mut::<3, 3>(VEL, ACCEL_SCALE)
            .copy_from(accel_gain);
        if scale_tau.is_finite() {
            for (first, sigma) in [
                (GYRO_SCALE, spec.gyro_scale),
                (ACCEL_SCALE, spec.accel_scale),
            ] {
                for i in first..first + 3 {
                    f[(i, i)] = -1.0 / scale_tau;
                    q[i] = 2.0 * sigma * sigma / scale_tau;
                }
            }
        }
        (f, q)
    }
}
