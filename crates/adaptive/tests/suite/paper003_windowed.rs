//! Paper 003, eq. 7–8: `R` from a window of innovations.
//!
//! - A hand-computed four-epoch run through every form (window not yet
//!   full, estimate, estimate, negative estimate floored).
//! - A 2-D projection onto the positive definite matrices by hand.
//! - Convergence to the true, correlated `R` from a wrong model `R` on a
//!   linear system, in every form.
//! - The estimate is symmetric positive definite with eigenvalues at least
//!   the floor for arbitrary innovations and predicted covariances
//!   (proptest, `f32` and `f64`).

use crate::support;

use kestrel_adaptive::{project_spd, symmetric_eigen, WindowedNoise, WindowedNoiseReport};
use kestrel_core::adapter::{GainStep, NoiseAdapter};
use kestrel_core::nalgebra::{Matrix1, Matrix2, Matrix3, SMatrix, SVector, Vector1, Vector2};
use kestrel_core::{Filter, FilterError, Real};
use kestrel_models::{LinearMeasurement, LinearProcess};
use proptest::prelude::*;
use support::hand::close;
use support::{cv, mat64, run_detailed, symmetric_pd, to, CvForm};

/// [`each_hand_form`] from x₀ = 0, P₀ = ½.
macro_rules! each_scalar_form {
    ($($rest:tt)+) => {
        each_hand_form!(Vector1::new(0.0), Matrix1::new(0.5), $($rest)+)
    };
}

#[test]
fn windowed_hand_run() {
    // x⁻ = x + w, Q = ½; z = x + v with model R = 1; x₀ = 0, P₀ = ½; W = 2.
    let process = LinearProcess::new(Matrix1::new(1.0), Matrix1::new(0.5));
    let sensor = LinearMeasurement::new(Matrix1::new(1.0), Matrix1::new(1.0));
    let est = WindowedNoise::<f64, 1, 2>::new(0.01).unwrap();
    each_scalar_form!(est, |name, f| {
        let mut step = |z: f64| {
            f.predict(&process, 1.0).unwrap();
            let detail = f.update_detailed(&sensor, &Vector1::new(z)).unwrap();
            let a: WindowedNoiseReport<f64> = detail.report.adapters;
            (detail, a, f.state()[0], f.covariance()[0])
        };
        // 1: P⁻ = 1, ν = 2; one sample, R = 1 kept: K = ½, x = 1, P = ½.
        let (detail, a, x, p) = step(2.0);
        assert!(!a.estimated && a.samples == 1, "{name}");
        assert_eq!(detail.noise[0], 1.0, "{name}");
        close(x, 1.0, name);
        close(p, 0.5, name);
        // 2: P⁻ = 1, ν = 5 − 1 = 4; Ĉ = (4 + 16)/2 = 10, R = 10 − 1 = 9;
        // K = 1/10, x = 1 + 0.4, P = 1 · 9/10.
        let (detail, a, x, p) = step(5.0);
        assert!(a.estimated && a.samples == 2 && a.raised == 0, "{name}");
        close(detail.noise[0], 9.0, name);
        close(a.min_eigenvalue, 9.0, name);
        close(x, 1.4, name);
        close(p, 0.9, name);
        // 3: P⁻ = 1.4, ν = 0; Ĉ = (16 + 0)/2 = 8, R = 8 − 1.4 = 6.6;
        // K = 1.4/8, x = 1.4, P = 1.4 · 6.6/8 = 1.155.
        let (detail, _, x, p) = step(1.4);
        close(detail.noise[0], 6.6, name);
        close(x, 1.4, name);
        close(p, 1.155, name);
        // 4: P⁻ = 1.655, ν = 0.5; Ĉ = (0 + 0.25)/2 = 0.125,
        // R = 0.125 − 1.655 = −1.53 → floored at 0.01; C = 1.665.
        let (detail, a, x, p) = step(1.9);
        assert_eq!(a.raised, 1, "{name}");
        assert_eq!(a.floor, 0.01, "{name}: the configured floor dominates");
        close(a.min_eigenvalue, -1.53, name);
        close(detail.noise[0], 0.01, name);
        close(x, 1.4 + 0.5 * 1.655 / 1.665, name);
        close(p, 1.655 * 0.01 / 1.665, name);
    });
}

#[test]
fn projection_by_hand() {
    // W = 2, ν₁ = (1, 1), ν₂ = (1, −1): Ĉ = I. H P⁻ Hᵀ = ½ [1 1; 1 1]:
    // Ĉ − H P⁻ Hᵀ = ½ [1 −1; −1 1], eigenvalues 0 along (1, 1)/√2 and 1
    // along (1, −1)/√2. Floor 0.1: 0.1 · ½ [1 1; 1 1] + ½ [1 −1; −1 1].
    let mut est = WindowedNoise::<f64, 2, 2>::new(0.1).unwrap();
    let hph = Matrix2::new(0.5, 0.5, 0.5, 0.5);
    let mut report = WindowedNoiseReport::default();
    for nu in [Vector2::new(1.0, 1.0), Vector2::new(1.0, -1.0)] {
        let mut step = GainStep::new(nu, hph, None, Matrix2::identity()).unwrap();
        est.before_gain(&mut step, &mut report);
        if report.estimated {
            let want = Matrix2::new(0.55, -0.45, -0.45, 0.55);
            for (g, w) in step.noise().iter().zip(want.iter()) {
                close(*g, *w, "projected R");
            }
        }
    }
    assert!(report.estimated && report.raised == 1);
    assert!(report.min_eigenvalue.abs() < 1e-15);
    assert_eq!(est.sample_covariance(), Matrix2::identity());

    // A rejected measurement (by an earlier adapter) is not pushed.
    let mut step = GainStep::new(Vector2::new(5.0, 5.0), hph, None, Matrix2::identity()).unwrap();
    step.reject();
    est.before_gain(&mut step, &mut report);
    assert_eq!(est.sample_covariance(), Matrix2::identity());
    assert_eq!(
        *step.noise(),
        Matrix2::identity(),
        "R untouched when rejected"
    );

    // In f32 the floor never goes below the resolution of H P⁻ Hᵀ:
    // Ĉ = 0, H P⁻ Hᵀ = 8 I: f = max(10⁻⁹, 128 · 2 · ε · 16), R = f I.
    let mut est = WindowedNoise::<f32, 2, 1>::new(1e-9).unwrap();
    let mut report = WindowedNoiseReport::default();
    let hph = Matrix2::<f32>::identity() * 8.0;
    let mut step = GainStep::new(Vector2::zeros(), hph, None, Matrix2::identity()).unwrap();
    est.before_gain(&mut step, &mut report);
    let f = 256.0 * f32::EPSILON * 16.0;
    assert_eq!(report.floor, f);
    assert_eq!(report.raised, 2);
    assert_eq!(*step.noise(), Matrix2::identity() * f);

    let bad = |name| Some(name);
    let param = |e: Option<FilterError>| match e {
        Some(FilterError::InvalidParameter { name, .. }) => Some(name),
        _ => None,
    };
    assert_eq!(
        param(WindowedNoise::<f64, 2, 0>::new(1.0).err()),
        bad("window")
    );
    assert_eq!(
        param(WindowedNoise::<f64, 2, 4>::new(0.0).err()),
        bad("min_variance")
    );
    assert_eq!(
        param(WindowedNoise::<f64, 2, 4>::new(f64::INFINITY).err()),
        bad("min_variance")
    );
}

#[test]
fn jacobi_eigen_by_hand_3x3() {
    // [2 −1 0; −1 2 −1; 0 −1 2]: eigenvalues 2 − √2, 2, 2 + √2.
    let a = Matrix3::new(2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0);
    let (values, vectors) = symmetric_eigen(&a).unwrap();
    let mut v: Vec<f64> = values.iter().copied().collect();
    v.sort_by(f64::total_cmp);
    let s = 2.0_f64.sqrt();
    for (got, want) in v.iter().zip([2.0 - s, 2.0, 2.0 + s]) {
        assert!((got - want).abs() < 1e-14, "{got} vs {want}");
    }
    let back = vectors * Matrix3::from_diagonal(&values) * vectors.transpose();
    assert!((back - a).abs().max() < 1e-14);
    assert!(
        (vectors.transpose() * vectors - Matrix3::identity())
            .abs()
            .max()
            < 1e-14
    );
    assert!(symmetric_eigen(&Matrix2::new(f64::NAN, 0.0, 0.0, 1.0)).is_none());
    assert!(project_spd(&Matrix2::<f64>::identity(), 0.0).is_none());
}

/// Runs the estimator (window 50, model `R = I`) on a stream whose true
/// `R` is correlated, and returns the mean `R` used over the last 9000 of
/// 10000 epochs.
fn converges<T: Real, F: CvForm<T>>(
    name: &str,
    make: fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>,
) {
    let truth = Matrix2::new(4.0, 1.0, 1.0, 2.0);
    let stream = cv::stream(&cv::Spec::new(5, 10_000, truth));
    let model = cv::sensor::<T>(&Matrix2::identity());
    let est = WindowedNoise::<T, 2, 50>::new(to(1e-3)).unwrap();
    let mut f = make(cv::x0(), cv::p0()).with_adapter(est);
    let mut sum = Matrix2::<f64>::zeros();
    run_detailed(&mut f, &stream, &model, |k, detail, f| {
        assert_eq!(detail.report.adapters.estimated, k >= 49, "{name} at {k}");
        assert!(symmetric_pd(&detail.noise), "{name}: R at {k}");
        assert!(symmetric_pd(&f.covariance()), "{name}: P at {k}");
        if k >= 1000 {
            sum += mat64(&detail.noise);
        }
    })
    .unwrap();
    let mean = sum / 9000.0;
    // Statistical accuracy: each window has relative spread √(2/50) = 0.2;
    // 9000 epochs hold 180 independent windows, so about 1.5 % relative.
    // 6 % of the diagonal scale is four of those.
    for i in 0..2 {
        for j in 0..2 {
            let scale = (truth[(i, i)] * truth[(j, j)]).sqrt();
            assert!(
                (mean[(i, j)] - truth[(i, j)]).abs() <= 0.06 * scale,
                "{name}: mean R {mean} vs true {truth}"
            );
        }
    }
}

#[test]
fn converges_to_the_true_noise_in_every_form() {
    each_form!(converges);
}

/// A random symmetric positive semi-definite `M × M` matrix `L Lᵀ · scale`.
fn spd<const M: usize>(entries: &[f64], scale: f64) -> SMatrix<f64, M, M> {
    let l = SMatrix::<f64, M, M>::from_fn(|i, j| if j <= i { entries[i * M + j] } else { 0.0 });
    l * l.transpose() * scale
}

/// Feeds `innovations` through a window of 4 and checks every estimate:
/// exactly symmetric, eigenvalues (by nalgebra's own solver, in `f64`) at
/// least the floor up to rounding, and a successful Cholesky factorisation.
fn always_spd<T: Real>(
    innovations: &[[f64; 3]],
    hph: &SMatrix<f64, 3, 3>,
    floor: f64,
) -> Result<(), TestCaseError> {
    let mut est = WindowedNoise::<T, 3, 4>::new(to(floor)).unwrap();
    let mut report = WindowedNoiseReport::default();
    let eps = support::from(kestrel_core::real::epsilon::<T>());
    for (k, nu) in innovations.iter().enumerate() {
        let nu = SVector::<f64, 3>::from(*nu);
        let r0 = SMatrix::<T, 3, 3>::identity();
        let Some(mut step) = GainStep::new(nu.map(to::<T>), hph.map(to::<T>), None, r0) else {
            continue;
        };
        est.before_gain(&mut step, &mut report);
        prop_assert_eq!(report.estimated, k >= 3);
        if !report.estimated {
            continue;
        }
        let r = mat64(step.noise());
        prop_assert!(symmetric_pd(step.noise()), "not SPD: {}", r);
        let values = r.symmetric_eigen().eigenvalues;
        let largest = values.abs().max();
        let slack = 64.0 * eps * largest;
        prop_assert!(
            values.min() >= floor * (1.0 - 1e-6) - slack,
            "eigenvalues {} below floor {}",
            values,
            floor
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn estimate_is_always_spd(
        innovations in proptest::collection::vec(proptest::array::uniform3(-1.0..1.0_f64), 4..12),
        nu_scale in prop_oneof![Just(1e-3), Just(1.0), Just(1e3)],
        entries in proptest::array::uniform9(-1.0..1.0_f64),
        hph_scale in prop_oneof![Just(1e-3), Just(1.0), Just(1e3)],
        floor in prop_oneof![Just(1e-9), Just(1e-4), Just(1e-2), Just(1.0)],
    ) {
        let innovations: Vec<[f64; 3]> =
            innovations.iter().map(|v| v.map(|x| x * nu_scale)).collect();
        let hph = spd::<3>(&entries, hph_scale);
        always_spd::<f64>(&innovations, &hph, floor)?;
        always_spd::<f32>(&innovations, &hph, floor)?;
    }
}
