//! Properties of the three update forms on random stable linear models of 2
//! to 24 states (f64, 100 predict/update steps per case, 256 cases each):
//!
//! - every form keeps its covariance exactly symmetric and positive definite;
//! - the square-root UKF's `S Sᵀ` equals the UKF's `P` (same sigma points,
//!   down to the textbook `α = 10⁻³`, whose centre weight of about `−10⁶`
//!   makes the square-root form downdate);
//! - on a linear model both unscented forms equal the Kalman filter.
//!
//! Why property c draws `α ≥ 10⁻²`: the unscented mean is
//! `χ₀ + Σ Wᵢ (χᵢ − χ₀)` with `Wᵢ = 1 / (2α²(N + κ))`, so the rounding of the
//! deviations (`ε‖x‖` each) reaches the state as about
//! `ε‖x‖ / (α²(N + κ))`. Measured over 40 random cases, the largest state
//! difference from the Kalman filter (relative to `‖x‖ + √‖P‖`) was 3.0e-9 at
//! `α = 10⁻³, κ = 3 − N`, 3.6e-10 at `α = 3·10⁻³` and 3.0e-11 at `α = 10⁻²`,
//! while the covariances agreed to 3e-12 at every `α`. The covariance
//! properties therefore use `α ∈ [10⁻³, 1]`, the state comparison
//! `α ∈ [10⁻², 1]`.

use crate::common;

use common::{dispatch, LinearCase, SIZES};
use kestrel::form::{SquareRootForm, TimeUpdate, UnscentedForm};
use kestrel::models::LinearMeasurement;
use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::sigma::MerweParams;
use kestrel::{Ekf, SrUkf, Ukf};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

const STEPS: usize = 100;

/// What one case draws besides the model seed.
#[derive(Debug, Clone, Copy)]
struct Draw {
    size: (usize, usize),
    seed: u64,
    /// Merwe `α`.
    alpha: f64,
    /// `κ = 3 − N` instead of `κ = 0`.
    kappa_3_minus_n: bool,
    /// The square-root form's time update by rank-one updates.
    rank_one: bool,
}

/// Random cases with `α` log-uniform in `[10^min_log_alpha, 1]`.
fn draws(min_log_alpha: f64) -> impl Strategy<Value = Draw> {
    (
        0..SIZES.len(),
        any::<u64>(),
        min_log_alpha..=0.0f64,
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(i, seed, log_alpha, kappa, rank_one)| Draw {
            size: SIZES[i],
            seed,
            alpha: 10f64.powf(log_alpha),
            kappa_3_minus_n: kappa,
            rank_one,
        })
}

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 256,
        ..ProptestConfig::default()
    }
}

impl Draw {
    fn params(&self, n: usize) -> MerweParams<f64> {
        let kappa = if self.kappa_3_minus_n {
            3.0 - n as f64
        } else {
            0.0
        };
        MerweParams::new(self.alpha, 2.0, kappa)
    }

    fn ukf<const N: usize, const M: usize>(&self, case: &LinearCase<N, M>) -> Ukf<f64, N> {
        let form = UnscentedForm::new(&case.p0)
            .and_then(|f| f.with_params(self.params(N)))
            .expect("valid sigma parameters");
        Ukf::with_form(case.x0, form).expect("finite x0")
    }

    fn sr_ukf<const N: usize, const M: usize>(&self, case: &LinearCase<N, M>) -> SrUkf<f64, N> {
        let method = if self.rank_one {
            TimeUpdate::RankOne
        } else {
            TimeUpdate::Householder
        };
        let form = SquareRootForm::new(&case.p0)
            .and_then(|f| f.with_params(self.params(N)))
            .expect("valid sigma parameters")
            .with_time_update(method);
        SrUkf::with_form(case.x0, form).expect("finite x0")
    }
}

/// `P` is exactly symmetric (to 1e-12 relative), factors, and has a positive
/// smallest eigenvalue.
fn check_pd<const N: usize>(
    p: &SMatrix<f64, N, N>,
    form: &str,
    step: usize,
) -> Result<(), TestCaseError> {
    let asym = common::asymmetry(p);
    prop_assert!(asym <= 1e-12, "{form} step {step}: asymmetry {asym:e}");
    prop_assert!(
        common::cholesky_succeeds(p),
        "{form} step {step}: Cholesky failed"
    );
    let lambda = common::min_eigenvalue(p);
    prop_assert!(
        lambda > 0.0,
        "{form} step {step}: min eigenvalue {lambda:e}"
    );
    Ok(())
}

/// Property a: all four forms stay symmetric positive definite.
fn positive_definite<const N: usize, const M: usize>(draw: Draw) -> Result<(), TestCaseError> {
    let case = common::linear_case::<N, M>(draw.seed, STEPS, false);
    // The sequential path needs a diagonal R: same model with R's diagonal.
    let diag_meas = LinearMeasurement::new(
        case.measurement.matrix,
        SMatrix::from_diagonal(&case.measurement.noise.diagonal()),
    );
    let mut batch = Ekf::new(case.x0, case.p0).expect("finite");
    batch.form_mut().set_sequential(false);
    let mut seq = Ekf::new(case.x0, case.p0).expect("finite");
    seq.form_mut().set_sequential(true);
    let mut ukf = draw.ukf(&case);
    let mut sr = draw.sr_ukf(&case);

    for (k, z) in case.measurements.iter().enumerate() {
        batch.predict(&case.process, 1.0).expect("predict");
        seq.predict(&case.process, 1.0).expect("predict");
        ukf.predict(&case.process, 1.0).expect("predict");
        sr.predict(&case.process, 1.0).expect("predict");
        for (name, p) in [
            ("EKF batch prior", batch.covariance()),
            ("EKF sequential prior", seq.covariance()),
            ("UKF prior", ukf.covariance()),
            ("SR-UKF prior", sr.covariance()),
        ] {
            check_pd(&p, name, k)?;
        }

        let report = batch.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "EKF batch update {k}: {report:?}");
        let report = seq.update(&diag_meas, z);
        prop_assert!(
            matches!(report, Ok(ref r) if r.sequential),
            "EKF sequential update {k}: {report:?}"
        );
        let report = ukf.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "UKF update {k}: {report:?}");
        let report = sr.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "SR-UKF update {k}: {report:?}");
        for (name, p) in [
            ("EKF batch posterior", batch.covariance()),
            ("EKF sequential posterior", seq.covariance()),
            ("UKF posterior", ukf.covariance()),
            ("SR-UKF posterior", sr.covariance()),
        ] {
            check_pd(&p, name, k)?;
        }
    }
    Ok(())
}

/// Asserts `(x, P)` equal the reference `(x_ref, P_ref)` to 1e-9: `P`
/// relative to `‖P_ref‖`, `x` relative to `‖x_ref‖ + √‖P_ref‖`.
fn check_equal<const N: usize>(
    (x, p): (&SVector<f64, N>, &SMatrix<f64, N, N>),
    (x_ref, p_ref): (&SVector<f64, N>, &SMatrix<f64, N, N>),
    what: &str,
) -> Result<(), TestCaseError> {
    let dp = common::relative_difference(p, p_ref);
    prop_assert!(dp <= 1e-9, "{what}: covariance differs by {dp:e}");
    let dx = common::state_difference(x, x_ref, p_ref);
    prop_assert!(dx <= 1e-9, "{what}: state differs by {dx:e}");
    Ok(())
}

/// Property b: `S Sᵀ` of the SR-UKF equals `P` of the UKF at every step,
/// to 1e-9 relative to `‖P‖`.
fn square_root_matches<const N: usize, const M: usize>(draw: Draw) -> Result<(), TestCaseError> {
    let case = common::linear_case::<N, M>(draw.seed, STEPS, false);
    let mut ukf = draw.ukf(&case);
    let mut sr = draw.sr_ukf(&case);
    for (k, z) in case.measurements.iter().enumerate() {
        ukf.predict(&case.process, 1.0).expect("predict");
        sr.predict(&case.process, 1.0).expect("predict");
        let dp = common::relative_difference(&sr.covariance(), &ukf.covariance());
        prop_assert!(dp <= 1e-9, "prior {k}: S Sᵀ differs from P by {dp:e}");
        let report = ukf.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "UKF update {k}: {report:?}");
        let report = sr.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "SR-UKF update {k}: {report:?}");
        let dp = common::relative_difference(&sr.covariance(), &ukf.covariance());
        prop_assert!(dp <= 1e-9, "posterior {k}: S Sᵀ differs from P by {dp:e}");
    }
    Ok(())
}

/// Property c: on a linear model the UKF (and the SR-UKF) is the Kalman
/// filter: states and covariances to 1e-9, relative.
fn unscented_is_kalman<const N: usize, const M: usize>(draw: Draw) -> Result<(), TestCaseError> {
    let case = common::linear_case::<N, M>(draw.seed, STEPS, false);
    let mut kf = Ekf::new(case.x0, case.p0).expect("finite");
    let mut ukf = draw.ukf(&case);
    let mut sr = draw.sr_ukf(&case);
    for (k, z) in case.measurements.iter().enumerate() {
        kf.predict(&case.process, 1.0).expect("predict");
        ukf.predict(&case.process, 1.0).expect("predict");
        sr.predict(&case.process, 1.0).expect("predict");
        let reference = (kf.state(), &kf.covariance());
        check_equal(
            (ukf.state(), &ukf.covariance()),
            reference,
            &format!("UKF prior {k}"),
        )?;
        check_equal(
            (sr.state(), &sr.covariance()),
            reference,
            &format!("SR-UKF prior {k}"),
        )?;

        let report = kf.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "KF update {k}: {report:?}");
        let report = ukf.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "UKF update {k}: {report:?}");
        let report = sr.update(&case.measurement, z);
        prop_assert!(report.is_ok(), "SR-UKF update {k}: {report:?}");
        let reference = (kf.state(), &kf.covariance());
        check_equal(
            (ukf.state(), &ukf.covariance()),
            reference,
            &format!("UKF posterior {k}"),
        )?;
        check_equal(
            (sr.state(), &sr.covariance()),
            reference,
            &format!("SR-UKF posterior {k}"),
        )?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn every_form_stays_symmetric_positive_definite(draw in draws(-3.0)) {
        dispatch!(draw.size, positive_definite(draw))?;
    }

    #[test]
    fn square_root_ukf_factor_reproduces_ukf_covariance(draw in draws(-3.0)) {
        dispatch!(draw.size, square_root_matches(draw))?;
    }

    #[test]
    fn unscented_forms_equal_kalman_filter_on_linear_models(draw in draws(-2.0)) {
        dispatch!(draw.size, unscented_is_kalman(draw))?;
    }
}

#[test]
fn size_table_covers_every_state_dimension_from_2_to_24() {
    for n in 2..=24 {
        assert!(SIZES.iter().any(|&(sn, _)| sn == n), "N = {n} missing");
    }
    for &(n, m) in SIZES {
        assert!((1..=n.min(6)).contains(&m), "({n}, {m})");
    }
}

#[test]
fn random_transitions_are_stable() {
    for (i, &(n, m)) in SIZES.iter().enumerate() {
        let rho = dispatch!((n, m), radius(i as u64));
        assert!(rho < 1.0, "N = {n}: spectral radius bound {rho}");
    }
}

fn radius<const N: usize, const M: usize>(seed: u64) -> f64 {
    let case: LinearCase<N, M> = common::linear_case(seed, 0, false);
    common::spectral_radius_bound(&case.process.transition)
}

#[test]
fn jacobi_eigenvalues_match_a_known_spectrum() {
    let mut rng = common::rng(11);
    let u = common::orthogonal::<6>(&mut rng);
    let d = SVector::<f64, 6>::from([-2.0, 1e-9, 0.5, 1.0, 3.0, 1e3]);
    let p = common::symmetrize(u * SMatrix::from_diagonal(&d) * u.transpose());
    let got = common::eigenvalues(&p);
    assert!((got - d).norm() <= 1e-12 * 1e3, "{got} vs {d}");
    assert!((common::min_eigenvalue(&p) + 2.0).abs() <= 1e-12 * 1e3);
}
