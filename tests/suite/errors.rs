//! Typed errors of every form, and the guarantee that goes with them: a
//! refused predict or update leaves the filter bit-for-bit unchanged (state,
//! covariance and the form's pending prediction), and the filter then works
//! exactly as if the bad call had never happened.

use crate::support;

use core::fmt::Debug;

use kestrel::form::{PredictForm, SquareRootForm, UnscentedForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix1, Matrix1x2, Matrix2, SMatrix, SVector, Vector1, Vector2};
use kestrel::sigma::MerweParams;
use kestrel::{
    Ekf, Filter, FilterError, LinearizedMeasurement, LinearizedProcess, MeasurementModel,
    ProcessModel, Quantity, SrUkf, Ukf,
};
use support::bits;

/// Panics unless `after` has the same state, covariance and form as `before`.
#[track_caller]
fn assert_unchanged<F, const N: usize>(
    name: &str,
    before: &Filter<f64, N, F>,
    after: &Filter<f64, N, F>,
) where
    F: kestrel::form::Form<f64, N> + PartialEq + Debug,
{
    assert_eq!(bits(before.state()), bits(after.state()), "{name}: state");
    assert_eq!(
        bits(&before.covariance()),
        bits(&after.covariance()),
        "{name}: covariance"
    );
    assert_eq!(before.form(), after.form(), "{name}: form");
}

/// A plain predict and update that any form accepts.
fn good_models<const N: usize>() -> (LinearProcess<f64, N>, LinearMeasurement<f64, N, 1>) {
    let mut h = SMatrix::<f64, 1, N>::zeros();
    h[0] = 1.0;
    (
        LinearProcess::new(SMatrix::identity(), SMatrix::identity() * 0.1),
        LinearMeasurement::new(h, Matrix1::new(1.0)),
    )
}

/// Runs the same good predict and update on `f` (which has just refused a
/// call) and on `reference` (its copy from before): the results must be
/// identical to the bit.
#[track_caller]
fn still_works<F, const N: usize>(
    name: &str,
    mut reference: Filter<f64, N, F>,
    f: &mut Filter<f64, N, F>,
) where
    F: PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, 1>, 1>
        + PartialEq
        + Debug,
{
    let (process, sensor) = good_models::<N>();
    let z = Vector1::new(0.5);
    for g in [&mut reference, &mut *f] {
        g.predict(&process, 1.0).expect("good predict");
        g.update(&sensor, &z).expect("good update");
    }
    assert_unchanged(name, &reference, f);
}

/// `f.update(model, z)` must fail with `want`, change nothing, and leave `f`
/// working.
#[track_caller]
fn update_fails<F, H, const N: usize, const M: usize>(
    name: &str,
    f: &mut Filter<f64, N, F>,
    model: &H,
    z: &SVector<f64, M>,
    want: FilterError,
) where
    F: UpdateForm<f64, N, H, M>
        + PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, 1>, 1>
        + Clone
        + PartialEq
        + Debug,
{
    let before = f.clone();
    assert_eq!(f.update(model, z).err(), Some(want), "{name}");
    assert_unchanged(name, &before, f);
    still_works(name, before, f);
}

/// `f.predict(model, 1)` must fail with `want`, change nothing, and leave
/// `f` working.
#[track_caller]
fn predict_fails<F, P, const N: usize>(
    name: &str,
    f: &mut Filter<f64, N, F>,
    model: &P,
    want: FilterError,
) where
    F: PredictForm<f64, N, P>
        + PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, 1>, 1>
        + Clone
        + PartialEq
        + Debug,
{
    let before = f.clone();
    assert_eq!(f.predict(model, 1.0).err(), Some(want), "{name}");
    assert_unchanged(name, &before, f);
    still_works(name, before, f);
}

/// Runs `$body` with `$f` bound to a fresh filter of each form (the
/// covariance form with sequential and with batch updates) built from
/// `($x0, $p0)`, and `$name` to the form's name.
macro_rules! each_form {
    ($x0:expr, $p0:expr, |$name:ident, $f:ident| $body:block) => {{
        let (x0, p0) = ($x0, $p0);
        {
            let $name = "ekf sequential";
            let mut $f = Ekf::new(x0, p0).unwrap();
            $f.form_mut().set_sequential(true);
            $body
        }
        {
            let $name = "ekf batch";
            let mut $f = Ekf::new(x0, p0).unwrap();
            $f.form_mut().set_sequential(false);
            $body
        }
        each_unscented_form!(x0, p0, |$name, $f| $body);
    }};
}

/// Like `each_form!` for the UKF and the square-root UKF only.
macro_rules! each_unscented_form {
    ($x0:expr, $p0:expr, |$name:ident, $f:ident| $body:block) => {{
        let (x0, p0) = ($x0, $p0);
        {
            let $name = "ukf";
            let mut $f = Ukf::new(x0, p0).unwrap();
            $body
        }
        {
            let $name = "sr-ukf";
            let mut $f = SrUkf::new(x0, p0).unwrap();
            $body
        }
    }};
}

/// A non-finite element of a vector.
fn non_finite(what: Quantity, index: usize) -> FilterError {
    FilterError::NonFinite {
        what,
        row: index,
        col: 0,
    }
}

/// A non-finite entry of a matrix.
fn non_finite_at(what: Quantity, row: usize, col: usize) -> FilterError {
    FilterError::NonFinite { what, row, col }
}

fn not_pd(what: Quantity, index: usize) -> FilterError {
    FilterError::NotPositiveDefinite { what, index }
}

/// Constant velocity with dt = 1 and unit white acceleration.
fn cv() -> LinearProcess<f64, 2> {
    LinearProcess::new(
        Matrix2::new(1.0, 1.0, 0.0, 1.0),
        Matrix2::new(0.25, 0.5, 0.5, 1.0),
    )
}

/// Both components measured, `R = diag(1, 2)`.
fn both() -> LinearMeasurement<f64, 2, 2> {
    LinearMeasurement::new(Matrix2::identity(), Matrix2::new(1.0, 0.0, 0.0, 2.0))
}

const X0: Vector2<f64> = Vector2::new(1.0, 0.5);

fn p0() -> Matrix2<f64> {
    Matrix2::new(4.0, 1.0, 1.0, 2.0)
}

#[test]
fn non_finite_measurement() {
    each_form!(X0, p0(), |name, f| {
        // After a predict, so the pending process noise must survive too.
        f.predict(&cv(), 1.0).unwrap();
        for (bad, index) in [(f64::NAN, 1), (f64::INFINITY, 0), (f64::NEG_INFINITY, 1)] {
            let mut z = Vector2::new(1.0, 2.0);
            z[index] = bad;
            let want = non_finite(Quantity::Measurement, index);
            update_fails(name, &mut f, &both(), &z, want);
        }
        // Finite z whose residual overflows.
        f.set_state(Vector2::new(-1e308, 0.0)).unwrap();
        let z = Vector2::new(1e308, 0.0);
        let want = non_finite(Quantity::Measurement, 0);
        update_fails(name, &mut f, &both(), &z, want);
    });
}

#[test]
fn non_finite_measurement_noise() {
    each_form!(X0, p0(), |name, f| {
        f.predict(&cv(), 1.0).unwrap();
        let bad =
            LinearMeasurement::new(Matrix2::identity(), Matrix2::new(1.0, 0.0, 0.0, f64::NAN));
        let want = non_finite_at(Quantity::MeasurementNoise, 1, 1);
        update_fails(name, &mut f, &bad, &Vector2::new(1.0, 2.0), want);
    });
}

/// Predicts NaN everywhere (its Jacobian is fine).
struct NanSensor;
impl MeasurementModel<f64, 2, 1> for NanSensor {
    fn predict(&self, _x: &Vector2<f64>) -> Vector1<f64> {
        Vector1::new(f64::NAN)
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(1.0)
    }
}
impl LinearizedMeasurement<f64, 2, 1> for NanSensor {
    fn jacobian(&self, _x: &Vector2<f64>) -> Matrix1x2<f64> {
        Matrix1x2::new(1.0, 0.0)
    }
}

/// A finite prediction with a NaN Jacobian.
struct NanJacobian;
impl MeasurementModel<f64, 2, 1> for NanJacobian {
    fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> {
        Vector1::new(x[0])
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(1.0)
    }
}
impl LinearizedMeasurement<f64, 2, 1> for NanJacobian {
    fn jacobian(&self, _x: &Vector2<f64>) -> Matrix1x2<f64> {
        Matrix1x2::new(1.0, f64::NAN)
    }
}

/// A finite prediction `x − (shift, 0)` with the Jacobian `h` and a dense
/// `R` (so the covariance form takes its batch update, where `H` is checked
/// through the outputs).
struct BadJacobian {
    h: Matrix2<f64>,
    shift: f64,
}
impl MeasurementModel<f64, 2, 2> for BadJacobian {
    fn predict(&self, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(x[0] - self.shift, x[1])
    }
    fn noise(&self) -> Matrix2<f64> {
        Matrix2::new(1.0, 0.25, 0.25, 1.0)
    }
}
impl LinearizedMeasurement<f64, 2, 2> for BadJacobian {
    fn jacobian(&self, _x: &Vector2<f64>) -> Matrix2<f64> {
        self.h
    }
}

/// The covariances the deferred checks are tried from: positive definite,
/// and semi-definite with a zero variance (where `∞ · 0` gives NaN rather
/// than `∞`).
fn deferred_priors() -> [Matrix2<f64>; 2] {
    [p0(), Matrix2::new(4.0, 0.0, 0.0, 0.0)]
}

const NON_FINITE: [f64; 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];

#[test]
fn a_non_finite_jacobian_is_named_in_the_batch_update_too() {
    for p in deferred_priors() {
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            for bad in NON_FINITE {
                let mut h = Matrix2::new(1.0, 0.5, -0.5, 2.0);
                h[(i, j)] = bad;
                let sensor = BadJacobian { h, shift: 0.0 };
                let want = non_finite_at(Quantity::MeasurementJacobian, i, j);
                let name = format!("P = {p}, H[{i}, {j}] = {bad}");
                let mut f = Ekf::new(X0, p).unwrap();
                update_fails(&name, &mut f, &sensor, &Vector2::new(1.0, 0.5), want);
                // After a prediction (the pending covariance) as well.
                f.predict(&cv(), 1.0).unwrap();
                update_fails(&name, &mut f, &sensor, &Vector2::new(1.0, 0.5), want);
                // An innovation that overflows as well (`ν₀ = MAX + MAX`):
                // the Jacobian is named first, as it is checked first.
                let sensor = BadJacobian { h, shift: f64::MAX };
                update_fails(&name, &mut f, &sensor, &Vector2::new(f64::MAX, 0.5), want);
            }
        }
    }
}

/// `h(x) = √x₀`: finite at the estimate, NaN at a sigma point left of 0.
struct SqrtSensor;
impl MeasurementModel<f64, 2, 1> for SqrtSensor {
    fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> {
        Vector1::new(x[0].sqrt())
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(1.0)
    }
}

#[test]
fn non_finite_predicted_measurement() {
    each_form!(X0, p0(), |name, f| {
        f.predict(&cv(), 1.0).unwrap();
        let want = non_finite(Quantity::PredictedMeasurement, 0);
        update_fails(name, &mut f, &NanSensor, &Vector1::new(1.0), want);
    });
    let mut f = Ekf::new(X0, p0()).unwrap();
    let want = non_finite_at(Quantity::MeasurementJacobian, 0, 1);
    update_fails("ekf", &mut f, &NanJacobian, &Vector1::new(1.0), want);
    // x₀ = 1 and P₀₀ = 4: the sigma points reach 1 − 2√2 < 0.
    each_unscented_form!(X0, p0(), |name, f| {
        let want = non_finite(Quantity::PredictedMeasurement, 0);
        update_fails(name, &mut f, &SqrtSensor, &Vector1::new(1.0), want);
    });
}

/// Propagates to NaN (its transition matrix is fine).
struct NanProcess;
impl ProcessModel<f64, 2> for NanProcess {
    fn propagate(&self, x: &Vector2<f64>, _dt: f64) -> Vector2<f64> {
        Vector2::new(x[0], f64::NAN)
    }
    fn noise(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        Matrix2::identity()
    }
}
impl LinearizedProcess<f64, 2> for NanProcess {
    fn transition(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        Matrix2::identity()
    }
}

/// A finite propagation with a NaN transition matrix.
struct NanTransition;
impl ProcessModel<f64, 2> for NanTransition {
    fn propagate(&self, x: &Vector2<f64>, _dt: f64) -> Vector2<f64> {
        *x
    }
    fn noise(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        Matrix2::identity()
    }
}
impl LinearizedProcess<f64, 2> for NanTransition {
    fn transition(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        Matrix2::new(1.0, f64::NAN, 0.0, 1.0)
    }
}

/// `x⁻ = (√x₀, x₁)`: finite at the estimate, NaN at a sigma point.
struct SqrtProcess;
impl ProcessModel<f64, 2> for SqrtProcess {
    fn propagate(&self, x: &Vector2<f64>, _dt: f64) -> Vector2<f64> {
        Vector2::new(x[0].sqrt(), x[1])
    }
    fn noise(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        Matrix2::identity()
    }
}

#[test]
fn non_finite_propagation() {
    each_form!(X0, p0(), |name, f| {
        // Once from a posterior, once with a prediction already pending.
        for _ in 0..2 {
            let want = non_finite(Quantity::PropagatedState, 1);
            predict_fails(name, &mut f, &NanProcess, want);
            f.predict(&cv(), 1.0).unwrap();
        }
    });
    let mut f = Ekf::new(X0, p0()).unwrap();
    let want = non_finite_at(Quantity::Transition, 0, 1);
    predict_fails("ekf", &mut f, &NanTransition, want);
    each_unscented_form!(X0, p0(), |name, f| {
        let want = non_finite(Quantity::PropagatedState, 0);
        predict_fails(name, &mut f, &SqrtProcess, want);
    });
}

/// A non-finite transition entry and, optionally, a NaN propagation.
struct BadTransition {
    phi: Matrix2<f64>,
    nan_state: bool,
}
impl ProcessModel<f64, 2> for BadTransition {
    fn propagate(&self, x: &Vector2<f64>, _dt: f64) -> Vector2<f64> {
        if self.nan_state {
            Vector2::new(f64::NAN, x[1])
        } else {
            *x
        }
    }
    fn noise(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        Matrix2::identity()
    }
}
impl LinearizedProcess<f64, 2> for BadTransition {
    fn transition(&self, _x: &Vector2<f64>, _dt: f64) -> Matrix2<f64> {
        self.phi
    }
}

#[test]
fn an_overflowing_innovation_is_named_in_the_batch_update() {
    let sensor = BadJacobian {
        h: Matrix2::identity(),
        shift: f64::MAX,
    };
    let want = non_finite(Quantity::Measurement, 0);
    let mut f = Ekf::new(X0, p0()).unwrap();
    update_fails("ekf", &mut f, &sensor, &Vector2::new(f64::MAX, 0.5), want);
}

#[test]
fn a_non_finite_transition_is_named_though_only_the_outputs_are_checked() {
    for p in deferred_priors() {
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            for bad in NON_FINITE {
                for nan_state in [false, true] {
                    let mut phi = Matrix2::new(1.0, 1.0, 0.0, 1.0);
                    phi[(i, j)] = bad;
                    let process = BadTransition { phi, nan_state };
                    // The transition is named even when the propagated
                    // state is bad too: it was checked first.
                    let want = non_finite_at(Quantity::Transition, i, j);
                    let name = format!("P = {p}, Φ[{i}, {j}] = {bad}, NaN x: {nan_state}");
                    let mut f = Ekf::new(X0, p).unwrap();
                    predict_fails(&name, &mut f, &process, want);
                    // With a prediction pending.
                    f.predict(&cv(), 1.0).unwrap();
                    predict_fails(&name, &mut f, &process, want);
                }
            }
        }
    }
}

#[test]
fn non_finite_process_noise() {
    each_form!(X0, p0(), |name, f| {
        let bad = LinearProcess::new(Matrix2::identity(), Matrix2::new(1.0, f64::NAN, 0.0, 1.0));
        // The check sees the matrix as the model returned it.
        let want = non_finite_at(Quantity::ProcessNoise, 0, 1);
        predict_fails(name, &mut f, &bad, want);
    });
}

#[test]
fn overflowing_propagated_covariance() {
    // Φ = 10²⁰⁰ I keeps the state finite but Φ P Φᵀ overflows. (The
    // square-root form only carries the factor, ~10²⁰⁰, so it is not refused.)
    let huge = LinearProcess::new(Matrix2::identity() * 1e200, Matrix2::identity());
    let want = non_finite_at(Quantity::PropagatedCovariance, 0, 0);
    let mut f = Ekf::new(X0, p0()).unwrap();
    predict_fails("ekf", &mut f, &huge, want);
    let mut f = Ukf::new(X0, p0()).unwrap();
    predict_fails("ukf", &mut f, &huge, want);
}

#[test]
fn non_psd_process_noise() {
    // [1 2; 2 1] has eigenvalues 3 and −1: the second pivot is 1 − 4 < 0.
    let bad = LinearProcess::new(Matrix2::identity(), Matrix2::new(1.0, 2.0, 2.0, 1.0));
    each_form!(X0, p0(), |name, f| {
        predict_fails(name, &mut f, &bad, not_pd(Quantity::ProcessNoise, 1));
        f.predict(&cv(), 1.0).unwrap();
        predict_fails(name, &mut f, &bad, not_pd(Quantity::ProcessNoise, 1));
    });
}

/// Random walk with `Q = diag(0, 1)`: the first component never gains
/// variance.
fn second_only() -> LinearProcess<f64, 2> {
    LinearProcess::new(Matrix2::identity(), Matrix2::new(0.0, 0.0, 0.0, 1.0))
}

#[test]
fn singular_innovation_covariance() {
    // P₀ = diag(0, 1), Q = diag(0, 1) give P⁻ = diag(0, 2); with H = [1 0],
    // R = 0, C = 0.
    let zero_first = Matrix2::new(0.0, 0.0, 0.0, 1.0);
    let exact = LinearMeasurement::new(Matrix1x2::new(1.0, 0.0), Matrix1::new(0.0));
    // P₀ = Q = diag(1, 0) give P⁻ = diag(2, 0); with H = I, R = diag(1, 0),
    // C = diag(3, 0), singular at pivot 1.
    let zero_second = Matrix2::new(1.0, 0.0, 0.0, 0.0);
    let first_noise = LinearProcess::new(Matrix2::identity(), Matrix2::new(1.0, 0.0, 0.0, 0.0));
    let half_exact = LinearMeasurement::new(Matrix2::identity(), Matrix2::new(1.0, 0.0, 0.0, 0.0));

    // (A fresh filter each time: a refused update is followed by good ones.)
    let z1 = Vector1::new(1.0);
    let z2 = Vector2::new(1.0, 2.0);
    for sequential in [true, false] {
        let mut f = Ekf::new(X0, zero_first).unwrap();
        f.form_mut().set_sequential(sequential);
        f.predict(&second_only(), 1.0).unwrap();
        let want = not_pd(Quantity::InnovationCovariance, 0);
        update_fails("ekf", &mut f, &exact, &z1, want);

        let mut f = Ekf::new(X0, zero_second).unwrap();
        f.form_mut().set_sequential(sequential);
        f.predict(&first_noise, 1.0).unwrap();
        let want = not_pd(Quantity::InnovationCovariance, 1);
        update_fails("ekf", &mut f, &half_exact, &z2, want);
    }
    let mut f = Ukf::new(X0, zero_first).unwrap();
    f.predict(&second_only(), 1.0).unwrap();
    let want = not_pd(Quantity::InnovationCovariance, 0);
    update_fails("ukf", &mut f, &exact, &z1, want);
    let mut f = Ukf::new(X0, zero_second).unwrap();
    f.predict(&first_noise, 1.0).unwrap();
    let want = not_pd(Quantity::InnovationCovariance, 1);
    update_fails("ukf", &mut f, &half_exact, &z2, want);

    // The square-root form accepts a singular R (its factor starts from a
    // semi-definite chol R) and refuses the singular innovation factor.
    let mut f = SrUkf::new(X0, zero_first).unwrap();
    f.predict(&second_only(), 1.0).unwrap();
    let want = not_pd(Quantity::InnovationCovariance, 0);
    update_fails("sr-ukf", &mut f, &exact, &z1, want);
    let mut f = SrUkf::new(X0, zero_second).unwrap();
    f.predict(&first_noise, 1.0).unwrap();
    let want = not_pd(Quantity::InnovationCovariance, 1);
    update_fails("sr-ukf", &mut f, &half_exact, &z2, want);
}

/// `z = x² + v`, `R = r`.
struct Squared(f64);
impl MeasurementModel<f64, 1, 1> for Squared {
    fn predict(&self, x: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(x[0] * x[0])
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(self.0)
    }
}

/// `x⁻ = x²`, `Q = 0.5`.
struct Square;
impl ProcessModel<f64, 1> for Square {
    fn propagate(&self, x: &Vector1<f64>, _dt: f64) -> Vector1<f64> {
        Vector1::new(x[0] * x[0])
    }
    fn noise(&self, _x: &Vector1<f64>, _dt: f64) -> Matrix1<f64> {
        Matrix1::new(0.5)
    }
}

/// Unscented 1-D filters at `(x, p)` with sigma-point parameters
/// `(α, β, κ)`.
fn unscented_1d(x: f64, p: f64, params: (f64, f64, f64)) -> (Ukf<f64, 1>, SrUkf<f64, 1>) {
    let (x, p) = (Vector1::new(x), Matrix1::new(p));
    let params = MerweParams::new(params.0, params.1, params.2);
    let ukf = UnscentedForm::new(&p).unwrap().with_params(params).unwrap();
    let sr = SquareRootForm::new(&p)
        .unwrap()
        .with_params(params)
        .unwrap();
    (
        Ukf::with_form(x, ukf).unwrap(),
        SrUkf::with_form(x, sr).unwrap(),
    )
}

#[test]
fn indefinite_unscented_innovation_covariance() {
    // With α = 1, κ = 0 the unscented variance of x² at (m, p) is
    // β p² + 4 m² p (see hand_computed.rs). At m = 0, p = 1, β = −2 it is −2,
    // so C = −2 + 1 < 0: a negative centre weight can make C indefinite.
    let (mut ukf, mut sr) = unscented_1d(0.0, 1.0, (1.0, -2.0, 0.0));
    let want = not_pd(Quantity::InnovationCovariance, 0);
    update_fails("ukf", &mut ukf, &Squared(1.0), &Vector1::new(1.0), want);
    update_fails("sr-ukf", &mut sr, &Squared(1.0), &Vector1::new(1.0), want);
}

#[test]
fn square_root_downdate_failures() {
    // Update: α = 1, β = −1, κ = 0 at m = 1, p = 1, R = 0.5.
    // ẑ = 2, P_zz = −1 + 4 = 3, C = 3.5 > 0, P_xz = 2m p = 2:
    // P⁺ = 1 − 2²/3.5 = −1/7 < 0, so downdating S⁻ = 1 by U = K S_z fails.
    let (_, mut sr) = unscented_1d(1.0, 1.0, (1.0, -1.0, 0.0));
    let want = FilterError::DowndateFailed {
        column: 0,
        index: 0,
    };
    update_fails(
        "sr-ukf update",
        &mut sr,
        &Squared(0.5),
        &Vector1::new(3.0),
        want,
    );

    // Predict: α = 0.5, β = −10, κ = 0 at m = 1, p = 1. The unscented
    // variance of x² is β p² + 4 m² p = −6, plus Q = 0.5: negative, so
    // removing the centre point (weight −12.25) from the factor fails.
    let (_, mut sr) = unscented_1d(1.0, 1.0, (0.5, -10.0, 0.0));
    predict_fails("sr-ukf predict", &mut sr, &Square, want);
}

#[test]
fn construction_and_setters_refuse_bad_input() {
    let nan_p = Matrix2::new(1.0, 0.0, f64::NAN, 1.0);
    let want = non_finite_at(Quantity::StateCovariance, 1, 0);
    assert_eq!(Ekf::new(X0, nan_p).err(), Some(want));
    assert_eq!(Ukf::new(X0, nan_p).err(), Some(want));
    assert_eq!(SrUkf::new(X0, nan_p).err(), Some(want));
    let nan_x = Vector2::new(0.0, f64::NAN);
    let want = non_finite(Quantity::State, 1);
    assert_eq!(Ekf::new(nan_x, p0()).err(), Some(want));
    assert_eq!(Ukf::new(nan_x, p0()).err(), Some(want));
    assert_eq!(SrUkf::new(nan_x, p0()).err(), Some(want));
    let indefinite = Matrix2::new(1.0, 2.0, 2.0, 1.0);
    let want = not_pd(Quantity::StateCovariance, 1);
    assert_eq!(Ekf::new(X0, indefinite).err(), Some(want));
    assert_eq!(Ukf::new(X0, indefinite).err(), Some(want));
    assert_eq!(SrUkf::new(X0, indefinite).err(), Some(want));

    each_form!(X0, p0(), |name, f| {
        f.predict(&cv(), 1.0).unwrap();
        let before = f.clone();
        assert!(f.set_state(nan_x).is_err(), "{name}");
        assert!(f.set_covariance(&nan_p).is_err(), "{name}");
        assert_unchanged(name, &before, &f);
        still_works(name, before, &mut f);
    });
    each_form!(X0, p0(), |name, f| {
        let before = f.clone();
        assert_eq!(f.set_covariance(&indefinite).err(), Some(want), "{name}");
        assert_unchanged(name, &before, &f);
    });
}

/// `R` that is not a covariance: every form refuses it with the same error,
/// naming `R` and the row and column of the user's matrix.
#[test]
fn invalid_measurement_noise_is_refused_by_every_form() {
    let sensor = |r: Matrix2<f64>| LinearMeasurement::new(Matrix2::identity(), r);
    let cases = [
        // A negative variance (diagonal: the sequential path's check).
        (
            Matrix2::new(1.0, 0.0, 0.0, -2.0),
            not_pd(Quantity::MeasurementNoise, 1),
        ),
        // A negative variance first, with a correlation (the batch check).
        (
            Matrix2::new(-1.0, 0.1, 0.1, 2.0),
            not_pd(Quantity::MeasurementNoise, 0),
        ),
        // Positive variances, correlation above 1: indefinite at row 1.
        (
            Matrix2::new(1.0, 2.0, 2.0, 1.0),
            not_pd(Quantity::MeasurementNoise, 1),
        ),
        // One off-diagonal entry missing.
        (
            Matrix2::new(1.0, 0.5, 0.0, 1.0),
            FilterError::NotSymmetric {
                what: Quantity::MeasurementNoise,
                row: 1,
                col: 0,
            },
        ),
        (
            Matrix2::new(1.0, 0.0, 0.0, f64::INFINITY),
            non_finite_at(Quantity::MeasurementNoise, 1, 1),
        ),
    ];
    each_form!(X0, p0(), |name, f| {
        for (r, want) in cases {
            update_fails(name, &mut f, &sensor(r), &Vector2::new(1.0, 2.0), want);
            f.predict(&cv(), 1.0).unwrap();
            update_fails(name, &mut f, &sensor(r), &Vector2::new(1.0, 2.0), want);
        }
    });
}

/// `Q` and `P0` that are not symmetric, and a bad `dt`: the same error in
/// every form, the filter unchanged.
#[test]
fn asymmetric_noise_and_bad_time_steps_are_refused_by_every_form() {
    let lopsided = Matrix2::new(1.0, 0.3, 0.0, 1.0);
    let asym = |what| FilterError::NotSymmetric {
        what,
        row: 1,
        col: 0,
    };
    let q = LinearProcess::new(Matrix2::identity(), lopsided);
    each_form!(X0, p0(), |name, f| {
        predict_fails(name, &mut f, &q, asym(Quantity::ProcessNoise));
        for (dt, want) in [
            (-1e-9, FilterError::NegativeTimeStep),
            (f64::NAN, non_finite(Quantity::TimeStep, 0)),
            (f64::NEG_INFINITY, non_finite(Quantity::TimeStep, 0)),
        ] {
            let before = f.clone();
            assert_eq!(f.predict(&cv(), dt).err(), Some(want), "{name}");
            assert_unchanged(name, &before, &f);
        }
        // dt = 0 is a valid (empty) step.
        f.predict(&cv(), 0.0).unwrap();
    });
    let want = Some(asym(Quantity::StateCovariance));
    assert_eq!(Ekf::new(X0, lopsided).err(), want);
    assert_eq!(Ukf::new(X0, lopsided).err(), want);
    assert_eq!(SrUkf::new(X0, lopsided).err(), want);
    // Rounding-level asymmetry (far below √ε) is accepted.
    let rounded = Matrix2::new(4.0, 1.0, 1.0 + 1e-15, 2.0);
    assert!(Ekf::new(X0, rounded).is_ok());
    assert!(Ukf::new(X0, rounded).is_ok());
    assert!(SrUkf::new(X0, rounded).is_ok());
    // A negative initial variance.
    let negative = Matrix2::new(4.0, 0.0, 0.0, -1.0);
    let want = Some(not_pd(Quantity::StateCovariance, 1));
    assert_eq!(Ekf::new(X0, negative).err(), want);
    assert_eq!(Ukf::new(X0, negative).err(), want);
    assert_eq!(SrUkf::new(X0, negative).err(), want);
}

/// A NaN `dt` used to surface as a non-finite entry of the propagated state
/// at an index into `Φ`; it is now named as the time step, before any model
/// is called.
#[test]
fn a_nan_time_step_is_named_as_such() {
    let want = non_finite(Quantity::TimeStep, 0);
    let mut f = Ekf::new(SVector::<f64, 6>::zeros(), SMatrix::identity()).unwrap();
    let process = LinearProcess::new(SMatrix::identity(), SMatrix::identity());
    assert_eq!(f.predict(&process, f64::NAN).err(), Some(want));
    assert_eq!(
        want.to_string(),
        "time step dt has a non-finite value at index 0"
    );
}

/// The messages a person reads: quantity, place, what is wrong.
#[test]
fn messages_speak_in_the_users_terms() {
    let cases = [
        (
            not_pd(Quantity::MeasurementNoise, 1),
            "measurement noise covariance R is not positive semi-definite (first failing row and column: 1)",
        ),
        (
            not_pd(Quantity::InnovationCovariance, 0),
            "innovation covariance is not positive definite (first failing row and column: 0)",
        ),
        (
            non_finite_at(Quantity::Transition, 0, 1),
            "state-transition matrix has a non-finite value at row 0, column 1",
        ),
        (FilterError::NegativeTimeStep, "time step dt is negative"),
    ];
    for (e, text) in cases {
        assert_eq!(e.to_string(), text);
    }
}
