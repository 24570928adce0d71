//! Paper 002: the χ² test with Huber inflation of `R` (ICT-EREKF) and the
//! plain rejecting χ² gate.
//!
//! - Hand-computed epochs in two dimensions through every form: the
//!   models are linear (`Φ = I`, `H = I`, `P⁻ = I`), so each form is the
//!   Kalman filter and `x⁺ = C̄⁻¹ ν`, `P⁺ = I − C̄⁻¹` with `C̄ = I + R̄`.
//! - Without a fault the update is bit for bit the plain filter's.
//! - On a stream with 5 % outliers of 20σ the Huber filter stays within 50 %
//!   of the outlier-free RMS while the plain filter is at least 3× worse.

use crate::support;

use kestrel_adaptive::{
    chi_square_quantile, ChiSquareGate, HuberInflation, HuberReport, InflationShape,
};
use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::nalgebra::{Matrix2, Vector2};
use kestrel_core::{Filter, FilterError, Real};
use support::hand::{close, epoch, epoch_detailed, planar_walk};
use support::{cv, rms, run, run_detailed, symmetric_pd, CvForm};

/// χ²_0.95(1) = 1.959964² (normal 97.5 % quantile squared).
const T1: f64 = 3.841_458_820_694_124;
/// χ²_0.95(2) = −2 ln 0.05.
const T2: f64 = 5.991_464_547_107_979;
/// statrs's quantiles are accurate to about 10⁻¹⁰ relative; the hand
/// epochs use the thresholds the adapters hold, checked against the
/// closed forms to this tolerance.
const QUANTILE_TOL: f64 = 1e-9;

/// The paper's test with its thresholds `(T', χ²_0.95(2))`, checked.
fn paper_huber() -> (HuberInflation<f64, 2>, f64, f64) {
    let h = HuberInflation::<f64, 2>::as_published().unwrap();
    assert!((h.component_threshold() - T1).abs() < QUANTILE_TOL);
    assert!((h.global_threshold() - T2).abs() < QUANTILE_TOL);
    (h, h.component_threshold(), h.global_threshold())
}

#[track_caller]
fn close_m(got: &Matrix2<f64>, want: &Matrix2<f64>, what: &str) {
    for (g, w) in got.iter().zip(want.iter()) {
        close(*g, *w, what);
    }
}

/// [`each_hand_form`] from x₀ = 0, P₀ = ½ I, so P⁻ = I.
macro_rules! each_form_2d {
    ($($rest:tt)+) => {
        each_hand_form!(Vector2::zeros(), Matrix2::identity() * 0.5, $($rest)+)
    };
}

#[test]
fn thresholds_are_the_chi_square_quantiles() {
    let h = HuberInflation::<f64, 2>::as_published().unwrap();
    assert!((h.global_threshold() - T2).abs() < 1e-9);
    assert!((h.component_threshold() - T1).abs() < 1e-9);
    assert!((chi_square_quantile(0.95, 2).unwrap() - T2).abs() < 1e-9);
    let bad = Some(FilterError::InvalidParameter {
        name: "significance",
        valid: "0.01 ≤ significance ≤ 0.15 (the range the test is built for)",
    });
    assert_eq!(HuberInflation::<f64, 2>::new(0.009).err(), bad);
    assert_eq!(HuberInflation::<f64, 2>::new(0.151).err(), bad);
    assert_eq!(HuberInflation::<f64, 2>::new(f64::NAN).err(), bad);
    assert!(HuberInflation::<f64, 2>::new(0.01).is_ok());
    assert!(HuberInflation::<f64, 2>::new(0.15).is_ok());
    assert_eq!(
        HuberInflation::<f32, 2>::as_published().unwrap().shape(),
        InflationShape::Congruence
    );
}

#[test]
fn huber_hand_epoch_diagonal_r() {
    // R = I, P⁻ = I: C = 2I. ν = z = (10, 1): T = (100 + 1)/2 = 50.5 > T2.
    // T₁ = 100/2 = 50 > T1: α₁ = T1/50; T₂ = 1/2: α₂ = 1.
    // R̄ = diag(50/T1, 1), C̄ = diag(1 + 50/T1, 2):
    // x⁺ = (10/(1 + 50/T1), 1/2), P⁺ = diag(1 − 1/(1 + 50/T1), 1/2).
    let m = planar_walk(Matrix2::identity());
    let (huber, t1, t2) = paper_huber();
    let rbar = 50.0 / t1;
    for shape in [InflationShape::Congruence, InflationShape::Diagonal] {
        let huber = huber.with_shape(shape);
        each_form_2d!(huber, |name, f| {
            let detail = epoch_detailed(&mut f, &m, Vector2::new(10.0, 1.0)).unwrap();
            let report = &detail.report;
            let a: HuberReport<f64, 2> = report.adapters;
            assert!(a.fault, "{name}");
            close(a.statistic, 50.5, name);
            close(a.threshold, t2, name);
            close(a.component_statistics[0], 50.0, name);
            close(a.component_statistics[1], 0.5, name);
            close(a.factors[0], t1 / 50.0, name);
            assert_eq!(a.factors[1], 1.0, "{name}");
            assert_eq!(a.inflated, 1, "{name}");
            close_m(&detail.noise, &Matrix2::new(rbar, 0.0, 0.0, 1.0), name);
            close(f.state()[0], 10.0 / (1.0 + rbar), name);
            close(f.state()[1], 0.5, name);
            close(f.covariance()[(0, 0)], 1.0 - 1.0 / (1.0 + rbar), name);
            close(f.covariance()[(1, 1)], 0.5, name);
            close(f.covariance()[(0, 1)], 0.0, name);
        });
    }
}

#[test]
fn huber_hand_epoch_full_r() {
    // R = [1 ½; ½ 1], P⁻ = I: C = [2 ½; ½ 2], det 3.75,
    // C⁻¹ = [2 −½; −½ 2]/3.75. ν = (10, 1):
    // T = (2·100 − 2·½·10 + 2·1)/3.75 = 192/3.75 = 51.2.
    // T₁ = 100/2 = 50 → α₁ = T1/50, T₂ = ½ → α₂ = 1.
    let r = Matrix2::new(1.0, 0.5, 0.5, 1.0);
    let m = planar_walk(r);
    let (huber, t1, _) = paper_huber();
    let a1 = t1 / 50.0;
    let want = [
        // Congruence: R̄₁₂ = ½ / √α₁.
        (
            InflationShape::Congruence,
            Matrix2::new(1.0 / a1, 0.5 / a1.sqrt(), 0.5 / a1.sqrt(), 1.0),
        ),
        // Diagonal only.
        (
            InflationShape::Diagonal,
            Matrix2::new(1.0 / a1, 0.5, 0.5, 1.0),
        ),
    ];
    for (shape, rbar) in want {
        // x⁺ = C̄⁻¹ ν and P⁺ = I − C̄⁻¹ with C̄ = I + R̄ (P⁻ = I), by the
        // 2 × 2 adjugate.
        let c = Matrix2::identity() + rbar;
        let det = c[(0, 0)] * c[(1, 1)] - c[(0, 1)] * c[(1, 0)];
        let inv = Matrix2::new(c[(1, 1)], -c[(0, 1)], -c[(1, 0)], c[(0, 0)]) / det;
        let huber = huber.with_shape(shape);
        each_form_2d!(huber, |name, f| {
            let detail = epoch_detailed(&mut f, &m, Vector2::new(10.0, 1.0)).unwrap();
            let report = &detail.report;
            let a = report.adapters;
            close(a.statistic, 51.2, name);
            close(a.factors[0], a1, name);
            assert_eq!(a.factors[1], 1.0, "{name}");
            close_m(&detail.noise, &rbar, name);
            let x = inv * Vector2::new(10.0, 1.0);
            close(f.state()[0], x[0], name);
            close(f.state()[1], x[1], name);
            close_m(&f.covariance(), &(Matrix2::identity() - inv), name);
        });
    }
}

/// An adapter that changes nothing but is not declared an identity, so the
/// filter runs the same adapter round (and the same Cholesky solves) as for
/// the Huber adapter. (With `()` the covariance form takes its square-root-
/// free fast path, equal to this one only to rounding.)
struct Passive;

impl kestrel_core::adapter::PriorAdapter<f64> for Passive {}

impl NoiseAdapter<f64, 2> for Passive {
    type Report = ();
    fn before_gain(&mut self, _: &mut kestrel_core::adapter::GainStep<f64, 2>, _: &mut ()) {}
}

#[test]
fn huber_global_pass_leaves_everything_bit_for_bit() {
    // R = [1 ¼; ¼ 1], P⁻ = I: C = [2 ¼; ¼ 2], det 3.9375.
    // ν = (2, 2): T = (8 − 2 + 8)/3.9375 ≈ 3.56 < T2.
    // ν = (3, 0): T = 18/3.9375 ≈ 4.57 < T2 although T₁ = 9/2 = 4.5 > T1:
    // the component test only runs after a global fault.
    let m = planar_walk(Matrix2::new(1.0, 0.25, 0.25, 1.0));
    for z in [Vector2::new(2.0, 2.0), Vector2::new(3.0, 0.0)] {
        each_form_2d!(
            HuberInflation::<f64, 2>::as_published().unwrap(),
            |name, f| {
                let mut plain = f.clone().with_adapter(Passive);
                let detail = epoch_detailed(&mut f, &m, z).unwrap();
                let report = &detail.report;
                let want_detail = epoch_detailed(&mut plain, &m, z).unwrap();
                let a = report.adapters;
                assert!(!a.fault, "{name}");
                assert_eq!(a.factors, Vector2::new(1.0, 1.0), "{name}");
                assert_eq!(a.inflated, 0, "{name}");
                assert_eq!(bits(&detail.noise), bits(&m.1.noise), "{name}");
                assert_eq!(bits(f.state()), bits(plain.state()), "{name}");
                assert_eq!(bits(&f.covariance()), bits(&plain.covariance()), "{name}");
                assert_eq!(
                    detail.innovation_covariance,
                    want_detail.innovation_covariance
                );
            }
        );
    }
}

/// Bit patterns, so "unchanged" also distinguishes −0.0.
fn bits<const R: usize, const C: usize>(
    m: &kestrel_core::nalgebra::SMatrix<f64, R, C>,
) -> Vec<u64> {
    m.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn huber_without_fault_matches_the_plain_filter_bit_for_bit_on_a_stream() {
    // Every epoch the global test passes must equal the plain update from
    // the same prior exactly; about 5 % of clean epochs fail it (false
    // alarms) and are merely inflated.
    let spec = cv::Spec::new(21, 400, Matrix2::new(1.0, 0.3, 0.3, 2.0));
    let stream = cv::stream(&spec);
    let sensor = cv::sensor::<f64>(&spec.r);
    let process = cv::process::<f64>(spec.q);
    let mut passes = 0;
    let mut f = support::ekf(cv::x0(), cv::p0())
        .with_adapter(HuberInflation::<f64, 2>::as_published().unwrap());
    for z in &stream.z {
        f.predict(&process, 1.0).unwrap();
        let mut plain = f.clone().with_adapter(Passive);
        let detail = f.update_detailed(&sensor, z).unwrap();
        let report = &detail.report;
        plain.update(&sensor, z).unwrap();
        if !report.adapters.fault {
            passes += 1;
            assert_eq!(bits(&detail.noise), bits(&sensor.noise));
            assert_eq!(bits(f.state()), bits(plain.state()));
            assert_eq!(bits(&f.covariance()), bits(&plain.covariance()));
        } else {
            assert!(report.adapters.statistic > T2 - 1e-9);
        }
    }
    // 400 clean epochs at α = 0.05: far more than 80 % pass.
    assert!(passes > 340, "{passes}");
}

/// Position RMS of a filter of form `F` with adapter `A` over `stream`,
/// after a 100-step transient, checking `P` and the used `R` on the way.
fn position_rms<T: Real, F: CvForm<T>, A: NoiseAdapter<T, 2>>(
    mut f: Filter<T, 4, F, A>,
    stream: &cv::Stream,
    r: &Matrix2<f64>,
) -> f64 {
    let sensor = cv::sensor::<T>(r);
    let errors = run_detailed(&mut f, stream, &sensor, |k, detail, f| {
        assert!(symmetric_pd(&f.covariance()), "P at {k}");
        assert!(symmetric_pd(&detail.noise), "R at {k}");
    })
    .unwrap();
    rms(&errors[100..])
}

fn outliers_case<T: Real, F: CvForm<T>>(
    name: &str,
    make: fn(
        kestrel_core::nalgebra::SVector<T, 4>,
        kestrel_core::nalgebra::SMatrix<T, 4, 4>,
    ) -> Filter<T, 4, F>,
) {
    let r = Matrix2::new(1.0, 0.0, 0.0, 1.0);
    let spec = cv::Spec::new(7, 2000, r).with_outliers(0.05, 20.0);
    let stream = cv::stream(&spec);
    let clean = stream.without_outliers();
    let outliers = stream.outlier.iter().filter(|&&o| o).count();
    assert!((70..=130).contains(&outliers), "{outliers} outliers");

    let reference = position_rms(make(cv::x0(), cv::p0()), &clean, &r);
    let plain = position_rms(make(cv::x0(), cv::p0()), &stream, &r);
    let huber = HuberInflation::<T, 2>::as_published().unwrap();
    let robust = position_rms(make(cv::x0(), cv::p0()).with_adapter(huber), &stream, &r);
    assert!(
        robust <= 1.5 * reference,
        "{name}: Huber RMS {robust} vs outlier-free {reference}"
    );
    assert!(
        plain >= 3.0 * reference,
        "{name}: plain RMS {plain} vs outlier-free {reference}"
    );
}

#[test]
fn huber_rejects_twenty_sigma_outliers_in_every_form() {
    each_form!(outliers_case);
}

// The plain gate ------------------------------------------------------------

#[test]
fn gate_hand_epochs() {
    // R = I, P⁻ = I: C = 2I.
    let m = planar_walk(Matrix2::identity());
    let gate = ChiSquareGate::<f64, 2>::new(0.05).unwrap();
    assert!((gate.threshold() - T2).abs() < QUANTILE_TOL);
    // z = (3, 1): T = 10/2 = 5 < T2: accepted, K = ½.
    each_form_2d!(gate, |name, f| {
        let report = epoch(&mut f, &m, Vector2::new(3.0, 1.0)).unwrap();
        close(report.adapters.statistic, 5.0, name);
        assert!(!report.adapters.rejected && !report.rejected, "{name}");
        close(f.state()[0], 1.5, name);
        close(f.state()[1], 0.5, name);
        close_m(&f.covariance(), &(Matrix2::identity() * 0.5), name);
    });
    // z = (3, 2): T = 13/2 = 6.5 > T2: rejected, the prior stays.
    each_form_2d!(gate, |name, f| {
        let report = epoch(&mut f, &m, Vector2::new(3.0, 2.0)).unwrap();
        close(report.adapters.statistic, 6.5, name);
        assert_eq!(report.adapters.threshold, gate.threshold(), "{name}");
        assert!(report.adapters.rejected && report.rejected, "{name}");
        assert_eq!(f.state(), &Vector2::zeros(), "{name}");
        close_m(&f.covariance(), &Matrix2::identity(), name);
    });
    // An explicit threshold of 6.5 accepts the same epoch (not strictly above).
    let loose = ChiSquareGate::<f64, 2>::with_threshold(6.5).unwrap();
    let mut f = support::ekf(Vector2::zeros(), Matrix2::identity() * 0.5).with_adapter(loose);
    let report = epoch(&mut f, &m, Vector2::new(3.0, 2.0)).unwrap();
    assert!(!report.rejected);
    assert_eq!(
        ChiSquareGate::<f64, 2>::with_threshold(0.0).err(),
        Some(FilterError::InvalidParameter {
            name: "threshold",
            valid: "finite and greater than 0"
        })
    );
    assert_eq!(
        ChiSquareGate::<f64, 2>::new(1.0).err(),
        Some(FilterError::InvalidParameter {
            name: "significance",
            valid: "0 < significance < 1"
        })
    );
}

#[test]
fn gate_rejects_every_twenty_sigma_outlier() {
    // 20σ on both components gives T ≈ 800 / (1 + H P Hᵀ); at α = 0.01 the
    // threshold is 9.21. Clean epochs are rejected about 1 % of the time.
    let r = Matrix2::identity();
    let spec = cv::Spec::new(11, 1000, r).with_outliers(0.05, 20.0);
    let stream = cv::stream(&spec);
    let sensor = cv::sensor::<f64>(&r);
    let mut f =
        support::ekf(cv::x0(), cv::p0()).with_adapter(ChiSquareGate::<f64, 2>::new(0.01).unwrap());
    let (mut false_alarms, mut clean) = (0, 0);
    run(&mut f, &stream, &sensor, |k, report, _| {
        assert_eq!(report.rejected, report.adapters.rejected);
        if stream.outlier[k] {
            assert!(report.rejected, "outlier at {k} accepted");
        } else {
            clean += 1;
            false_alarms += usize::from(report.rejected);
        }
    })
    .unwrap();
    assert!(false_alarms * 100 <= 3 * clean, "{false_alarms} of {clean}");
}
