//! The error models of an inertial system alone, built once for every state
//! layout: the navigation errors `[φ, δv, δr]` driven by gyro and
//! accelerometer errors that sit where an [`InertialLayout`] says.

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

/// Where the sensor errors sit in an inertial error state whose first nine
/// components are `[φ, δv, δr]` ([`ATT`], [`VEL`], [`POS`]); implemented
/// by [`Ins15Model`](super::Ins15Model) and
/// [`Ins18Model`](super::Ins18Model), whose constructors it drives.
///
/// ```
/// use kestrel_nav::error_model::{Ins15Model, Ins18Model, InertialLayout};
/// assert_eq!(<Ins15Model as InertialLayout>::GYRO_CONST, None);
/// assert_eq!(<Ins18Model as InertialLayout>::GYRO_CONST, Some(9));
/// assert_eq!(<Ins18Model as InertialLayout>::GYRO_BIAS, 12);
/// ```
pub trait InertialLayout {
    /// First index of the gyro bias (body, rad/s): a first-order
    /// Gauss-Markov process when the spec has one, otherwise a random walk
    /// of the spec's `gyro_bias_rw` (a random constant when that is 0).
    const GYRO_BIAS: usize;
    /// First index of a second gyro error that is always a random constant
    /// (body, rad/s; the gyro error is then the sum of both), if any.
    const GYRO_CONST: Option<usize>;
    /// First index of the accelerometer bias (body, m/s²): Gauss-Markov when
    /// the spec has one, otherwise a random walk of `accel_bias_rw` (a
    /// random constant when 0).
    const ACCEL_BIAS: usize;
}

impl<const N: usize> ErrorStateModel<N>
where
    Self: InertialLayout,
{
    /// The model over `dt` seconds linearised at `nav` with the specific
    /// force `f_ned` (m/s², NED; the mean over the interval when the model
    /// spans several IMU samples, see [`ForcingMean`]), from
    /// [`continuous`](Self::continuous).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
    /// use kestrel_nav::error_model::{Ins15Model, ins15::{ATT, GYRO_BIAS}};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    ///     Euler::default());
    /// let spec = ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1);
    /// let m = Ins15Model::new(&Ellipsoid::wgs84(), &spec, &nav, &Vector3::new(0.0, 0.0, -9.79), 0.1);
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
        let (f, q) = Self::continuous(earth, spec, nav, f_ned);
        Self::from_continuous(f, q, dt)
    }

    /// The model over the interval summarised by `mean` (its length, mean
    /// specific force and mean `C_b^n`), with the position and velocity of
    /// `nav` (the solution at the start or middle of the interval).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown,
    ///     nalgebra::Vector3};
    /// use kestrel_nav::error_model::{Ins15Model, Ins18Model, ForcingMean};
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
    /// let m = Ins15Model::from_mean(&earth, &ImuSpec::perfect(), &s, &mean);
    /// assert!((m.dt() - 0.1).abs() < 1e-15);
    /// let m = Ins18Model::from_mean(&earth, &ImuSpec::perfect(), &s, &mean);
    /// assert!((m.dt() - 0.1).abs() < 1e-15);
    /// ```
    pub fn from_mean(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        mean: &ForcingMean,
    ) -> Self {
        let (f, q) = Self::continuous_with(earth, spec, nav, &mean.c_bn(), &mean.f_ned());
        Self::from_continuous(f, q, mean.dt())
    }

    /// The continuous `F` and noise densities of the model at `nav` (sensor
    /// errors mapped by the attitude of `nav`), also for models that extend
    /// these states (place them in the top-left corner).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
    /// use kestrel_nav::error_model::{ins18, ins15, Ins15Model, Ins18Model};
    /// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(),
    ///     Euler::from_degrees(0.0, 0.0, 90.0));
    /// let (earth, spec, f) = (Ellipsoid::wgs84(), ImuSpec::perfect(), Vector3::zeros());
    /// // Yaw 90°: body x points east, so a gyro x bias tilts about east.
    /// let (f15, _) = Ins15Model::continuous(&earth, &spec, &nav, &f);
    /// assert!((f15[(ins15::ATT + 1, ins15::GYRO_BIAS)] + 1.0).abs() < 1e-15);
    /// let (f18, _) = Ins18Model::continuous(&earth, &spec, &nav, &f);
    /// assert!((f18[(ins18::ATT + 1, ins18::GYRO_CONST)] + 1.0).abs() < 1e-15);
    /// ```
    pub fn continuous(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        f_ned: &Vector3<f64>,
    ) -> (SMatrix<f64, N, N>, SVector<f64, N>) {
        let c = nav.att.to_rotation_matrix().into_inner();
        Self::continuous_with(earth, spec, nav, &c, f_ned)
    }

    /// [`continuous`](Self::continuous) with the body-frame sensor errors
    /// mapped by `c_bn` instead of the attitude of `nav`, typically the mean
    /// over the interval ([`ForcingMean::c_bn`]).
    ///
    /// Dynamics: the navigation block of [`nav_error_dynamics`], every gyro
    /// error into attitude through `−C_b^n`, the accelerometer bias into
    /// velocity through `C_b^n`. A Gauss-Markov bias follows `ḃ = −b/τ + w`
    /// with density `2σ²/τ`; otherwise a random-walk bias `ḃ = w` has
    /// density `rw²`. Noise densities: `ARW²` on φ and `VRW²` on δv
    /// (the rotation `C_b^n` drops out because the spec is the same on every
    /// axis).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::{Matrix3, Vector3}};
    /// use kestrel_nav::error_model::{ins18::{ATT, GYRO_CONST, GYRO_MARKOV}, Ins15Model,
    ///     Ins18Model};
    /// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// let (earth, c, f) = (Ellipsoid::wgs84(), Matrix3::identity(), Vector3::zeros());
    /// let spec = ImuSpec::perfect().with_accel_vrw_m_s_per_sqrt_h(0.06);
    /// let (_, q) = Ins15Model::continuous_with(&earth, &spec, &nav, &c, &f);
    /// assert!((q[3] - 1e-6).abs() < 1e-18);
    /// let (f, _) = Ins18Model::continuous_with(&earth, &ImuSpec::perfect(), &nav, &c, &f);
    /// // Both gyro drifts enter the attitude error the same way.
    /// assert_eq!(f[(ATT, GYRO_CONST)], f[(ATT, GYRO_MARKOV)]);
    /// ```
    pub fn continuous_with(
        earth: &Ellipsoid,
        spec: &ImuSpec,
        nav: &NavState,
        c_bn: &Matrix3<f64>,
        f_ned: &Vector3<f64>,
    ) -> (SMatrix<f64, N, N>, SVector<f64, N>) {
        let (gyro, accel) = (Self::GYRO_BIAS, Self::ACCEL_BIAS);
        let mut f = SMatrix::<f64, N, N>::zeros();
        f.fixed_view_mut::<9, 9>(0, 0)
            .copy_from(&nav_error_dynamics(earth, nav, f_ned));
        let c = *c_bn;
        if let Some(k) = Self::GYRO_CONST {
            f.fixed_view_mut::<3, 3>(ATT, k).copy_from(&(-c));
        }
        f.fixed_view_mut::<3, 3>(ATT, gyro).copy_from(&(-c));
        f.fixed_view_mut::<3, 3>(VEL, accel).copy_from(&c);
        let (fg, qg) = bias_process(
            spec.has_gyro_markov(),
            spec.gyro_markov_sigma,
            spec.gyro_markov_tau,
            spec.gyro_bias_rw,
        );
        let (fa, qa) = bias_process(
            spec.has_accel_markov(),
            spec.accel_markov_sigma,
            spec.accel_markov_tau,
            spec.accel_bias_rw,
        );
        let mut q = SVector::<f64, N>::zeros();
        for i in 0..3 {
            f[(gyro + i, gyro + i)] = fg;
            f[(accel + i, accel + i)] = fa;
            q[ATT + i] = spec.gyro_arw * spec.gyro_arw;
            q[VEL + i] = spec.accel_vrw * spec.accel_vrw;
            q[gyro + i] = qg;
            q[accel + i] = qa;
        }
        (f, q)
    }
}

/// `F` and `q` of a bias state: first-order Gauss-Markov when `markov`
/// (`−1/τ`, `2σ²/τ`), otherwise a random walk of density `rw` (`0`, `rw²`;
/// a random constant for `rw = 0`).
fn bias_process(markov: bool, sigma: f64, tau: f64, rw: f64) -> (f64, f64) {
    if markov {
        (-1.0 / tau, 2.0 * sigma * sigma / tau)
    } else {
        (0.0, rw * rw)
    }
}
