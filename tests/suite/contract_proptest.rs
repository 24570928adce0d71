//! The input contract under random invalid input (10 000 cases in all):
//! an indefinite, asymmetric or non-finite `P0`, `Q` or `R`, and a negative
//! or non-finite `dt`. Every form (the covariance form with sequential and
//! with batch updates, the UKF and the square-root UKF) must return the same
//! error, the one [`kestrel::contract`] gives for that input, and stay
//! unchanged bit for bit, with or without a prediction pending.

use crate::support;

use kestrel::contract::check_covariance;
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix2, Matrix2x3, Matrix3, SMatrix, Vector2, Vector3};
use kestrel::{Ekf, Filter, FilterError, Quantity, SrUkf, Ukf};
use proptest::prelude::*;
use support::bits;

const CASES: u32 = 2500;

/// What a filter looks like from outside, to the bit.
fn snapshot<F: kestrel::form::Form<f64, 3>>(f: &Filter<f64, 3, F>) -> (Vec<u64>, Vec<u64>) {
    (bits(f.state()), bits(&f.covariance()))
}

/// A random symmetric positive-definite `D×D` matrix: `A Aᵀ + I/10`.
fn spd<const D: usize>(entries: &[f64]) -> SMatrix<f64, D, D> {
    let a = SMatrix::<f64, D, D>::from_iterator(entries.iter().copied());
    a * a.transpose() + SMatrix::identity() * 0.1
}

/// How a valid covariance is spoiled.
#[derive(Debug, Clone, Copy)]
enum Spoil {
    /// Variance `k` made negative.
    NegativeVariance(usize),
    /// Off-diagonal `(i, j)` shifted by `δ` times the scale (asymmetric).
    Asymmetric(usize, usize, f64),
    /// Entry `(i, j)` made NaN or infinite.
    NonFinite(usize, usize, f64),
    /// Subtract `c v vᵀ` with `c` beyond the matrix's reach along `v`.
    Indefinite([f64; 3], f64),
}

fn spoil_strategy() -> impl Strategy<Value = Spoil> {
    prop_oneof![
        (0..3usize).prop_map(Spoil::NegativeVariance),
        (0..3usize, 0..3usize, 1e-4..10.0f64)
            .prop_filter("off-diagonal", |(i, j, _)| i != j)
            .prop_map(|(i, j, d)| Spoil::Asymmetric(i, j, d)),
        (
            0..3usize,
            0..3usize,
            prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)]
        )
            .prop_map(|(i, j, v)| Spoil::NonFinite(i, j, v)),
        (prop::array::uniform3(-1.0..1.0f64), 1.01..10.0f64)
            .prop_filter("a direction", |(v, _)| v.iter().map(|x| x * x).sum::<f64>()
                > 0.01)
            .prop_map(|(v, c)| Spoil::Indefinite(v, c)),
    ]
}

/// `a` spoiled (only the leading `D×D` block of the spoil's indices used).
fn spoiled<const D: usize>(mut a: SMatrix<f64, D, D>, spoil: Spoil) -> SMatrix<f64, D, D> {
    match spoil {
        Spoil::NegativeVariance(k) => {
            let k = k % D;
            a[(k, k)] = -a[(k, k)].abs() - 0.01;
        }
        Spoil::Asymmetric(i, j, d) => {
            let (i, j) = (i % D, j % D);
            let (i, j) = if i == j { (0, D - 1) } else { (i, j) };
            a[(i, j)] += d * (a[(i, i)] * a[(j, j)]).sqrt();
        }
        Spoil::NonFinite(i, j, v) => a[(i % D, j % D)] = v,
        Spoil::Indefinite(v, c) => {
            let v = SMatrix::<f64, D, 1>::from_iterator(v.iter().copied());
            // vᵀ A⁻¹ v is the largest c for which A − c v vᵀ stays PSD.
            let reach = v.dot(&(a.try_inverse().unwrap() * v));
            a -= v * v.transpose() * (c / reach);
            // Exactly symmetric: only definiteness is spoiled.
            a = (a + a.transpose()) * 0.5;
        }
    }
    a
}

/// Runs `f` on a fresh filter of every form, each after a valid predict
/// (so a prediction is pending) when `pending`; returns the errors.
macro_rules! on_every_form {
    ($x0:expr, $p0:expr, $pending:expr, |$f:ident| $call:expr) => {{
        let mut errors = Vec::new();
        let good = LinearProcess::new(Matrix3::identity(), Matrix3::identity() * 0.01);
        macro_rules! run {
            ($filter:expr) => {{
                let mut $f = $filter;
                if $pending {
                    $f.predict(&good, 1.0).unwrap();
                }
                let before = snapshot(&$f);
                let form_before = $f.form().clone();
                let result: Result<(), FilterError> = $call;
                prop_assert_eq!(snapshot(&$f), before);
                prop_assert!(*$f.form() == form_before);
                errors.push(result.err());
            }};
        }
        run!({
            let mut f = Ekf::new($x0, $p0).unwrap();
            f.form_mut().set_sequential(true);
            f
        });
        run!({
            let mut f = Ekf::new($x0, $p0).unwrap();
            f.form_mut().set_sequential(false);
            f
        });
        run!(Ukf::new($x0, $p0).unwrap());
        run!(SrUkf::new($x0, $p0).unwrap());
        errors
    }};
}

/// All the same, and equal to `want`.
fn all_equal(errors: &[Option<FilterError>], want: FilterError) -> Result<(), TestCaseError> {
    for e in errors {
        prop_assert_eq!(*e, Some(want));
    }
    Ok(())
}

fn config() -> ProptestConfig {
    ProptestConfig::with_cases(CASES)
}

/// Every form refuses the measurement (update) path through `model`.
fn update_everywhere(
    x0: Vector3<f64>,
    p0: Matrix3<f64>,
    pending: bool,
    model: &LinearMeasurement<f64, 3, 2>,
) -> Result<Vec<Option<FilterError>>, TestCaseError> {
    let z = Vector2::new(0.5, -0.5);
    Ok(on_every_form!(x0, p0, pending, |f| f
        .update(model, &z)
        .map(|_| ())))
}

/// Every form refuses the predict through `model` with step `dt`.
fn predict_everywhere(
    x0: Vector3<f64>,
    p0: Matrix3<f64>,
    pending: bool,
    model: &LinearProcess<f64, 3>,
    dt: f64,
) -> Result<Vec<Option<FilterError>>, TestCaseError> {
    Ok(on_every_form!(x0, p0, pending, |f| f.predict(model, dt)))
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn invalid_measurement_noise(
        p in prop::collection::vec(-1.0..1.0f64, 9),
        r in prop::collection::vec(-1.0..1.0f64, 4),
        diagonal in any::<bool>(),
        spoil in spoil_strategy(),
        pending in any::<bool>(),
    ) {
        let mut r = spd::<2>(&r);
        if diagonal {
            r = Matrix2::from_diagonal(&r.diagonal());
        }
        let r = spoiled(r, spoil);
        let want = check_covariance(&r, Quantity::MeasurementNoise).unwrap_err();
        let h = Matrix2x3::new(1.0, 0.0, 0.5, 0.0, 1.0, -0.5);
        let model = LinearMeasurement::new(h, r);
        let errors = update_everywhere(Vector3::new(1.0, -2.0, 0.5), spd::<3>(&p), pending, &model)?;
        all_equal(&errors, want)?;
    }

    #[test]
    fn invalid_process_noise(
        p in prop::collection::vec(-1.0..1.0f64, 9),
        q in prop::collection::vec(-1.0..1.0f64, 9),
        spoil in spoil_strategy(),
        pending in any::<bool>(),
    ) {
        let q = spoiled(spd::<3>(&q), spoil);
        let want = check_covariance(&q, Quantity::ProcessNoise).unwrap_err();
        let model = LinearProcess::new(Matrix3::identity(), q);
        let errors = predict_everywhere(Vector3::zeros(), spd::<3>(&p), pending, &model, 0.1)?;
        all_equal(&errors, want)?;
    }

    #[test]
    fn invalid_initial_covariance(
        p in prop::collection::vec(-1.0..1.0f64, 9),
        spoil in spoil_strategy(),
    ) {
        let p0 = spoiled(spd::<3>(&p), spoil);
        let want = check_covariance(&p0, Quantity::StateCovariance).unwrap_err();
        let x0 = Vector3::new(1.0, 2.0, 3.0);
        prop_assert_eq!(Ekf::new(x0, p0).err(), Some(want));
        prop_assert_eq!(Ukf::new(x0, p0).err(), Some(want));
        prop_assert_eq!(SrUkf::new(x0, p0).err(), Some(want));
        // And through the setter, which leaves the filter as it was.
        let good = spd::<3>(&p);
        let errors = on_every_form!(x0, good, true, |f| f.set_covariance(&p0));
        all_equal(&errors, want)?;
    }

    #[test]
    fn invalid_time_step(
        p in prop::collection::vec(-1.0..1.0f64, 9),
        dt in prop_oneof![
            (-1e6..-1e-12f64).boxed(),
            Just(f64::NAN).boxed(),
            Just(f64::INFINITY).boxed(),
            Just(f64::NEG_INFINITY).boxed(),
        ],
        pending in any::<bool>(),
    ) {
        let want = if dt.is_finite() {
            FilterError::NegativeTimeStep
        } else {
            FilterError::NonFinite { what: Quantity::TimeStep, row: 0, col: 0 }
        };
        let model = LinearProcess::new(Matrix3::identity(), Matrix3::identity());
        let errors = predict_everywhere(Vector3::zeros(), spd::<3>(&p), pending, &model, dt)?;
        all_equal(&errors, want)?;
    }
}
