//! Error-state systems: which error model the engine propagates and where
//! its sensor-error states sit.

use nalgebra::{SMatrix, Vector3};

use crate::earth::Ellipsoid;
use crate::error_model::{ins15, ins21, ForcingMean, Ins15Model, Ins18Model, Ins21Model};
use crate::imu_spec::ImuSpec;
use crate::measurement::ErrorLayout;
use crate::state::NavState;

/// An error-state system of `N` states: its layout (for measurements and
/// feedback), the process model over one covariance-propagation interval
/// and the initial covariance.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::Vector3};
/// use kestrel_nav::engine::{ErrorSystem, Ins15, InitialUncertainty};
/// use kestrel_nav::error_model::ForcingMean;
/// let sys = Ins15::new(ImuSpec::perfect().with_gyro_bias_deg_per_h(1.0));
/// let p0 = sys.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
/// assert!((p0[(9, 9)].sqrt() - 1.0_f64.to_radians() / 3600.0).abs() < 1e-15);
/// let nav = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let model = sys.process(&Ellipsoid::wgs84(), &nav, &ForcingMean::default());
/// assert_eq!(model.dt(), 0.0);
/// ```
pub trait ErrorSystem<const N: usize>: ErrorLayout<N> {
    /// The process model (for any filter scalar).
    type Process;

    /// The process model over the interval summarised by `forcing` (its
    /// duration, mean specific force and mean attitude), with the position
    /// and velocity of `nav` (the solution at the end of the interval).
    fn process(&self, earth: &Ellipsoid, nav: &NavState, forcing: &ForcingMean) -> Self::Process;

    /// A diagonal initial covariance: the navigation errors from `nav`, the
    /// sensor errors from the system's own specification.
    fn initial_covariance(&self, nav: &InitialUncertainty) -> SMatrix<f64, N, N>;
}

/// Initial standard deviations of the navigation errors (NED components).
///
/// ```
/// let u = kestrel_nav::engine::InitialUncertainty::new(0.01, 0.1, 5.0);
/// assert_eq!(u.pos.z, 5.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialUncertainty {
    /// Attitude error, rad.
    pub att: Vector3<f64>,
    /// Velocity error, m/s.
    pub vel: Vector3<f64>,
    /// Position error, m.
    pub pos: Vector3<f64>,
}

impl InitialUncertainty {
    /// The same standard deviation on the three axes of each (rad, m/s, m).
    ///
    /// ```
    /// let u = kestrel_nav::engine::InitialUncertainty::new(0.02, 0.3, 5.0);
    /// assert_eq!(u.att.y, 0.02);
    /// ```
    pub fn new(att: f64, vel: f64, pos: f64) -> Self {
        Self {
            att: Vector3::repeat(att),
            vel: Vector3::repeat(vel),
            pos: Vector3::repeat(pos),
        }
    }

    /// Writes the variances into the first nine diagonal entries.
    pub(crate) fn fill<const N: usize>(&self, p: &mut SMatrix<f64, N, N>) {
        for i in 0..3 {
            p[(i, i)] = self.att[i] * self.att[i];
            p[(3 + i, 3 + i)] = self.vel[i] * self.vel[i];
            p[(6 + i, 6 + i)] = self.pos[i] * self.pos[i];
        }
    }
}

/// Sets the three diagonal entries of the block at `first` to `sigma²`.
pub(crate) fn fill_block<const N: usize>(p: &mut SMatrix<f64, N, N>, first: usize, sigma: f64) {
    for i in first..first + 3 {
        p[(i, i)] = sigma * sigma;
    }
}

/// The 15-state system `[φ, δv, δr, b_g, b_a]` of
/// [`Ins15Model`] for an IMU of specification `spec`.
///
/// ```
/// use kestrel_nav::ImuSpec;
/// use kestrel_nav::engine::Ins15;
/// use kestrel_nav::measurement::ErrorLayout;
/// assert_eq!(<Ins15 as ErrorLayout<15>>::GYRO_BIAS, &[9]);
/// let _ = Ins15::new(ImuSpec::perfect());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ins15 {
    /// The IMU specification (noise densities, bias models, initial biases).
    pub spec: ImuSpec,
}

impl Ins15 {
    /// The system for an IMU of specification `spec`.
    ///
    /// ```
    /// let s = kestrel_nav::engine::Ins15::new(kestrel_nav::ImuSpec::perfect());
    /// assert_eq!(s.spec.gyro_bias, 0.0);
    /// ```
    pub fn new(spec: ImuSpec) -> Self {
        Self { spec }
    }
}

impl ErrorLayout<15> for Ins15 {
    const GYRO_BIAS: &'static [usize] = &[ins15::GYRO_BIAS];
    const ACCEL_BIAS: &'static [usize] = &[ins15::ACCEL_BIAS];
}

impl ErrorSystem<15> for Ins15 {
    type Process = Ins15Model;

    fn process(&self, earth: &Ellipsoid, nav: &NavState, forcing: &ForcingMean) -> Ins15Model {
        Ins15Model::from_mean(earth, &self.spec, nav, forcing)
    }

    fn initial_covariance(&self, nav: &InitialUncertainty) -> SMatrix<f64, 15, 15> {
        let mut p = SMatrix::zeros();
        nav.fill(&mut p);
        fill_biases(&mut p, &self.spec, ins15::GYRO_BIAS, ins15::ACCEL_BIAS);
        p
    }
}

/// The 18-state system `[φ, δv, δr, ε_c, ε_r, ∇]` of papers 000 and 004
/// ([`Ins18Model`]).
///
/// ```
/// use kestrel_nav::ImuSpec;
/// use kestrel_nav::engine::Ins18;
/// use kestrel_nav::measurement::ErrorLayout;
/// assert_eq!(<Ins18 as ErrorLayout<18>>::GYRO_BIAS, &[9, 12]);
/// let _ = Ins18::new(ImuSpec::perfect());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ins18 {
    /// The IMU specification.
    pub spec: ImuSpec,
}

impl Ins18 {
    /// The system for an IMU of specification `spec`.
    ///
    /// ```
    /// let s = kestrel_nav::engine::Ins18::new(kestrel_nav::ImuSpec::perfect());
    /// assert_eq!(s.spec.accel_bias, 0.0);
    /// ```
    pub fn new(spec: ImuSpec) -> Self {
        Self { spec }
    }
}

impl ErrorLayout<18> for Ins18 {
    const GYRO_BIAS: &'static [usize] = &[
        crate::error_model::ins18::GYRO_CONST,
        crate::error_model::ins18::GYRO_MARKOV,
    ];
    const ACCEL_BIAS: &'static [usize] = &[crate::error_model::ins18::ACCEL_BIAS];
}

impl ErrorSystem<18> for Ins18 {
    type Process = Ins18Model;

    fn process(&self, earth: &Ellipsoid, nav: &NavState, forcing: &ForcingMean) -> Ins18Model {
        Ins18Model::from_mean(earth, &self.spec, nav, forcing)
    }

    fn initial_covariance(&self, nav: &InitialUncertainty) -> SMatrix<f64, 18, 18> {
        use crate::error_model::ins18::{ACCEL_BIAS, GYRO_CONST, GYRO_MARKOV};
        let mut p = SMatrix::zeros();
        nav.fill(&mut p);
        let s = &self.spec;
        fill_block(&mut p, GYRO_CONST, s.gyro_bias);
        fill_block(
            &mut p,
            GYRO_MARKOV,
            markov_var(s.has_gyro_markov(), s.gyro_markov_sigma).sqrt(),
        );
        let accel =
            (s.accel_bias.powi(2) + markov_var(s.has_accel_markov(), s.accel_markov_sigma)).sqrt();
        fill_block(&mut p, ACCEL_BIAS, accel);
        p
    }
}

/// The 21-state system `[φ, δv, δr, b_g, b_a, s_g, s_a]` of
/// [`Ins21Model`]: the 15 states plus gyro and accelerometer scale-factor
/// errors, random constants or (finite `scale_tau`) first-order
/// Gauss-Markov processes of steady-state σ `spec.gyro_scale`,
/// `spec.accel_scale`. Their initial σ are those of the spec too.
///
/// ```
/// use kestrel_nav::ImuSpec;
/// use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins21};
/// use kestrel_nav::measurement::ErrorLayout;
/// assert_eq!(<Ins21 as ErrorLayout<21>>::GYRO_SCALE, Some(15));
/// let s = Ins21::new(ImuSpec::perfect().with_accel_scale_ppm(500.0), f64::INFINITY);
/// let p0 = s.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
/// assert!((p0[(18, 18)].sqrt() - 5e-4).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ins21 {
    /// The IMU specification; `gyro_scale`, `accel_scale` are the σ of the
    /// scale-factor errors.
    pub spec: ImuSpec,
    /// Correlation time of the scale-factor errors, s (infinite: random
    /// constants).
    pub scale_tau: f64,
}

impl Ins21 {
    /// The system for an IMU of specification `spec` with scale-factor
    /// correlation time `scale_tau` (s; `f64::INFINITY` for constants).
    ///
    /// ```
    /// let s = kestrel_nav::engine::Ins21::new(kestrel_nav::ImuSpec::perfect(), 3600.0);
    /// assert_eq!(s.scale_tau, 3600.0);
    /// ```
    pub fn new(spec: ImuSpec, scale_tau: f64) -> Self {
        Self { spec, scale_tau }
    }
}

impl ErrorLayout<21> for Ins21 {
    const GYRO_BIAS: &'static [usize] = &[ins21::GYRO_BIAS];
    const ACCEL_BIAS: &'static [usize] = &[ins21::ACCEL_BIAS];
    const GYRO_SCALE: Option<usize> = Some(ins21::GYRO_SCALE);
    const ACCEL_SCALE: Option<usize> = Some(ins21::ACCEL_SCALE);
}

impl ErrorSystem<21> for Ins21 {
    type Process = Ins21Model;

    fn process(&self, earth: &Ellipsoid, nav: &NavState, forcing: &ForcingMean) -> Ins21Model {
        Ins21Model::from_mean_scaled(earth, &self.spec, self.scale_tau, nav, forcing)
    }

    fn initial_covariance(&self, nav: &InitialUncertainty) -> SMatrix<f64, 21, 21> {
        let mut p = SMatrix::zeros();
        nav.fill(&mut p);
        let s = &self.spec;
        fill_biases(&mut p, s, ins21::GYRO_BIAS, ins21::ACCEL_BIAS);
        fill_block(&mut p, ins21::GYRO_SCALE, s.gyro_scale);
        fill_block(&mut p, ins21::ACCEL_SCALE, s.accel_scale);
        p
    }
}

/// The single gyro and accelerometer bias blocks at `gyro` and `accel`:
/// the turn-on σ and the Markov σ combined.
fn fill_biases<const N: usize>(p: &mut SMatrix<f64, N, N>, s: &ImuSpec, gyro: usize, accel: usize) {
    let g = (s.gyro_bias.powi(2) + markov_var(s.has_gyro_markov(), s.gyro_markov_sigma)).sqrt();
    let a = (s.accel_bias.powi(2) + markov_var(s.has_accel_markov(), s.accel_markov_sigma)).sqrt();
    fill_block(p, gyro, g);
    fill_block(p, accel, a);
}

/// The steady-state variance of a Markov process, or 0 when absent.
pub(crate) fn markov_var(enabled: bool, sigma: f64) -> f64 {
    if enabled {
        sigma * sigma
    } else {
        0.0
    }
}
