//! Small filters checked against numbers worked out by hand (the arithmetic
//! is in the comments), for every form: the covariance form with sequential
//! and with batch updates, the UKF and the square-root UKF (both time-update
//! methods). All inputs are exactly representable, so the expected values
//! are exact fractions and the tolerance is 1e-12.

use crate::support;

use kestrel::form::{PredictForm, SquareRootForm, TimeUpdate, UnscentedForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix1, Matrix1x2, Matrix2, SMatrix, SVector, Vector1, Vector2};
use kestrel::sigma::MerweParams;
use kestrel::{
    Ekf, Filter, LinearizedMeasurement, LinearizedProcess, MeasurementModel, ProcessModel, SrUkf,
    Ukf, UpdateDetail,
};
use support::{assert_close, assert_scalar};

const TOL: f64 = 1e-12;

/// What an update report must say for a plain (adapter-free) update.
struct Expected<const M: usize> {
    innovation: SVector<f64, M>,
    covariance: SMatrix<f64, M, M>,
    noise: SMatrix<f64, M, M>,
    nis: f64,
    sequential: bool,
}

#[track_caller]
fn check_report<const M: usize>(name: &str, got: &UpdateDetail<f64, M>, want: &Expected<M>) {
    let report = &got.report;
    assert_close(&report.innovation, &want.innovation, TOL, name);
    assert_close(&report.innovation_used, &want.innovation, TOL, name);
    assert_close(&got.innovation_covariance, &want.covariance, TOL, name);
    assert_close(
        &got.nominal_innovation_covariance,
        &want.covariance,
        TOL,
        name,
    );
    assert_close(&got.noise, &want.noise, TOL, name);
    assert_scalar(report.nis, want.nis, TOL, name);
    assert_scalar(report.adapted_nis, want.nis, TOL, name);
    assert_eq!(report.fade, 1.0, "{name}: fade");
    assert!(!report.rejected, "{name}: rejected");
    assert_eq!(
        report.sequential, want.sequential,
        "{name}: sequential flag"
    );
}

/// Runs `$check(name, filter, sequential_enabled)` for each form built from
/// `($x0, $p0)`; `sequential_enabled` is whether scalar updates may be used.
macro_rules! all_forms {
    ($x0:expr, $p0:expr, $check:ident) => {{
        let (x0, p0) = ($x0, $p0);
        let mut batch = Ekf::new(x0, p0).unwrap();
        batch.form_mut().set_sequential(false);
        let rank_one = SquareRootForm::new(&p0)
            .unwrap()
            .with_time_update(TimeUpdate::RankOne);
        let mut sequential = Ekf::new(x0, p0).unwrap();
        sequential.form_mut().set_sequential(true);
        $check("ekf sequential", sequential, true);
        $check("ekf batch", batch, false);
        $check("ukf", Ukf::new(x0, p0).unwrap(), false);
        $check("sr-ukf", SrUkf::new(x0, p0).unwrap(), false);
        $check(
            "sr-ukf rank-one",
            SrUkf::with_form(x0, rank_one).unwrap(),
            false,
        );
    }};
}

// ---------------------------------------------------------------------------
// 1-D random walk: x⁻ = x, Q = 1, R = 5, P₀ = 4, x₀ = 0.

fn random_walk<F>(name: &str, mut f: Filter<f64, 1, F>, sequential: bool)
where
    F: PredictForm<f64, 1, LinearProcess<f64, 1>>
        + UpdateForm<f64, 1, LinearMeasurement<f64, 1, 1>, 1>,
{
    let process = LinearProcess::new(Matrix1::new(1.0), Matrix1::new(1.0));
    let sensor = LinearMeasurement::new(Matrix1::new(1.0), Matrix1::new(5.0));

    // Step 1. P⁻ = 4 + 1 = 5; C = 5 + 5 = 10; K = 5/10 = 0.5.
    // z = 2: ν = 2, x⁺ = 0 + 0.5·2 = 1, P⁺ = (1 − 0.5)·5 = 2.5, NIS = 4/10.
    f.predict(&process, 1.0).unwrap();
    assert_scalar(f.state()[0], 0.0, TOL, name);
    assert_scalar(f.covariance()[0], 5.0, TOL, name);
    let detail = f.update_detailed(&sensor, &Vector1::new(2.0)).unwrap();
    check_report(
        name,
        &detail,
        &Expected {
            innovation: Vector1::new(2.0),
            covariance: Matrix1::new(10.0),
            noise: Matrix1::new(5.0),
            nis: 0.4,
            sequential,
        },
    );
    assert_scalar(f.state()[0], 1.0, TOL, name);
    assert_scalar(f.covariance()[0], 2.5, TOL, name);

    // Step 2. P⁻ = 2.5 + 1 = 3.5; C = 8.5; K = 3.5/8.5 = 7/17.
    // z = 9.5: ν = 8.5, x⁺ = 1 + 3.5 = 4.5, P⁺ = 3.5·5/8.5 = 35/17,
    // NIS = 8.5²/8.5 = 8.5.
    f.predict(&process, 1.0).unwrap();
    assert_scalar(f.covariance()[0], 3.5, TOL, name);
    let detail = f.update_detailed(&sensor, &Vector1::new(9.5)).unwrap();
    check_report(
        name,
        &detail,
        &Expected {
            innovation: Vector1::new(8.5),
            covariance: Matrix1::new(8.5),
            noise: Matrix1::new(5.0),
            nis: 8.5,
            sequential,
        },
    );
    assert_scalar(f.state()[0], 4.5, TOL, name);
    assert_scalar(f.covariance()[0], 35.0 / 17.0, TOL, name);
}

#[test]
fn random_walk_1d() {
    all_forms!(Vector1::new(0.0), Matrix1::new(4.0), random_walk);
}

// ---------------------------------------------------------------------------
// 2-D constant velocity, dt = 1, position measured.

fn constant_velocity<F>(name: &str, mut f: Filter<f64, 2, F>, sequential: bool)
where
    F: PredictForm<f64, 2, LinearProcess<f64, 2>>
        + UpdateForm<f64, 2, LinearMeasurement<f64, 2, 1>, 1>,
{
    // Φ = [1 1; 0 1]; Q = [1/4 1/2; 1/2 1] (rank one: white acceleration
    // of unit variance held over the step, Γ = [1/2, 1]ᵀ).
    let process = LinearProcess::new(
        Matrix2::new(1.0, 1.0, 0.0, 1.0),
        Matrix2::new(0.25, 0.5, 0.5, 1.0),
    );
    let sensor = LinearMeasurement::new(Matrix1x2::new(1.0, 0.0), Matrix1::new(0.75));

    // x₀ = (1, 2), P₀ = [4 1; 1 2].
    // x⁻ = Φ x₀ = (3, 2).
    // Φ P₀ = [5 3; 1 2]; Φ P₀ Φᵀ = [5+3 3; 1+2 2] = [8 3; 3 2];
    // P⁻ = [8.25 3.5; 3.5 3].
    f.predict(&process, 1.0).unwrap();
    assert_close(f.state(), &Vector2::new(3.0, 2.0), TOL, name);
    assert_close(
        &f.covariance(),
        &Matrix2::new(8.25, 3.5, 3.5, 3.0),
        TOL,
        name,
    );

    // C = 8.25 + 0.75 = 9; K = (8.25, 3.5)/9 = (11/12, 7/18).
    // z = 6: ν = 3, x⁺ = (3 + 33/12, 2 + 21/18) = (5.75, 19/6), NIS = 9/9.
    // P⁺ = P⁻ − P⁻Hᵀ H P⁻ / 9:
    //   P⁺₁₁ = 8.25 − 68.0625/9 = 8.25 − 7.5625 = 0.6875
    //   P⁺₁₂ = 3.5 − 28.875/9 = 84/24 − 77/24 = 7/24
    //   P⁺₂₂ = 3 − 12.25/9 = 3 − 49/36 = 59/36
    let detail = f.update_detailed(&sensor, &Vector1::new(6.0)).unwrap();
    check_report(
        name,
        &detail,
        &Expected {
            innovation: Vector1::new(3.0),
            covariance: Matrix1::new(9.0),
            noise: Matrix1::new(0.75),
            nis: 1.0,
            sequential,
        },
    );
    assert_close(f.state(), &Vector2::new(5.75, 19.0 / 6.0), TOL, name);
    assert_close(
        &f.covariance(),
        &Matrix2::new(0.6875, 7.0 / 24.0, 7.0 / 24.0, 59.0 / 36.0),
        TOL,
        name,
    );
}

#[test]
fn constant_velocity_2d() {
    all_forms!(
        Vector2::new(1.0, 2.0),
        Matrix2::new(4.0, 1.0, 1.0, 2.0),
        constant_velocity
    );
}

// ---------------------------------------------------------------------------
// 2-D measurement of a 2-D state, no predict: P = [2 1; 1 2], H = I.

fn vector_measurement<F>(name: &str, mut f: Filter<f64, 2, F>, sequential: bool)
where
    F: UpdateForm<f64, 2, LinearMeasurement<f64, 2, 2>, 2> + Clone,
{
    let start = f.clone();

    // Diagonal R = I (the covariance form may go component by component).
    // C = [3 1; 1 3], C⁻¹ = [3 −1; −1 3]/8.
    // K = P C⁻¹ = [2 1; 1 2][3 −1; −1 3]/8 = [5 1; 1 5]/8.
    // z = (9, −1), x = (1, −1): ν = (8, 0), x⁺ = x + K ν = (1 + 5, −1 + 1).
    // P⁺ = (I − K) P = [3 −1; −1 3]/8 · [2 1; 1 2] = [5 1; 1 5]/8.
    // NIS = νᵀ C⁻¹ ν = 64·3/8 = 24.
    let diagonal = LinearMeasurement::new(Matrix2::identity(), Matrix2::identity());
    let detail = f
        .update_detailed(&diagonal, &Vector2::new(9.0, -1.0))
        .unwrap();
    check_report(
        name,
        &detail,
        &Expected {
            innovation: Vector2::new(8.0, 0.0),
            covariance: Matrix2::new(3.0, 1.0, 1.0, 3.0),
            noise: Matrix2::identity(),
            nis: 24.0,
            sequential,
        },
    );
    assert_close(f.state(), &Vector2::new(6.0, 0.0), TOL, name);
    assert_close(
        &f.covariance(),
        &(Matrix2::new(5.0, 1.0, 1.0, 5.0) / 8.0),
        TOL,
        name,
    );

    // Correlated R = [1 ½; ½ 1] (never sequential): C = [3 1.5; 1.5 3] = 1.5 P,
    // so K = P C⁻¹ = I/1.5 = (2/3) I and P⁺ = (I − K) P = P/3.
    // z = (4, −1): ν = (3, 0), x⁺ = (1 + 2, −1);
    // NIS = 3² (C⁻¹)₁₁ = 9 · (P⁻¹)₁₁ / 1.5 = 9 · (2/3) / 1.5 = 4.
    let mut f = start;
    let correlated = LinearMeasurement::new(Matrix2::identity(), Matrix2::new(1.0, 0.5, 0.5, 1.0));
    let detail = f
        .update_detailed(&correlated, &Vector2::new(4.0, -1.0))
        .unwrap();
    check_report(
        name,
        &detail,
        &Expected {
            innovation: Vector2::new(3.0, 0.0),
            covariance: Matrix2::new(3.0, 1.5, 1.5, 3.0),
            noise: Matrix2::new(1.0, 0.5, 0.5, 1.0),
            nis: 4.0,
            sequential: false,
        },
    );
    assert_close(f.state(), &Vector2::new(3.0, -1.0), TOL, name);
    assert_close(
        &f.covariance(),
        &(Matrix2::new(2.0, 1.0, 1.0, 2.0) / 3.0),
        TOL,
        name,
    );
}

#[test]
fn vector_measurement_2d() {
    all_forms!(
        Vector2::new(1.0, -1.0),
        Matrix2::new(2.0, 1.0, 1.0, 2.0),
        vector_measurement
    );
}

// ---------------------------------------------------------------------------
// Nonlinear: f(x) = x² and h(x) = x² in one dimension.

/// `x⁻ = x²`, `Q = 0.5`, `Φ = 2x`.
struct Square;
impl ProcessModel<f64, 1> for Square {
    fn propagate(&self, x: &Vector1<f64>, _dt: f64) -> Vector1<f64> {
        Vector1::new(x[0] * x[0])
    }
    fn noise(&self, _x: &Vector1<f64>, _dt: f64) -> Matrix1<f64> {
        Matrix1::new(0.5)
    }
}
impl LinearizedProcess<f64, 1> for Square {
    fn transition(&self, x: &Vector1<f64>, _dt: f64) -> Matrix1<f64> {
        Matrix1::new(2.0 * x[0])
    }
}

/// `z = x² + v`, `R = 1`, `H = 2x`.
struct Squared;
impl MeasurementModel<f64, 1, 1> for Squared {
    fn predict(&self, x: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(x[0] * x[0])
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(1.0)
    }
}
impl LinearizedMeasurement<f64, 1, 1> for Squared {
    fn jacobian(&self, x: &Vector1<f64>) -> Matrix1<f64> {
        Matrix1::new(2.0 * x[0])
    }
}

/// The EKF linearises at the estimate. x₀ = 1, P₀ = 1.
/// Predict: x⁻ = 1² = 1, Φ = 2, P⁻ = 2·1·2 + 0.5 = 4.5.
/// Update with z = 4: ẑ = 1, H = 2, C = 4·4.5 + 1 = 19, ν = 3,
/// K = 2·4.5/19 = 9/19, x⁺ = 1 + 27/19 = 46/19,
/// P⁺ = 4.5 − 9²/19 = (85.5 − 81)/19 = 9/38, NIS = 9/19.
#[test]
fn ekf_on_squares() {
    for sequential in [true, false] {
        let name = if sequential { "sequential" } else { "batch" };
        let mut f = Ekf::new(Vector1::new(1.0), Matrix1::new(1.0)).unwrap();
        f.form_mut().set_sequential(sequential);
        f.predict(&Square, 1.0).unwrap();
        assert_scalar(f.state()[0], 1.0, TOL, name);
        assert_scalar(f.covariance()[0], 4.5, TOL, name);
        let detail = f.update_detailed(&Squared, &Vector1::new(4.0)).unwrap();
        check_report(
            name,
            &detail,
            &Expected {
                innovation: Vector1::new(3.0),
                covariance: Matrix1::new(19.0),
                noise: Matrix1::new(1.0),
                nis: 9.0 / 19.0,
                sequential,
            },
        );
        assert_scalar(f.state()[0], 46.0 / 19.0, TOL, name);
        assert_scalar(f.covariance()[0], 9.0 / 38.0, TOL, name);
    }
}

/// The unscented transform of `y = x²` for `x ~ (m, p)` in one dimension,
/// from the Merwe points `m ± η√p`, `η² = α²(1 + κ)`:
///
/// - weights: `W₀ᵐ = 1 − 1/η²`, `W₀ᶜ = W₀ᵐ + 1 − α² + β`, `Wᵢ = 1/(2η²)`;
/// - points map to `m² ± 2mη√p + η²p`, so the mean is
///   `m² + 2Wᵢη²p = m² + p` (exact for a Gaussian);
/// - deviations: centre `−p`, pairs `±2mη√p + (η² − 1)p`, so
///   `P_yy = W₀ᶜp² + 4m²p + (η² − 1)²p²/η² = (β + α²κ)p² + 4m²p`
///   (the Gaussian value `2p² + 4m²p` whenever `β + α²κ = 2`);
/// - cross covariance `P_xy = Wᵢ · 2 · η√p · 2mη√p = 2mp`.
struct SquareTransform {
    mean: f64,
    var: f64,
    cross: f64,
}

fn square_transform(params: (f64, f64, f64), m: f64, p: f64) -> SquareTransform {
    let (alpha, beta, kappa) = params;
    SquareTransform {
        mean: m * m + p,
        var: (beta + alpha * alpha * kappa) * p * p + 4.0 * m * m * p,
        cross: 2.0 * m * p,
    }
}

/// `(α, β, κ)`: the default; Julier's `κ = 3 − N` with `β = 0`; a small
/// spread with a negative centre weight (`W₀ᶜ = −0.25`); and `β = 1`, which
/// is not the Gaussian value.
const PARAMS: [(f64, f64, f64); 4] = [
    (1.0, 2.0, 0.0),
    (1.0, 0.0, 2.0),
    (0.5, 2.0, 0.0),
    (1.0, 1.0, 0.0),
];

fn unscented_on_squares<F>(name: &str, mut f: Filter<f64, 1, F>, params: (f64, f64, f64))
where
    F: PredictForm<f64, 1, Square> + UpdateForm<f64, 1, Squared, 1> + Clone,
{
    let start = f.clone();

    // Update from (m, p) = (1, 1) with R = 1, z = 4. For the defaults:
    // ẑ = 2, P_zz = 2 + 4 = 6, C = 7, P_xz = 2, K = 2/7, ν = 2,
    // x⁺ = 1 + 4/7 = 11/7, P⁺ = 1 − 2·2/7 = 3/7, NIS = 4/7.
    let t = square_transform(params, 1.0, 1.0);
    let c = t.var + 1.0;
    let nu = 4.0 - t.mean;
    let k = t.cross / c;
    let detail = f.update_detailed(&Squared, &Vector1::new(4.0)).unwrap();
    check_report(
        name,
        &detail,
        &Expected {
            innovation: Vector1::new(nu),
            covariance: Matrix1::new(c),
            noise: Matrix1::new(1.0),
            nis: nu * nu / c,
            sequential: false,
        },
    );
    assert_scalar(f.state()[0], 1.0 + k * nu, TOL, name);
    assert_scalar(f.covariance()[0], 1.0 - t.cross * t.cross / c, TOL, name);
    if params == PARAMS[0] {
        assert_scalar(f.state()[0], 11.0 / 7.0, TOL, name);
        assert_scalar(f.covariance()[0], 3.0 / 7.0, TOL, name);
        assert_scalar(detail.report.nis, 4.0 / 7.0, TOL, name);
    }

    // Predict from (1, 1) with Q = 0.5: mean 1 + 1 = 2 and, for the
    // defaults, P⁻ = 2 + 4 + 0.5 = 6.5.
    let mut f = start;
    f.predict(&Square, 1.0).unwrap();
    let t = square_transform(params, 1.0, 1.0);
    assert_scalar(f.state()[0], t.mean, TOL, name);
    assert_scalar(f.covariance()[0], t.var + 0.5, TOL, name);
    if params == PARAMS[0] {
        assert_scalar(f.covariance()[0], 6.5, TOL, name);
    }

    // And an update from the predicted (m, p) = (2, 6.5) with z = 20: for
    // the defaults ẑ = 4 + 6.5 = 10.5, P_zz = 2·42.25 + 4·4·6.5 = 188.5,
    // C = 189.5, P_xz = 26, ν = 9.5.
    let (m, p) = (t.mean, t.var + 0.5);
    let t = square_transform(params, m, p);
    let c = t.var + 1.0;
    let nu = 20.0 - t.mean;
    let detail = f.update_detailed(&Squared, &Vector1::new(20.0)).unwrap();
    assert_scalar(detail.report.innovation[0], nu, TOL, name);
    assert_scalar(detail.innovation_covariance[0], c, 1e-12 * c, name);
    assert_scalar(f.state()[0], m + t.cross / c * nu, TOL, name);
    assert_scalar(f.covariance()[0], p - t.cross * t.cross / c, TOL, name);
    if params == PARAMS[0] {
        assert_scalar(detail.innovation_covariance[0], 189.5, TOL, name);
        assert_scalar(f.state()[0], 2.0 + 26.0 * 9.5 / 189.5, TOL, name);
    }
}

#[test]
fn unscented_forms_on_squares() {
    let (x0, p0) = (Vector1::new(1.0), Matrix1::new(1.0));
    for params in PARAMS {
        let merwe = MerweParams::new(params.0, params.1, params.2);
        let ukf = UnscentedForm::new(&p0).unwrap().with_params(merwe).unwrap();
        unscented_on_squares("ukf", Ukf::with_form(x0, ukf).unwrap(), params);
        for method in [TimeUpdate::Householder, TimeUpdate::RankOne] {
            let sr = SquareRootForm::new(&p0)
                .unwrap()
                .with_params(merwe)
                .unwrap()
                .with_time_update(method);
            unscented_on_squares("sr-ukf", SrUkf::with_form(x0, sr).unwrap(), params);
        }
    }
}
