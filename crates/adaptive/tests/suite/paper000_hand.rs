//! Hand-computed epochs of every paper-000 / 004 adapter, in one or two
//! dimensions, through real filters of every form. The models are linear,
//! so every form is the Kalman filter and must reproduce the same numbers;
//! the expected values are worked out below with scalar arithmetic (or, in
//! 2-D, with nalgebra's general inverse and the paper's `(I − H K)` form),
//! independently of the adapters' code.

use crate::support;

use kestrel_adaptive::{
    chi_square_quantile, DivergenceFading, ImprovedAdaptive, OutlierCompression, SageHusa,
    StrongTracking,
};
use kestrel_core::nalgebra::{Matrix1, Matrix2, Vector1, Vector2};
use kestrel_core::FilterError;
use kestrel_models::{LinearMeasurement, LinearProcess};
use support::hand::{close, epoch, epoch_detailed, Models};

/// The scalar models `x⁻ = φ x + w`, `w ~ N(0, q)`, `z = x + v`, `v ~ N(0, r)`.
fn scalar(phi: f64, q: f64, r: f64) -> Models<1, 1> {
    (
        LinearProcess::new(Matrix1::new(phi), Matrix1::new(q)),
        LinearMeasurement::new(Matrix1::new(1.0), Matrix1::new(r)),
    )
}

/// [`each_hand_form`] from x₀ = 0, P₀ = `$p0`.
macro_rules! each_scalar_form {
    ($p0:expr, $($rest:tt)+) => {
        each_hand_form!(Vector1::new(0.0), Matrix1::new($p0), $($rest)+)
    };
}

/// The name of an out-of-range parameter, as the error reports it.
fn bad(name: &'static str) -> Option<&'static str> {
    Some(name)
}

/// The parameter an error names, if it is an `InvalidParameter`.
fn param<T>(r: Result<T, FilterError>) -> Option<&'static str> {
    match r {
        Err(FilterError::InvalidParameter { name, valid }) => {
            assert!(!valid.is_empty(), "{name}: the valid range is stated");
            Some(name)
        }
        _ => None,
    }
}

// χ² quantiles --------------------------------------------------------------

/// Survival function of χ²(2k): `e^{−x/2} Σ_{j<k} (x/2)^j / j!`.
fn even_survival(x: f64, dof: usize) -> f64 {
    let (h, mut term, mut sum) = (x / 2.0, 1.0, 0.0);
    for j in 0..dof / 2 {
        if j > 0 {
            term *= h / j as f64;
        }
        sum += term;
    }
    (-h).exp() * sum
}

/// statrs's quantiles are converged to about 10⁻¹⁰ relative (observed: the
/// tail probability at χ²_0.95(2) is off by 2.5·10⁻¹¹).
#[test]
fn chi_square_quantiles_match_closed_forms() {
    // One degree of freedom: the square of the normal 0.975 quantile.
    let c = chi_square_quantile(0.95, 1).unwrap();
    assert!((c - 1.959_963_984_540_054_f64.powi(2)).abs() < 1e-9, "{c}");
    for (p, dof) in [
        (0.95, 2),
        (0.98, 2),
        (0.95, 4),
        (0.95, 6),
        (0.98, 6),
        (0.99, 6),
    ] {
        let c = chi_square_quantile(p, dof).unwrap();
        let tail = even_survival(c, dof);
        assert!(
            (tail - (1.0 - p)).abs() < 1e-10,
            "χ²_{p}({dof}) = {c}: tail {tail}"
        );
    }
    assert_eq!(param(chi_square_quantile(0.0, 2)), bad("probability"));
    assert_eq!(param(chi_square_quantile(1.0, 2)), bad("probability"));
    assert_eq!(param(chi_square_quantile(f64::NAN, 2)), bad("probability"));
    assert_eq!(param(chi_square_quantile(0.5, 0)), bad("dof"));
}

// Outlier compression -------------------------------------------------------

#[test]
fn compression_scales_an_outlier_to_the_threshold() {
    // P₀ = 3, Q = 0, R = 1: C = 4. z = 10: τ = 25 > c = χ²_0.95(1).
    let models = scalar(1.0, 0.0, 1.0);
    let c = 1.959_963_984_540_054_f64.powi(2);
    let factor = (c / 25.0).sqrt();
    let adapter = OutlierCompression::<f64, 1>::new(0.05).unwrap();
    assert!((adapter.threshold() - c).abs() < 1e-9);
    each_scalar_form!(3.0, adapter, |name, f| {
        let report = epoch(&mut f, &models, Vector1::new(10.0)).unwrap();
        let a = report.adapters;
        assert!(a.compressed, "{name}");
        close(a.statistic, 25.0, name);
        close(a.factor, factor, name);
        close(report.innovation_used[0], 10.0 * factor, name);
        // K = ¾ on the compressed innovation; P⁺ = 3 · 1 / 4.
        close(f.state()[0], 0.75 * 10.0 * factor, name);
        close(f.covariance()[0], 0.75, name);
    });
}

#[test]
fn compression_leaves_an_inlier_exactly_alone() {
    // τ = 9 / 4 < c: the factor is exactly 1 and the estimate is the plain one.
    let models = scalar(1.0, 0.0, 1.0);
    each_scalar_form!(
        3.0,
        OutlierCompression::<f64, 1>::new(0.05).unwrap(),
        |name, f| {
            let report = epoch(&mut f, &models, Vector1::new(3.0)).unwrap();
            assert_eq!(report.adapters.factor, 1.0, "{name}");
            assert!(!report.adapters.compressed, "{name}");
            assert_eq!(report.innovation_used, report.innovation, "{name}");
            close(f.state()[0], 2.25, name);
        }
    );
}

// Divergence-tested fading --------------------------------------------------

#[test]
fn divergence_fading_hand_epoch() {
    // φ = 2, P₀ = 1, Q = 1, R = 2: Φ P Φᵀ = 4, P⁻ = 5, C = 7; γ = 2: bound 14.
    let models = scalar(2.0, 1.0, 2.0);
    let fading = DivergenceFading::new(2.0, 100.0).unwrap();

    // z = 6: νᵀν = 36 > 14; λ = (36 − 1 − 2) / 4 = 8.25, P⁻ = 34, C = 36.
    each_scalar_form!(1.0, fading, |name, f| {
        let detail = epoch_detailed(&mut f, &models, Vector1::new(6.0)).unwrap();
        let a = detail.report.adapters;
        assert!(a.diverged, "{name}");
        close(a.statistic, 36.0, name);
        close(a.bound, 14.0, name);
        close(a.fade, 8.25, name);
        close(detail.report.fade, 8.25, name);
        close(detail.innovation_covariance[0], 36.0, name);
        close(f.state()[0], 34.0 / 36.0 * 6.0, name);
        close(f.covariance()[0], 34.0 * 2.0 / 36.0, name);
    });

    // z = 3: 9 ≤ 14, no fade: K = 5/7.
    each_scalar_form!(1.0, fading, |name, f| {
        let report = epoch(&mut f, &models, Vector1::new(3.0)).unwrap();
        assert!(!report.adapters.diverged, "{name}");
        assert_eq!(report.adapters.fade, 1.0, "{name}");
        close(f.state()[0], 15.0 / 7.0, name);
    });

    // λ_max = 4 clamps: P⁻ = 4 · 4 + 1 = 17, C = 19.
    let clamped = DivergenceFading::new(2.0, 4.0).unwrap();
    each_scalar_form!(1.0, clamped, |name, f| {
        let report = epoch(&mut f, &models, Vector1::new(6.0)).unwrap();
        assert_eq!(report.adapters.fade, 4.0, "{name}");
        close(f.state()[0], 17.0 / 19.0 * 6.0, name);
    });
}

#[test]
fn divergence_fading_parameters_are_validated() {
    assert_eq!(param(DivergenceFading::new(0.99, 10.0)), bad("reserve"));
    assert_eq!(
        param(DivergenceFading::new(f64::INFINITY, 10.0)),
        bad("reserve")
    );
    assert_eq!(param(DivergenceFading::new(1.0, 0.5)), bad("max_fade"));
    assert_eq!(param(DivergenceFading::new(1.0, f64::NAN)), bad("max_fade"));
    assert!(DivergenceFading::new(1.0, f64::INFINITY).is_ok());
    let g = DivergenceFading::<f64>::with_false_alarm(0.05, 2, 10.0).unwrap();
    let want = -2.0 * 0.05_f64.ln();
    assert!((g.reserve() - want).abs() < 1e-9 * want, "γ = χ²_0.95(2)");
}

// Strong tracking -----------------------------------------------------------

/// An independent scalar strong-tracking filter: returns (x, P, λ) per epoch.
fn strong_tracking_reference(
    (phi, q, r): (f64, f64, f64),
    (rho, beta, max): (f64, f64, f64),
    zs: &[f64],
) -> Vec<(f64, f64, f64)> {
    let (mut x, mut p, mut v) = (0.0, 1.0, 0.0);
    let mut out = Vec::new();
    for (k, z) in zs.iter().enumerate() {
        let m = phi * p * phi;
        let nu = z - phi * x;
        v = if k == 0 {
            nu * nu
        } else {
            (rho * v + nu * nu) / (1.0 + rho)
        };
        let lambda = ((v - q - beta * r) / m).max(1.0).min(max);
        let prior = lambda * m + q;
        let gain = prior / (prior + r);
        x = phi * x + gain * nu;
        p = (1.0 - gain) * prior;
        out.push((x, p, lambda));
    }
    out
}

#[test]
fn strong_tracking_hand_epochs() {
    // φ = 1, P₀ = 1, Q = ½, R = 1; ρ = 0.95, β = 1.5.
    // Epoch 1, z = 4: V₁ = 16, N = 16 − ½ − 1.5 = 14, M = 1: λ = 14.
    let models = scalar(1.0, 0.5, 1.0);
    let zs = [4.0, 4.5, 3.0, 3.2, 3.1];
    let want = strong_tracking_reference((1.0, 0.5, 1.0), (0.95, 1.5, f64::INFINITY), &zs);
    assert_eq!(want[0].2, 14.0);
    close(want[0].0, 14.5 / 15.5 * 4.0, "reference x₁");
    let st = StrongTracking::new(0.95, 1.5).unwrap();
    each_scalar_form!(1.0, st, |name, f| {
        for (k, (z, (x, p, lambda))) in zs.iter().zip(&want).enumerate() {
            let report = epoch(&mut f, &models, Vector1::new(*z)).unwrap();
            let what = format!("{name} epoch {k}");
            close(report.adapters.fade, *lambda, &what);
            close(f.state()[0], *x, &what);
            close(f.covariance()[0], *p, &what);
        }
    });
    // λ = 1 when tr N ≤ tr M: the later epochs of this record reach it.
    assert!(want.iter().any(|w| w.2 == 1.0), "{want:?}");

    // Clamped at λ_max = 3.
    let want = strong_tracking_reference((1.0, 0.5, 1.0), (0.95, 1.5, 3.0), &zs);
    let st = StrongTracking::new(0.95, 1.5)
        .unwrap()
        .with_max_fade(3.0)
        .unwrap();
    each_scalar_form!(1.0, st, |name, f| {
        for (z, (x, _, lambda)) in zs.iter().zip(&want) {
            let report = epoch(&mut f, &models, Vector1::new(*z)).unwrap();
            assert!(report.adapters.fade <= 3.0, "{name}");
            close(report.adapters.fade, *lambda, name);
            close(f.state()[0], *x, name);
        }
    });
}

#[test]
fn strong_tracking_parameters_are_validated() {
    assert_eq!(param(StrongTracking::new(-0.1, 1.0)), bad("rho"));
    assert_eq!(param(StrongTracking::new(1.1, 1.0)), bad("rho"));
    assert_eq!(param(StrongTracking::new(0.95, 0.9)), bad("softening"));
    assert_eq!(param(StrongTracking::new(f64::NAN, 1.0)), bad("rho"));
    assert_eq!(
        param(StrongTracking::new(0.95, 1.0).unwrap().with_max_fade(0.9)),
        bad("max_fade")
    );
}

// Sage-Husa -----------------------------------------------------------------

#[test]
fn sage_husa_two_scalar_epochs() {
    // P₀ = 1, Q = 0, R = 1, b = 0.9.
    let models = scalar(1.0, 0.0, 1.0);
    let b: f64 = 0.9;
    // Epoch 1, z = 2: C = 2, K = ½, e = ½ · 2 = 1, H P⁺ Hᵀ = ½;
    // d₁ = (1 − b) / (1 − b²) = 1 / 1.9.
    let d1 = (1.0 - b) / (1.0 - b * b);
    let r1 = (1.0 - d1) * 1.0 + d1 * (1.0 + 0.5);
    // Epoch 2, z = 4: P⁻ = ½, R = R̂₁, x⁻ = 1, ν = 3.
    let c2 = 0.5 + r1;
    let k2 = 0.5 / c2;
    let e2 = (1.0 - k2) * 3.0;
    let hph2 = (1.0 - k2) * 0.5;
    let d2 = (1.0 - b) / (1.0 - b * b * b);
    let r2 = (1.0 - d2) * r1 + d2 * (e2 * e2 + hph2);

    each_scalar_form!(1.0, SageHusa::new(b).unwrap(), |name, f| {
        let first = epoch_detailed(&mut f, &models, Vector1::new(2.0)).unwrap();
        assert!(first.report.adapters.estimated, "{name}");
        assert_eq!(first.report.adapters.count, 1, "{name}");
        close(first.report.adapters.weight, d1, name);
        close(first.noise[0], 1.0, name);
        close(f.adapter().estimate()[0], r1, name);

        let second = epoch_detailed(&mut f, &models, Vector1::new(4.0)).unwrap();
        close(second.noise[0], r1, name);
        close(second.report.adapters.trace, r1, name);
        close(second.report.adapters.weight, d2, name);
        close(f.state()[0], 1.0 + k2 * 3.0, name);
        close(f.adapter().estimate()[0], r2, name);
        assert_eq!(f.adapter().count(), 2, "{name}");
    });
}

#[test]
fn sage_husa_matrix_epoch_with_the_papers_form() {
    // Two components observing a 2-state random walk through a full H, with
    // a full R̂₀: the sample (I − H K) ν νᵀ (I − H K)ᵀ + H P⁺ Hᵀ computed from
    // K = P⁻ Hᵀ C⁻¹ with a general inverse.
    let phi = Matrix2::<f64>::identity();
    let q = Matrix2::new(0.2, 0.05, 0.05, 0.1);
    let h = Matrix2::new(1.0, 0.5, -0.3, 2.0);
    let r_model = Matrix2::new(1.0, 0.0, 0.0, 1.0);
    let r0 = Matrix2::new(0.8, 0.3, 0.3, 1.5);
    let p0 = Matrix2::new(2.0, 0.4, 0.4, 1.0);
    let z = Vector2::new(1.5, -2.0);
    let b: f64 = 0.97;

    let prior = phi * p0 * phi.transpose() + q;
    let c = h * prior * h.transpose() + r0;
    let k = prior * h.transpose() * c.try_inverse().unwrap();
    let i_hk = Matrix2::identity() - h * k;
    let nu = z; // x₀ = 0
    let posterior = (Matrix2::identity() - k * h) * prior;
    let sample = i_hk * nu * nu.transpose() * i_hk.transpose() + h * posterior * h.transpose();
    let d = (1.0 - b) / (1.0 - b * b);
    let want = r0 * (1.0 - d) + sample * d;

    let process = LinearProcess::new(phi, q);
    let sensor = LinearMeasurement::new(h, r_model);
    let adapter = SageHusa::new(b).unwrap().with_initial(r0).unwrap();
    let check = |name: &str, estimate: Matrix2<f64>, state: Vector2<f64>| {
        for (g, w) in estimate.iter().zip(want.iter()) {
            assert!((g - w).abs() < 1e-12, "{name}: R̂ {estimate} want {want}");
        }
        let x = k * nu;
        assert!((state - x).norm() < 1e-12, "{name}: x {state} want {x}");
        assert_eq!(estimate, estimate.transpose(), "{name}: R̂ symmetric");
    };
    let mut f = support::ekf(Vector2::zeros(), p0).with_adapter(adapter);
    f.predict(&process, 1.0).unwrap();
    f.update(&sensor, &z).unwrap();
    check("EKF", *f.adapter().estimate(), *f.state());
    let mut f = support::ukf(Vector2::zeros(), p0).with_adapter(adapter);
    f.predict(&process, 1.0).unwrap();
    f.update(&sensor, &z).unwrap();
    check("UKF", *f.adapter().estimate(), *f.state());
    let mut f = support::sr_ukf(Vector2::zeros(), p0).with_adapter(adapter);
    f.predict(&process, 1.0).unwrap();
    f.update(&sensor, &z).unwrap();
    check("SR-UKF", *f.adapter().estimate(), *f.state());
}

#[test]
fn sage_husa_floor_raises_the_diagonal() {
    // b = ½, z = 0: e = 0, H P⁺ Hᵀ = ½, d₁ = ½ / ¾ = ⅔: R̂ = ⅓ + ⅓ = ⅔ < 0.9.
    let models = scalar(1.0, 0.0, 1.0);
    let floored = SageHusa::new(0.5)
        .unwrap()
        .with_floor(Vector1::new(0.9))
        .unwrap();
    each_scalar_form!(1.0, SageHusa::new(0.5).unwrap(), |name, f| {
        epoch(&mut f, &models, Vector1::new(0.0)).unwrap();
        close(f.adapter().estimate()[0], 2.0 / 3.0, name);
    });
    each_scalar_form!(1.0, floored, |name, f| {
        epoch(&mut f, &models, Vector1::new(0.0)).unwrap();
        assert_eq!(f.adapter().estimate()[0], 0.9, "{name}");
    });
}

#[test]
fn sage_husa_parameters_are_validated() {
    assert_eq!(param(SageHusa::<f64, 1>::new(0.0)), bad("forgetting"));
    assert_eq!(
        param(SageHusa::<f64, 1>::new(1.0 + f64::EPSILON)),
        bad("forgetting")
    );
    assert!(SageHusa::<f64, 1>::new(1.0).is_ok(), "b = 1: no forgetting");
    assert_eq!(param(SageHusa::<f64, 1>::new(f64::NAN)), bad("forgetting"));
    let sh = SageHusa::<f64, 2>::new(0.95).unwrap();
    assert_eq!(
        param(sh.with_initial(Matrix2::new(1.0, 2.0, 2.0, 1.0))),
        bad("initial")
    );
    assert_eq!(param(sh.with_floor(Vector2::new(0.1, -1.0))), bad("floor"));
    assert_eq!(
        SageHusa::<f64, 2>::as_published().unwrap().forgetting(),
        0.95
    );
}

#[test]
fn sage_husa_after_a_fading_member_skips_the_faded_epoch() {
    // The divergence case above (fades by 8.25), then Sage-Husa in the tuple.
    let models = scalar(2.0, 1.0, 2.0);
    let tuple = (
        DivergenceFading::new(2.0, 100.0).unwrap(),
        SageHusa::new(0.9).unwrap(),
    );
    each_scalar_form!(1.0, tuple, |name, f| {
        let report = epoch(&mut f, &models, Vector1::new(6.0)).unwrap();
        let (fading, sh) = report.adapters;
        close(fading.fade, 8.25, name);
        assert!(sh.skipped_for_fade && !sh.estimated, "{name}");
        assert_eq!(sh.weight, 0.0, "{name}");
        assert_eq!(f.adapter().1.count(), 0, "{name}");
        // R̂ is still the model's R.
        assert_eq!(f.adapter().1.estimate()[0], 2.0, "{name}");
    });
    // With skipping off, the same epoch is estimated.
    let tuple = (
        DivergenceFading::new(2.0, 100.0).unwrap(),
        SageHusa::new(0.9).unwrap().with_skip_when_faded(false),
    );
    each_scalar_form!(1.0, tuple, |name, f| {
        let report = epoch(&mut f, &models, Vector1::new(6.0)).unwrap();
        assert!(report.adapters.1.estimated, "{name}");
    });
}

// The composition -------------------------------------------------------------

#[test]
fn improved_adaptive_tests_against_the_estimate() {
    // P₀ = 1, Q = 0, R = 1 (model), b = 0.9, γ = 2, α = 0.05.
    // Epoch 1, z = 2: τ = 4 / 2 = 2 < 3.84, 4 ≤ 2 · 2: no fade;
    // R̂₁ = 1 + ½ d₁ as in the scalar Sage-Husa case.
    // Epoch 2, z = 1.2: P⁻ = ½, the test's bound is γ (½ + R̂₁), not γ (½ + 1).
    let models = scalar(1.0, 0.0, 1.0);
    let b: f64 = 0.9;
    let d1 = (1.0 - b) / (1.0 - b * b);
    let r1 = 1.0 + 0.5 * d1;
    let adapter = ImprovedAdaptive::<f64, 1>::with_params(b, 0.05, 2.0, 100.0).unwrap();
    each_scalar_form!(1.0, adapter, |name, f| {
        let first = epoch(&mut f, &models, Vector1::new(2.0)).unwrap();
        let (compression, fading) = first.adapters.tests;
        assert!(!compression.compressed && !fading.diverged, "{name}");
        close(fading.bound, 4.0, name);
        assert!(first.adapters.sage_husa.estimated, "{name}");
        close(f.adapter().sage_husa.estimate()[0], r1, name);

        let second = epoch_detailed(&mut f, &models, Vector1::new(1.2)).unwrap();
        let (compression, fading) = second.report.adapters.tests;
        close(compression.statistic, 0.2 * 0.2 / (0.5 + r1), name);
        close(fading.bound, 2.0 * (0.5 + r1), name);
        close(second.noise[0], r1, name);
    });

    // An outlier at epoch 2 (z = 30, ν = 29): compressed to τ = c, i.e.
    // νᵀν = c C with C = ½ + R̂₁. As c > γ = 2 the divergence test still
    // fails: λ = (c C − 0 − R̂₁) / ½, and Sage-Husa skips the epoch.
    let c = 1.959_963_984_540_054_f64.powi(2);
    let cov = 0.5 + r1;
    let lambda = (c * cov - r1) / 0.5;
    each_scalar_form!(1.0, adapter, |name, f| {
        epoch(&mut f, &models, Vector1::new(2.0)).unwrap();
        let report = epoch(&mut f, &models, Vector1::new(30.0)).unwrap();
        let (compression, fading) = report.adapters.tests;
        assert!(compression.compressed, "{name}");
        close(compression.statistic, 29.0 * 29.0 / cov, name);
        close(fading.statistic, c * cov, name);
        assert!(fading.diverged, "{name}");
        close(fading.fade, lambda, name);
        assert!(report.adapters.sage_husa.skipped_for_fade, "{name}");
        close(f.adapter().sage_husa.estimate()[0], r1, name);
    });
}
