//! The 18-state INS error model of papers 000 and 004: attitude, velocity,
//! position, gyro constant drift, gyro Markov drift, accelerometer bias.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::discrete::ErrorStateModel;
use super::dynamics::nav_error_dynamics;
use super::fifteen::markov;
use super::forcing::ForcingMean;
use crate::earth::Ellipsoid;
use crate::imu_spec::ImuSpec;
use crate::state::NavState;

/// First index of the attitude error φ (NED, rad).
pub const ATT: usize = 0;
/// First index of the velocity error δv (NED, m/s).
pub const VEL: usize = 3;
/// First index of the position error δr (NED, m).
pub const POS: usize = 6;
/// First index of the gyro constant drift ε_c (body, rad/s).
pub const GYRO_CONST: usize = 9;
/// First index of the gyro first-order Markov drift ε_r (body, rad/s).
pub const GYRO_MARKOV: usize = 12;
/// First index of the accelerometer bias ∇ (body, m/s²).
pub const ACCEL_BIAS: usize = 15;

/// The 18-state error model `[φ, δv, δr, ε_c, ε_r, ∇]` (indices [`ATT`],
/// [`VEL`], [`POS`], [`GYRO_CONST`], [`GYRO_MARKOV`], [`ACCEL_BIAS`]).
pub type ErrorModel18 = ErrorStateModel<18>;

impl ErrorStateModel<18> {
    /// The model over `dt` seconds linearised at `nav` with the specific
    /// force `f_ned` (m/s², NED).
    ///
    /// The gyro error is `ε_c + ε_r`: `ε_c` a random constant (its size
    /// enters through the initial covariance, `spec.gyro_bias`), `ε_r` a
    /// first-order Markov process (`spec.gyro_markov_sigma`, `_tau`; a
    /// random constant if the spec has none). `∇` is a Markov process when
    /// the spec gives an accelerometer one, otherwise a random constant.
    /// White noise: `ARW²` on φ, `VRW²` on δv, the Markov driving densities
    /// `2σ²/τ` on `ε_r` and `∇`.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
    /// use kestrel_nav::error_model::{ErrorModel18, eighteen::GYRO_MARKOV};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(40.1, 118.6, 100.0), Vector3::zeros(),
    ///     Euler::default());
    /// let spec = ImuSpec::perfect().with_gyro_markov_deg_per_h(0.005, 3600.0);
    /// let m = ErrorModel18::new(&Ellipsoid::krasovsky(), &spec, &nav, &Vector3::zeros(), 1.0);
    /// let k = GYRO_MARKOV;
    /// assert!((m.f()[(k, k)] + 1.0 / 3600.0).abs() < 1e-18);
    /// ```
    pub fn new(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        f_ned: &Vector3<f64>,
        dt: f64,
    ) -> Self {
        let (f, q) = continuous18(earth, spec, nav, f_ned);
        Self::from_continuous(f, q, dt)
    }

    /// The model over the interval summarised by `mean` (its length, mean
    /// specific force and mean `C_b^n`), with the position and velocity of
    /// `nav` (the solution at the start or middle of the interval).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown,
    ///     nalgebra::Vector3};
    /// use kestrel_nav::error_model::{ErrorModel18, ForcingMean};
    /// let earth = Ellipsoid::wgs84();
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut ins = Strapdown::new(earth, s);
    /// let mut mean = ForcingMean::default();
    /// for k in 1..=20 {
    ///     let imu = ImuIncrement::from_rates(k as f64 * 0.005, 0.005, Vector3::new(0.0, 0.0, 0.1),
    ///         Vector3::new(0.0, 0.0, -9.8));
    ///     ins.step(&imu);
    ///     mean.add(&ins, imu.dt);
    /// }
    /// let m = ErrorModel18::from_mean(&earth, &ImuSpec::perfect(), &s, &mean);
    /// assert!((m.dt() - 0.1).abs() < 1e-15);
    /// ```
    pub fn from_mean(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        mean: &ForcingMean,
    ) -> Self {
        let (f, q) = continuous18_with(earth, spec, nav, &mean.c_bn(), &mean.f_ned());
        Self::from_continuous(f, q, mean.dt())
    }
}

/// The continuous `F` and noise densities of [`ErrorModel18`] at `nav`
/// (sensor errors mapped by the attitude of `nav`).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
/// use kestrel_nav::error_model::{continuous18, eighteen::{ATT, GYRO_CONST}};
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(),
///     Euler::from_degrees(0.0, 0.0, 90.0));
/// let (f, _) = continuous18(&Ellipsoid::wgs84(), &ImuSpec::perfect(), &nav, &Vector3::zeros());
/// // Yaw 90°: body x points east, so a gyro x bias tilts about east.
/// assert!((f[(ATT + 1, GYRO_CONST)] + 1.0).abs() < 1e-15);
/// ```
pub fn continuous18(
    earth: &Ellipsoid,
    spec: &ImuSpec,
    nav: &NavState,
    f_ned: &Vector3<f64>,
) -> (SMatrix<f64, 18, 18>, SVector<f64, 18>) {
    let c = nav.att.to_rotation_matrix().into_inner();
    continuous18_with(earth, spec, nav, &c, f_ned)
}

/// [`continuous18`] with the body-frame sensor errors mapped by `c_bn`
/// instead of the attitude of `nav`, typically the mean over the interval
/// ([`ForcingMean::c_bn`]).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState,
///     nalgebra::{Matrix3, Vector3}};
/// use kestrel_nav::error_model::{continuous18_with, eighteen::{ATT, GYRO_CONST, GYRO_MARKOV}};
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let (f, _) = continuous18_with(&Ellipsoid::wgs84(), &ImuSpec::perfect(), &nav,
///     &Matrix3::identity(), &Vector3::zeros());
/// // Both gyro drifts enter the attitude error the same way.
/// assert_eq!(f[(ATT, GYRO_CONST)], f[(ATT, GYRO_MARKOV)]);
/// ```
pub fn continuous18_with(
    earth: &Ellipsoid,
    spec: &ImuSpec,
    nav: &NavState,
    c_bn: &Matrix3<f64>,
    f_ned: &Vector3<f64>,
) -> (SMatrix<f64, 18, 18>, SVector<f64, 18>) {
    let mut f = SMatrix::<f64, 18, 18>::zeros();
    f.fixed_view_mut::<9, 9>(0, 0)
        .copy_from(&nav_error_dynamics(earth, nav, f_ned));
    let c = *c_bn;
    f.fixed_view_mut::<3, 3>(ATT, GYRO_CONST).copy_from(&(-c));
    f.fixed_view_mut::<3, 3>(ATT, GYRO_MARKOV).copy_from(&(-c));
    f.fixed_view_mut::<3, 3>(VEL, ACCEL_BIAS).copy_from(&c);
    let (fg, qg) = markov(
        spec.has_gyro_markov(),
        spec.gyro_markov_sigma,
        spec.gyro_markov_tau,
    );
    let (fa, qa) = markov(
        spec.has_accel_markov(),
        spec.accel_markov_sigma,
        spec.accel_markov_tau,
    );
    let mut q = SVector::<f64, 18>::zeros();
    for i in 0..3 {
        f[(GYRO_MARKOV + i, GYRO_MARKOV + i)] = fg;
        f[(ACCEL_BIAS + i, ACCEL_BIAS + i)] = fa;
        q[ATT + i] = spec.gyro_arw * spec.gyro_arw;
        q[VEL + i] = spec.accel_vrw * spec.accel_vrw;
        q[GYRO_MARKOV + i] = qg;
        q[ACCEL_BIAS + i] = qa;
    }
    (f, q)
}
