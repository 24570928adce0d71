//! The 16-state SINS/odometer error system: the 15 INS error states plus
//! the odometer scale-factor error.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::earth::Ellipsoid;
use crate::engine::{ErrorSystem, InitialUncertainty, Ins15};
use crate::error_model::{ErrorStateModel, ForcingMean, Ins15Model};
use crate::imu_spec::ImuSpec;
use crate::measurement::ErrorLayout;
use crate::state::NavState;

/// Index of the odometer scale-factor error in the 16-state system.
pub const ODOMETER_SCALE: usize = 15;

/// The odometer scale-factor error as a first-order Gauss-Markov process
/// `δk̇ = −δk / τ + w`, `E[w²] = 2σ²/τ`, with an initial standard deviation.
///
/// ```
/// let p = kestrel_nav::odometer::ScaleFactorProcess::as_published();
/// assert_eq!(p.tau, 3600.0);
/// assert_eq!(p.initial_std, 0.005);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaleFactorProcess {
    /// Correlation time, s.
    pub tau: f64,
    /// Steady-state standard deviation (ratio).
    pub sigma: f64,
    /// Standard deviation of the initial scale-factor error (ratio).
    pub initial_std: f64,
}

impl ScaleFactorProcess {
    /// A process with correlation time `tau` (s), steady-state σ `sigma`
    /// and initial σ `initial_std` (ratios).
    ///
    /// ```
    /// let p = kestrel_nav::odometer::ScaleFactorProcess::new(1000.0, 1e-3, 1e-2);
    /// assert_eq!(p.sigma, 1e-3);
    /// ```
    pub fn new(tau: f64, sigma: f64, initial_std: f64) -> Self {
        Self {
            tau,
            sigma,
            initial_std,
        }
    }

    /// The published model (Xu, Zhou and Wang, *Application of Fuzzy Adaptive
    /// Kalman Filtering Algorithm in SINS/DR Integrated Navigation*,
    /// Ordnance Industry Automation, 2024; paper 003 in
    /// `crates/core/REFERENCES.md`): τ = 3600 s, the 0.5 % constant error as the initial σ and
    /// the 0.05 % random error as the steady-state σ. (A steady-state σ as
    /// large as the constant part would let the estimate wander along the
    /// direction the odometer cannot tell from an along-track INS velocity
    /// error on long straight legs.)
    ///
    /// ```
    /// let p = kestrel_nav::odometer::ScaleFactorProcess::as_published();
    /// assert_eq!((p.sigma, p.initial_std), (0.0005, 0.005));
    /// ```
    pub fn as_published() -> Self {
        Self::new(3600.0, 0.0005, 0.005)
    }
}

/// The 16-state system `[φ, δv, δr, b_g, b_a, δk]`: the 15-state model of
/// [`Ins15`] (same `F`, same noise) and the odometer scale-factor error
/// `δk` at index [`ODOMETER_SCALE`], decoupled in `F` (`F₁₅,₁₅ = −1/τ`,
/// density `2σ²/τ`). It couples to the rest only through the odometer
/// measurement.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::{Matrix3, Vector3}};
/// use kestrel_nav::error_model::ForcingMean;
/// use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess, ODOMETER_SCALE};
/// let sys = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
/// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0), Vector3::zeros(),
///     Euler::default());
/// let model = sys.model(&Ellipsoid::wgs84(), &nav, &Matrix3::identity(), &Vector3::zeros(), 1.0);
/// assert_eq!(model.f()[(ODOMETER_SCALE, ODOMETER_SCALE)], -1.0 / 3600.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InsOdometer16 {
    /// The IMU specification.
    pub spec: ImuSpec,
    /// The odometer scale-factor process.
    pub scale: ScaleFactorProcess,
}

impl InsOdometer16 {
    /// The system for an IMU `spec` and odometer scale process `scale`.
    ///
    /// ```
    /// use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess};
    /// let s = InsOdometer16::new(kestrel_nav::ImuSpec::perfect(), ScaleFactorProcess::as_published());
    /// assert_eq!(s.scale.tau, 3600.0);
    /// ```
    pub fn new(spec: ImuSpec, scale: ScaleFactorProcess) -> Self {
        Self { spec, scale }
    }

    /// The model over `dt` s at `nav` with specific force `f_ned` (m/s²)
    /// and attitude `c_bn` (`C_b^n`, maps the body-frame sensor errors).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::nalgebra::{Matrix3, Vector3};
    /// use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess, ODOMETER_SCALE};
    /// let sys = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
    /// let nav = NavState::new(0.0, Geodetic::new(0.6, 2.1, 0.0), Vector3::zeros(), Euler::default());
    /// let m = sys.model(&Ellipsoid::wgs84(), &nav, &Matrix3::identity(), &Vector3::zeros(), 36.0);
    /// let k = ODOMETER_SCALE;
    /// // Φ = 1 − Δt/τ + (Δt/τ)²/2, Q = (Φ² + 1) q Δt / 2 with q = 2σ²/τ.
    /// assert!((m.phi()[(k, k)] - (1.0 - 0.01 + 0.00005)).abs() < 1e-15);
    /// let q = 2.0 * 0.0005f64.powi(2) / 3600.0;
    /// assert!((m.qd()[(k, k)] - (m.phi()[(k, k)].powi(2) + 1.0) * q * 18.0).abs() < 1e-20);
    /// ```
    pub fn model(
        &self,
        earth: &Ellipsoid,
        nav: &NavState,
        c_bn: &Matrix3<f64>,
        f_ned: &Vector3<f64>,
        dt: f64,
    ) -> ErrorStateModel<16> {
        let (f15, q15) = Ins15Model::continuous_with(earth, &self.spec, nav, c_bn, f_ned);
        let mut f = SMatrix::<f64, 16, 16>::zeros();
        f.fixed_view_mut::<15, 15>(0, 0).copy_from(&f15);
        let mut q = SVector::<f64, 16>::zeros();
        q.fixed_rows_mut::<15>(0).copy_from(&q15);
        if self.scale.tau.is_finite() && self.scale.tau > 0.0 {
            f[(ODOMETER_SCALE, ODOMETER_SCALE)] = -1.0 / self.scale.tau;
            q[ODOMETER_SCALE] = 2.0 * self.scale.sigma * self.scale.sigma / self.scale.tau;
        }
        ErrorStateModel::from_continuous(f, q, dt)
    }
}

impl ErrorLayout<16> for InsOdometer16 {
    const GYRO_BIAS: &'static [usize] = <Ins15 as ErrorLayout<15>>::GYRO_BIAS;
    const ACCEL_BIAS: &'static [usize] = <Ins15 as ErrorLayout<15>>::ACCEL_BIAS;
    const ODOMETER_SCALE: Option<usize> = Some(ODOMETER_SCALE);
}

impl ErrorSystem<16> for InsOdometer16 {
    type Process = ErrorStateModel<16>;

    fn process(&self, earth: &Ellipsoid, nav: &NavState, forcing: &ForcingMean) -> Self::Process {
        self.model(earth, nav, &forcing.c_bn(), &forcing.f_ned(), forcing.dt())
    }

    fn initial_covariance(&self, nav: &InitialUncertainty) -> SMatrix<f64, 16, 16> {
        let p15 = Ins15::new(self.spec).initial_covariance(nav);
        let mut p = SMatrix::<f64, 16, 16>::zeros();
        p.fixed_view_mut::<15, 15>(0, 0).copy_from(&p15);
        p[(ODOMETER_SCALE, ODOMETER_SCALE)] = self.scale.initial_std * self.scale.initial_std;
        p
    }
}
