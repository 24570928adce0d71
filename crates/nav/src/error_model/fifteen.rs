//! The 15-state INS error model: attitude, velocity, position, gyro bias,
//! accelerometer bias.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::discrete::ErrorStateModel;
use super::dynamics::nav_error_dynamics;
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
/// First index of the gyro bias (body, rad/s).
pub const GYRO_BIAS: usize = 9;
/// First index of the accelerometer bias (body, m/s²).
pub const ACCEL_BIAS: usize = 12;

/// The 15-state error model `[φ, δv, δr, b_g, b_a]` (indices [`ATT`],
/// [`VEL`], [`POS`], [`GYRO_BIAS`], [`ACCEL_BIAS`]).
pub type ErrorModel15 = ErrorStateModel<15>;

impl ErrorStateModel<15> {
    /// The model over `dt` seconds linearised at `nav` with the specific
    /// force `f_ned` (m/s², NED; the mean over the interval when the model
    /// spans several IMU samples, see [`ForcingMean`](super::ForcingMean)).
    ///
    /// Dynamics: the navigation block of [`nav_error_dynamics`], gyro bias
    /// into attitude through `−C_b^n`, accelerometer bias into velocity
    /// through `C_b^n`. Each bias is a first-order Gauss-Markov process
    /// (`ḃ = −b/τ + w`, density `2σ²/τ`) when the spec has one, otherwise a
    /// random constant. Noise densities: `ARW²` on φ and `VRW²` on δv (the
    /// rotation `C_b^n` drops out because the spec is the same on every axis).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
    /// use kestrel_nav::error_model::{ErrorModel15, fifteen::{ATT, GYRO_BIAS}};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    ///     Euler::default());
    /// let spec = ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1);
    /// let m = ErrorModel15::new(&Ellipsoid::wgs84(), &spec, &nav, &Vector3::new(0.0, 0.0, -9.79), 0.1);
    /// // Level, yaw 0: a gyro x bias tilts about north, φ̇_N = −b_x.
    /// assert!((m.phi()[(ATT, GYRO_BIAS)] + 0.1).abs() < 1e-6);
    /// ```
    pub fn new(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        f_ned: &Vector3<f64>,
        dt: f64,
    ) -> Self {
        let (f, q) = continuous15(earth, spec, nav, f_ned);
        Self::from_continuous(f, q, dt)
    }

    /// The model over the interval summarised by `mean` (its length, mean
    /// specific force and mean `C_b^n`), with the position and velocity of
    /// `nav` (the solution at the start or middle of the interval).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown,
    ///     nalgebra::Vector3};
    /// use kestrel_nav::error_model::{ErrorModel15, ForcingMean};
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
    /// let m = ErrorModel15::from_mean(&earth, &ImuSpec::perfect(), &s, &mean);
    /// assert!((m.dt() - 0.1).abs() < 1e-15);
    /// ```
    pub fn from_mean(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        mean: &ForcingMean,
    ) -> Self {
        let (f, q) = continuous15_with(earth, spec, nav, &mean.c_bn(), &mean.f_ned());
        Self::from_continuous(f, q, mean.dt())
    }
}

/// The continuous `F` and noise densities of [`ErrorModel15`] at `nav`
/// (sensor errors mapped by the attitude of `nav`), for models that
/// extend the 15 states (place them in the top-left corner).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
/// use kestrel_nav::error_model::{continuous15, fifteen::{ATT, GYRO_BIAS}};
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(),
///     Euler::from_degrees(0.0, 0.0, 90.0));
/// let (f, _) = continuous15(&Ellipsoid::wgs84(), &ImuSpec::perfect(), &nav, &Vector3::zeros());
/// // Yaw 90°: body x points east, so a gyro x bias tilts about east.
/// assert!((f[(ATT + 1, GYRO_BIAS)] + 1.0).abs() < 1e-15);
/// ```
pub fn continuous15(
    earth: &Ellipsoid,
    spec: &ImuSpec,
    nav: &NavState,
    f_ned: &Vector3<f64>,
) -> (SMatrix<f64, 15, 15>, SVector<f64, 15>) {
    let c = nav.att.to_rotation_matrix().into_inner();
    continuous15_with(earth, spec, nav, &c, f_ned)
}

/// [`continuous15`] with the body-frame sensor errors mapped by `c_bn`
/// instead of the attitude of `nav`, typically the mean over the interval
/// ([`ForcingMean::c_bn`]).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::{Matrix3, Vector3}};
/// use kestrel_nav::error_model::continuous15_with;
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let spec = ImuSpec::perfect().with_accel_vrw_m_s_per_sqrt_h(0.06);
/// let (_, q) =
///     continuous15_with(&Ellipsoid::wgs84(), &spec, &nav, &Matrix3::identity(), &Vector3::zeros());
/// assert!((q[3] - 1e-6).abs() < 1e-18);
/// ```
pub fn continuous15_with(
    earth: &Ellipsoid,
    spec: &ImuSpec,
    nav: &NavState,
    c_bn: &Matrix3<f64>,
    f_ned: &Vector3<f64>,
) -> (SMatrix<f64, 15, 15>, SVector<f64, 15>) {
    let mut f = SMatrix::<f64, 15, 15>::zeros();
    f.fixed_view_mut::<9, 9>(0, 0)
        .copy_from(&nav_error_dynamics(earth, nav, f_ned));
    let c = *c_bn;
    f.fixed_view_mut::<3, 3>(ATT, GYRO_BIAS).copy_from(&(-c));
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
    let mut q = SVector::<f64, 15>::zeros();
    for i in 0..3 {
        f[(GYRO_BIAS + i, GYRO_BIAS + i)] = fg;
        f[(ACCEL_BIAS + i, ACCEL_BIAS + i)] = fa;
        q[ATT + i] = spec.gyro_arw * spec.gyro_arw;
        q[VEL + i] = spec.accel_vrw * spec.accel_vrw;
        q[GYRO_BIAS + i] = qg;
        q[ACCEL_BIAS + i] = qa;
    }
    (f, q)
}

/// `(−1/τ, 2σ²/τ)` of a Gauss-Markov process, or `(0, 0)` (random constant).
pub(super) fn markov(enabled: bool, sigma: f64, tau: f64) -> (f64, f64) {
    if enabled {
        (-1.0 / tau, 2.0 * sigma * sigma / tau)
    } else {
        (0.0, 0.0)
    }
}
