//! Helpers shared by the adapter tests: seeded noise, a planar
//! constant-velocity target observed in position, measurement streams with
//! outliers, a changed noise level or an unmodelled jump, a runner that
//! works with every form in `f32` and `f64`, matrix checks, and the
//! helpers of hand-computed epochs ([`hand`]).
//!
//! Each test binary uses only part of this module.
#![allow(dead_code)]

pub mod cv;
#[macro_use]
pub mod hand;

use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::form::{PredictForm, UpdateForm};
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{Ekf, Filter, Real, SrUkf, Ukf};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// A deterministic generator for `seed`.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A vector of independent standard normal entries.
pub fn normal<const R: usize>(rng: &mut ChaCha8Rng) -> SVector<f64, R> {
    SVector::from_fn(|_, _| rng.sample(StandardNormal))
}

/// Converts an `f64` value to `T`.
pub fn to<T: Real>(v: f64) -> T {
    kestrel_core::real::lit(v)
}

/// Converts a `T` value to `f64`.
pub fn from<T: Real>(v: T) -> f64 {
    kestrel_core::nalgebra::try_convert(v).unwrap_or(f64::NAN)
}

/// A matrix in `f64`.
pub fn mat64<T: Real, const R: usize, const C: usize>(m: &SMatrix<T, R, C>) -> SMatrix<f64, R, C> {
    m.map(from)
}

/// A covariance-form filter (batch updates whenever an adapter is present).
pub fn ekf<T: Real, const N: usize>(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Ekf<T, N> {
    Ekf::new(x0, p0).expect("finite initial state")
}

/// An unscented filter with the default sigma points.
pub fn ukf<T: Real, const N: usize>(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Ukf<T, N> {
    Ukf::new(x0, p0).expect("finite initial state")
}

/// A square-root unscented filter with the default sigma points.
pub fn sr_ukf<T: Real, const N: usize>(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> SrUkf<T, N> {
    SrUkf::new(x0, p0).expect("PSD initial covariance")
}

/// Calls `$run(name, constructor $(, args)*)` for the EKF, UKF and SR-UKF
/// of the [`cv`] state size, in `f64` and in `f32`. `$run` takes
/// `fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>` and is generic
/// over whichever of `T` and `F` it needs.
#[macro_export]
macro_rules! each_form {
    ($run:ident $(, $arg:expr)* $(,)?) => {{
        $crate::each_form_f64!($run $(, $arg)*);
        $run("EKF f32", $crate::support::ekf::<f32, { $crate::support::cv::N }> $(, $arg)*);
        $run("UKF f32", $crate::support::ukf::<f32, { $crate::support::cv::N }> $(, $arg)*);
        $run("SR-UKF f32", $crate::support::sr_ukf::<f32, { $crate::support::cv::N }> $(, $arg)*);
    }};
}

/// The same, in `f64` only.
#[macro_export]
macro_rules! each_form_f64 {
    ($run:ident $(, $arg:expr)* $(,)?) => {{
        $run("EKF", $crate::support::ekf::<f64, { $crate::support::cv::N }> $(, $arg)*);
        $run("UKF", $crate::support::ukf::<f64, { $crate::support::cv::N }> $(, $arg)*);
        $run("SR-UKF", $crate::support::sr_ukf::<f64, { $crate::support::cv::N }> $(, $arg)*);
    }};
}

/// A filter constructor of the [`cv`] state size in `f64`, as the
/// [`each_form_f64`] runner passes it.
pub type Make<F> =
    fn(SVector<f64, { cv::N }>, SMatrix<f64, { cv::N }, { cv::N }>) -> Filter<f64, { cv::N }, F>;

/// A form that runs the linear models of [`cv`].
pub trait CvForm<T: Real>: PredictForm<T, { cv::N }, kestrel_models::LinearProcess<T, { cv::N }>>
    + UpdateForm<T, { cv::N }, kestrel_models::LinearMeasurement<T, { cv::N }, { cv::M }>, { cv::M }>
{
}

impl<T: Real, F> CvForm<T> for F where
    F: PredictForm<T, { cv::N }, kestrel_models::LinearProcess<T, { cv::N }>>
        + UpdateForm<
            T,
            { cv::N },
            kestrel_models::LinearMeasurement<T, { cv::N }, { cv::M }>,
            { cv::M },
        >
{
}

/// Whether `p` is exactly symmetric and an independent Cholesky
/// factorisation (nalgebra's, in `f64`) succeeds.
pub fn symmetric_pd<T: Real, const N: usize>(p: &SMatrix<T, N, N>) -> bool {
    let p = mat64(p);
    p == p.transpose() && p.iter().all(|v| v.is_finite()) && p.cholesky().is_some()
}

/// The root mean square of `errors`.
pub fn rms(errors: &[f64]) -> f64 {
    (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt()
}

/// Runs `filter` over `stream` (predict with `dt = 1`, update), returning the
/// position error norm after each update, or the first error. `check` sees
/// every update's report and the filter after it.
pub fn run<T: Real, F: CvForm<T>, A: NoiseAdapter<T, { cv::M }>>(
    filter: &mut Filter<T, { cv::N }, F, A>,
    stream: &cv::Stream,
    sensor: &kestrel_models::LinearMeasurement<T, { cv::N }, { cv::M }>,
    mut check: impl FnMut(
        usize,
        &kestrel_core::UpdateReport<T, { cv::M }, A::Report>,
        &Filter<T, { cv::N }, F, A>,
    ),
) -> Result<Vec<f64>, kestrel_core::FilterError> {
    run_detailed(filter, stream, sensor, |k, d, f| check(k, &d.report, f))
}

/// As [`run`], `check` seeing every update's detail (its matrices too).
pub fn run_detailed<T: Real, F: CvForm<T>, A: NoiseAdapter<T, { cv::M }>>(
    filter: &mut Filter<T, { cv::N }, F, A>,
    stream: &cv::Stream,
    sensor: &kestrel_models::LinearMeasurement<T, { cv::N }, { cv::M }>,
    mut check: impl FnMut(
        usize,
        &kestrel_core::UpdateDetail<T, { cv::M }, A::Report>,
        &Filter<T, { cv::N }, F, A>,
    ),
) -> Result<Vec<f64>, kestrel_core::FilterError> {
    let process = cv::process::<T>(stream.q);
    let mut errors = Vec::with_capacity(stream.z.len());
    for (k, (z, truth)) in stream.z.iter().zip(&stream.truth).enumerate() {
        filter.predict(&process, T::one())?;
        let detail = filter.update_detailed(sensor, &z.map(to::<T>))?;
        check(k, &detail, filter);
        let x = filter.state().map(from);
        errors.push((x.fixed_rows::<2>(0) - truth.fixed_rows::<2>(0)).norm());
    }
    Ok(errors)
}

/// Consistency after an unmodelled step change at epoch `jump`, judged from
/// the NIS of `m`-dimensional innovations (`nis[k]` for epoch `k`): the
/// first epoch after the jump whose NIS is inside its 95 % bound
/// `χ²_0.95(m)`, and the mean NIS over the 10 epochs `jump + 11 ..= jump + 20`
/// with the 95 % bound of such a mean, `χ²_0.95(10 m) / 10`.
pub fn recovery(nis: &[f64], jump: usize, m: usize) -> Recovery {
    let single = chi_square_upper(m);
    let window = chi_square_upper(10 * m) / 10.0;
    Recovery {
        first_inside: (1..=20).find(|j| nis[jump + j] <= single),
        window_mean: nis[jump + 11..=jump + 20].iter().sum::<f64>() / 10.0,
        window_bound: window,
    }
}

/// The step-change stream: `jump + 100` epochs of the [`cv`] target with
/// `R = I` and `q = 10⁻⁴`, whose true position jumps by (30, −30) (30 σ per
/// axis) at epoch `jump`.
pub fn jump_stream(jump: usize) -> cv::Stream {
    let mut spec = cv::Spec::new(5, jump + 100, kestrel_core::nalgebra::Matrix2::identity())
        .with_jump(
            jump,
            kestrel_core::nalgebra::Vector4::new(30.0, -30.0, 0.0, 0.0),
        );
    spec.q = 1e-4;
    cv::stream(&spec)
}

/// Runs the fading `filter` over [`jump_stream`]`(jump)` and asserts that
/// it does not fade before the jump, fades at it (`fade` reads `λ` from the
/// adapter's report), and [`recovery`] says it is back within 20 epochs.
pub fn assert_fades_and_recovers<F: CvForm<f64>, A: NoiseAdapter<f64, { cv::M }>>(
    name: &str,
    filter: &mut Filter<f64, { cv::N }, F, A>,
    jump: usize,
    fade: impl Fn(&A::Report) -> f64,
) {
    let mut nis = Vec::new();
    let mut fades = Vec::new();
    let sensor = cv::sensor(&kestrel_core::nalgebra::Matrix2::identity());
    run(filter, &jump_stream(jump), &sensor, |_, r, _| {
        nis.push(r.nis);
        fades.push(fade(&r.adapters));
    })
    .unwrap();
    assert!(
        fades[..jump].iter().all(|l| *l == 1.0),
        "{name}: no fade before the jump"
    );
    assert!(fades[jump] > 1.0, "{name}: λ = {} at the jump", fades[jump]);
    let recovery = recovery(&nis, jump, 2);
    assert!(recovery.recovered(), "{name}: {recovery:?}");
}

/// See [`recovery`].
#[derive(Debug, Clone, Copy)]
pub struct Recovery {
    /// Steps after the jump until the first NIS inside `χ²_0.95(m)`, if
    /// within 20.
    pub first_inside: Option<usize>,
    /// Mean NIS over epochs `jump + 11 ..= jump + 20`.
    pub window_mean: f64,
    /// Its 95 % bound.
    pub window_bound: f64,
}

impl Recovery {
    /// Whether the filter is back inside both bounds within 20 steps.
    pub fn recovered(&self) -> bool {
        self.first_inside.is_some() && self.window_mean <= self.window_bound
    }
}

/// `χ²_0.95(dof)`, from statrs directly.
pub fn chi_square_upper(dof: usize) -> f64 {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    ChiSquared::new(dof as f64)
        .expect("dof > 0")
        .inverse_cdf(0.95)
}

/// Epochs left out of state RMS figures (the initial transient).
pub const BURN_IN: usize = 100;

/// The outlier benchmark stream: 2000 epochs of the [`cv`] target with
/// `R = I`, `q = 0.01`, and 5 % outliers of ±20 σ per component. Its
/// [`cv::Stream::without_outliers`] is the same truth measured cleanly.
pub fn outlier_stream(seed: u64) -> cv::Stream {
    cv::stream(
        &cv::Spec::new(seed, 2000, kestrel_core::nalgebra::Matrix2::identity())
            .with_outliers(0.05, 20.0),
    )
}

/// The RMS position error after [`BURN_IN`].
pub fn position_rms(errors: &[f64]) -> f64 {
    rms(&errors[BURN_IN..])
}
