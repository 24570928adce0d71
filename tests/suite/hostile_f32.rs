//! A numerically hostile problem in `f32` on which the covariance form loses
//! positive definiteness and the square-root form does not.
//!
//! The system is a deterministic constant-acceleration model (position,
//! velocity, acceleration, `Φ = [[1, 1, ½], [0, 1, 1], [0, 0, 1]]`, `Q = 0`)
//! observed in position with `R = 1`, written in coordinates rotated by a
//! fixed random orthogonal matrix `T` (`Φ' = T Φ Tᵀ`, `H' = e₁ᵀ Tᵀ`), so the
//! covariance is a dense matrix rather than a graded one. With no process
//! noise, information accumulates at different rates (`P` shrinks like
//! `k⁻¹, k⁻³, k⁻⁵` along its principal directions) and the condition number
//! of `P` grows like `k⁴`. Every filter starts from `x = 0`, `P = 100 I`; the
//! measurements are a fixed pseudo-random `N(0, 1)` sequence. All inputs are
//! `f32` values, and each `f32` filter is compared with an `f64` run of the
//! same form on the same inputs.
//!
//! Observed (300 steps):
//!
//! - condition number of the reference `P`: 4.2e7 after 100 updates, 6.9e8
//!   after 200, 3.5e9 after 300 — far past `1/ε_f32 ≈ 8.4e6`; the `f64`
//!   covariance and square-root forms agree to 2.2e-10 throughout;
//! - `f32` covariance form: `P` is first indefinite after update 112; after
//!   300 updates its smallest eigenvalue is −5.5 (reference 8.5e-12), its
//!   error is 1.9e2 relative to `‖P‖`, and 23 updates were refused because
//!   the innovation covariance itself had gone indefinite;
//! - `f32` square-root UKF: every factor has a positive diagonal (smallest
//!   entry 4.0e-6), `S Sᵀ` stays within 2.4e-4 of its reference relative to
//!   `‖P‖` and the state within 4.9e-4 relative to `‖x‖ + √‖P‖`. Rounding
//!   perturbs a factor by about `ε‖S‖`, i.e. `P` by about
//!   `ε √cond(P) ‖P‖` in its weakest direction, where the covariance form
//!   perturbs `P` by `ε ‖P‖` directly.
//!
//! Two textbook cases were tried first and rejected, because there the
//! square-root form's checked measurement downdate refuses the update too:
//! the Dyer–McReynolds example (`P₀ = I`, `H = [[1, 1, 1], [1, 1, 1 + δ]]`,
//! `R = δ² I`) with `δ` from 1e-5 to 1e-3, where the posterior keeps only
//! about `δ²/3 < ε_f32` of the prior variance (the covariance form refuses
//! it as well, its `H P Hᵀ + R` being indefinite in `f32`); and a precise
//! measurement of a state with a huge prior (`P₁₁ = 10⁸, R = 10⁻⁶`), where
//! the covariance form returns a singular `P` and the downdate fails. No
//! form that removes information by downdating can represent a variance
//! reduction below `ε` of the prior; the square-root advantage is in
//! conditioning accumulated over many steps.

use crate::common;

use kestrel::form::{PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{self, Matrix1, Matrix1x3, Matrix3, SMatrix, Vector1, Vector3};
use kestrel::real::lit;
use kestrel::{Ekf, Filter, Real, SrUkf};

const STEPS: usize = 300;
/// Relative tolerance on `S Sᵀ` against the `f64` reference (`‖ΔP‖ / ‖P‖`).
const TOL: f64 = 1e-3;
/// Relative tolerance on the state (`‖Δx‖ / (‖x‖ + √‖P‖)`).
const STATE_TOL: f64 = 1e-2;

/// The rotated constant-acceleration problem, all values exact in `f32`.
struct Problem {
    phi: Matrix3<f64>,
    h: Matrix1x3<f64>,
    measurements: Vec<f64>,
}

/// Rounds to the nearest `f32` so both precisions see the same inputs.
fn f32_exact<const R: usize, const C: usize>(m: SMatrix<f64, R, C>) -> SMatrix<f64, R, C> {
    m.map(|v| f64::from(v as f32))
}

fn problem() -> Problem {
    let mut rng = common::rng(0);
    let t = common::orthogonal::<3>(&mut rng);
    let phi = Matrix3::new(1.0, 1.0, 0.5, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0);
    let measurements = (0..STEPS)
        .map(|_| f64::from(common::gaussian::<1, 1>(&mut rng)[0] as f32))
        .collect();
    Problem {
        phi: f32_exact(t * phi * t.transpose()),
        h: f32_exact(Matrix1x3::new(1.0, 0.0, 0.0) * t.transpose()),
        measurements,
    }
}

fn to_f64<T: Real, const R: usize, const C: usize>(m: &SMatrix<T, R, C>) -> SMatrix<f64, R, C> {
    m.map(nalgebra::convert_unchecked::<T, f64>)
}

/// Runs `filter` over the problem, calling `inspect` after every step;
/// returns the number of refused predicts and updates.
fn run<T: Real, F>(
    filter: &mut Filter<T, 3, F>,
    problem: &Problem,
    mut inspect: impl FnMut(usize, &Filter<T, 3, F>),
) -> usize
where
    F: PredictForm<T, 3, LinearProcess<T, 3>> + UpdateForm<T, 3, LinearMeasurement<T, 3, 1>, 1>,
{
    let process = LinearProcess::new(problem.phi.cast::<T>(), Matrix3::zeros());
    let sensor = LinearMeasurement::new(problem.h.cast::<T>(), Matrix1::new(T::one()));
    let mut refused = 0;
    for (k, &z) in problem.measurements.iter().enumerate() {
        refused += usize::from(filter.predict(&process, T::one()).is_err());
        refused += usize::from(filter.update(&sensor, &Vector1::new(lit(z))).is_err());
        inspect(k, filter);
    }
    refused
}

fn p0<T: Real>() -> Matrix3<T> {
    Matrix3::identity() * lit::<T>(100.0)
}

/// The state and covariance after each step, in f64.
type Trace = Vec<(Vector3<f64>, Matrix3<f64>)>;

/// The trace of a run and its number of refused steps.
fn trace<T: Real, F>(mut filter: Filter<T, 3, F>, problem: &Problem) -> (Trace, usize)
where
    F: PredictForm<T, 3, LinearProcess<T, 3>> + UpdateForm<T, 3, LinearMeasurement<T, 3, 1>, 1>,
{
    let mut out = Vec::with_capacity(STEPS);
    let refused = run(&mut filter, problem, |_, f| {
        out.push((to_f64(f.state()), to_f64(&f.covariance())));
    });
    (out, refused)
}

#[test]
fn f64_references_agree_and_reach_an_f32_hostile_condition_number() {
    let problem = problem();
    let (kf, refused_kf) = trace(Ekf::new(Vector3::zeros(), p0::<f64>()).unwrap(), &problem);
    let (sr, refused_sr) = trace(SrUkf::new(Vector3::zeros(), p0::<f64>()).unwrap(), &problem);
    assert_eq!((refused_kf, refused_sr), (0, 0));
    for (k, ((x_kf, p_kf), (x_sr, p_sr))) in kf.iter().zip(&sr).enumerate() {
        assert!(common::min_eigenvalue(p_kf) > 0.0, "step {k}");
        let dp = common::relative_difference(p_sr, p_kf);
        assert!(dp <= 1e-8, "step {k}: f64 forms differ by {dp:e}");
        let dx = common::state_difference(x_sr, x_kf, p_kf);
        assert!(dx <= 1e-8, "step {k}: f64 states differ by {dx:e}");
    }
    let eig = common::eigenvalues(&kf[STEPS - 1].1);
    let condition = eig[2] / eig[0];
    assert!(condition > 1e9, "condition number {condition:e}");
}

#[test]
fn f32_square_root_ukf_stays_positive_definite_and_accurate() {
    let problem = problem();
    let (reference, refused) = trace(SrUkf::new(Vector3::zeros(), p0::<f64>()).unwrap(), &problem);
    assert_eq!(refused, 0);
    let mut filter = SrUkf::new(Vector3::zeros(), p0::<f32>()).unwrap();
    let refused = run(&mut filter, &problem, |k, f| {
        let s = f.form().factor();
        assert!(
            s.diagonal().iter().all(|&d| d > 0.0),
            "step {k}: factor diagonal {}",
            s.diagonal()
        );
        let (x_ref, p_ref) = &reference[k];
        let p = to_f64(&s) * to_f64(&s).transpose();
        let dp = common::relative_difference(&p, p_ref);
        assert!(dp <= TOL, "step {k}: S Sᵀ off by {dp:e}");
        let dx = common::state_difference(&to_f64(f.state()), x_ref, p_ref);
        assert!(dx <= STATE_TOL, "step {k}: state off by {dx:e}");
    });
    assert_eq!(refused, 0, "the f32 square-root form refused a step");
}

#[test]
fn f32_covariance_form_loses_positive_definiteness() {
    let problem = problem();
    let (reference, _) = trace(Ekf::new(Vector3::zeros(), p0::<f64>()).unwrap(), &problem);
    let (run32, _) = trace(Ekf::new(Vector3::zeros(), p0::<f32>()).unwrap(), &problem);
    let indefinite = run32
        .iter()
        .position(|(_, p)| !common::cholesky_succeeds(p) || common::min_eigenvalue(p) <= 0.0);
    assert!(
        indefinite.is_some(),
        "the f32 covariance stayed positive definite"
    );
    let (_, p_ref) = &reference[STEPS - 1];
    let error = common::relative_difference(&run32[STEPS - 1].1, p_ref);
    assert!(
        error > 1e3 * TOL,
        "final f32 covariance error only {error:e}"
    );
}
