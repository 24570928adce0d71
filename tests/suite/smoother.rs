//! The RTS smoother (`kestrel::smoother`):
//!
//! - equals an RTS computed by hand in exact rational arithmetic (textbook
//!   covariance recursion) on a two-state example;
//! - equals the batch least-squares (information-form) solution of a
//!   linear-Gaussian model, means and covariance blocks, to 1e-9;
//! - keeps every smoothed covariance exactly symmetric, positive definite
//!   and no larger than the filtered one (property test on random models);
//! - refuses bad use and bad records with typed errors;
//! - runs in `f32` close to `f64`.
//!
//! The smoother's zero-allocation test is in `no_alloc.rs`.

use crate::support;

use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix1x2, Matrix2, SMatrix, SVector, Vector1, Vector2};
use kestrel::smoother::{RtsEpoch, RtsRecord, Smoothed, SmootherError};
use kestrel::{Ekf, FilterError, Quantity};
use proptest::prelude::*;
use support::{assert_close, assert_scalar};

/// Smooths the two-state example of `hand_computed_two_state_example` in
/// scalar `T`.
fn two_state<T: kestrel::Real>() -> [Smoothed<T, 2>; 3] {
    let l = kestrel::real::lit::<T>;
    let motion = LinearProcess::new(
        Matrix2::new(l(1.0), l(1.0), l(0.0), l(1.0)),
        Matrix2::new(l(0.25), l(0.0), l(0.0), l(0.5)),
    );
    let position = LinearMeasurement::new(
        Matrix1x2::new(l(1.0), l(0.0)),
        SMatrix::from_element(l(1.0)),
    );
    let mut filter = Ekf::new(Vector2::new(l(0.0), l(1.0)), Matrix2::identity()).unwrap();
    let mut storage = [RtsEpoch::default(); 3];
    let mut record = RtsRecord::new(&mut storage);
    record.start(&filter).unwrap();
    for z in [2.0, 3.0] {
        record.predict(&mut filter, &motion, l(1.0)).unwrap();
        filter.update(&position, &Vector1::new(l(z))).unwrap();
        record.observe(&filter).unwrap();
    }
    let mut out = [Smoothed::default(); 3];
    record.smooth(&mut out).unwrap();
    out
}

/// `Φ = [1 1; 0 1]`, `Q = diag(¼, ½)`, `H = [1 0]`, `R = 1`, `x₀ = (0, 1)`,
/// `P₀ = I`, fixes 2 and 3. The expected values were computed in exact
/// fractions with the textbook recursion `Pˢ = P⁺ + C (Pˢ₊ − P⁻₊) Cᵀ`
/// (the smoother uses the rearranged form), filter in the simple form
/// `P⁺ = (I − K H) P⁻`.
#[test]
fn hand_computed_two_state_example() {
    let out = two_state::<f64>();
    let want = [
        (
            [4.0 / 13.0, 17.0 / 13.0],
            [9.0 / 13.0, -4.0 / 13.0, 83.0 / 195.0],
        ),
        (
            [22.0 / 13.0, 17.0 / 13.0],
            [83.0 / 195.0, -6.0 / 65.0, 77.0 / 130.0],
        ),
        ([3.0, 17.0 / 13.0], [11.0 / 15.0, 2.0 / 5.0, 71.0 / 65.0]),
    ];
    for (k, (s, (x, p))) in out.iter().zip(want).enumerate() {
        assert_close(
            &s.state,
            &Vector2::new(x[0], x[1]),
            1e-14,
            &format!("x at {k}"),
        );
        let p = Matrix2::new(p[0], p[1], p[1], p[2]);
        assert_close(&s.covariance, &p, 1e-14, &format!("P at {k}"));
    }
}

#[test]
fn f32_smoothing_agrees_with_f64() {
    let single = two_state::<f32>();
    let double = two_state::<f64>();
    for (s, d) in single.iter().zip(&double) {
        assert_close(&s.state.cast::<f64>(), &d.state, 1e-5, "state");
        assert_close(
            &s.covariance.cast::<f64>(),
            &d.covariance,
            1e-5,
            "covariance",
        );
    }
}

const N: usize = 3;
const EPOCHS: usize = 5;
const ALL: usize = N * EPOCHS;

/// A three-state linear-Gaussian model with position fixes at epochs 1, 3
/// and 4 (none at 2, two at 4).
struct Linear {
    phi: SMatrix<f64, N, N>,
    q: SMatrix<f64, N, N>,
    h: SMatrix<f64, 1, N>,
    r: f64,
    m0: SVector<f64, N>,
    p0: SMatrix<f64, N, N>,
    /// `(epoch, z)` in order.
    fixes: Vec<(usize, f64)>,
}

fn linear_case() -> Linear {
    let dt = 0.5;
    Linear {
        phi: SMatrix::<f64, N, N>::new(1.0, dt, 0.5 * dt * dt, 0.0, 1.0, dt, 0.0, 0.0, 0.9),
        q: SMatrix::<f64, N, N>::new(0.02, 0.01, 0.0, 0.01, 0.05, 0.01, 0.0, 0.01, 0.1),
        h: SMatrix::<f64, 1, N>::new(1.0, 0.0, 0.0),
        r: 0.3,
        m0: SVector::<f64, N>::new(0.5, -1.0, 0.2),
        p0: SMatrix::<f64, N, N>::new(2.0, 0.3, 0.0, 0.3, 1.0, 0.1, 0.0, 0.1, 0.5),
        fixes: vec![(1, 0.1), (3, -1.2), (4, -1.9), (4, -2.3)],
    }
}

/// The smoothed means and covariances of all epochs as the solution of the
/// joint quadratic in `(x₀ … x₄)`: information matrix `Λ` and vector `η`,
/// mean `Λ⁻¹ η`, covariance blocks of `Λ⁻¹`.
fn batch(case: &Linear) -> (SVector<f64, ALL>, SMatrix<f64, ALL, ALL>) {
    let mut lambda = SMatrix::<f64, ALL, ALL>::zeros();
    let mut eta = SVector::<f64, ALL>::zeros();
    let p0i = case.p0.try_inverse().unwrap();
    lambda.fixed_view_mut::<N, N>(0, 0).add_assign(&p0i);
    eta.fixed_rows_mut::<N>(0).add_assign(&(p0i * case.m0));
    let qi = case.q.try_inverse().unwrap();
    for k in 0..EPOCHS - 1 {
        // (x_{k+1} − Φ x_k)ᵀ Q⁻¹ (…) with the block row [−Φ, I].
        let (a, b) = (k * N, (k + 1) * N);
        let phi = case.phi;
        lambda
            .fixed_view_mut::<N, N>(a, a)
            .add_assign(&(phi.transpose() * qi * phi));
        lambda
            .fixed_view_mut::<N, N>(a, b)
            .add_assign(&(-phi.transpose() * qi));
        lambda.fixed_view_mut::<N, N>(b, a).add_assign(&(-qi * phi));
        lambda.fixed_view_mut::<N, N>(b, b).add_assign(&qi);
    }
    for &(k, z) in &case.fixes {
        let h = case.h;
        let o = k * N;
        lambda
            .fixed_view_mut::<N, N>(o, o)
            .add_assign(&(h.transpose() * h / case.r));
        eta.fixed_rows_mut::<N>(o)
            .add_assign(&(h.transpose() * (z / case.r)));
    }
    let cov = lambda.cholesky().unwrap().inverse();
    (cov * eta, cov)
}

use std::ops::AddAssign;

#[test]
fn equals_the_batch_least_squares_solution() {
    let case = linear_case();
    let motion = LinearProcess::new(case.phi, case.q);
    let fix = LinearMeasurement::new(case.h, SMatrix::from_element(case.r));
    let mut filter = Ekf::new(case.m0, case.p0).unwrap();
    let mut storage = [RtsEpoch::default(); EPOCHS];
    let mut record = RtsRecord::new(&mut storage);
    record.start(&filter).unwrap();
    for k in 1..EPOCHS {
        record.predict(&mut filter, &motion, 0.5).unwrap();
        for &(_, z) in case.fixes.iter().filter(|(e, _)| *e == k) {
            filter.update(&fix, &Vector1::new(z)).unwrap();
        }
        record.observe(&filter).unwrap();
    }
    let mut out = [Smoothed::default(); EPOCHS];
    record.smooth(&mut out).unwrap();
    let (mean, cov) = batch(&case);
    for (k, s) in out.iter().enumerate() {
        let o = k * N;
        let want_x: SVector<f64, N> = mean.fixed_rows::<N>(o).into();
        let want_p: SMatrix<f64, N, N> = cov.fixed_view::<N, N>(o, o).into();
        assert_close(&s.state, &want_x, 1e-9, &format!("mean at epoch {k}"));
        assert_close(
            &s.covariance,
            &want_p,
            1e-9,
            &format!("covariance at epoch {k}"),
        );
    }
    // The smoother changed every epoch but the last (not a vacuous match).
    let filtered = record.epochs();
    assert!((out[2].state - filtered[2].posterior_state).norm() > 1e-2);
    assert_eq!(out[4].state, filtered[4].posterior_state);
}

/// A random stable model, an initial covariance and a measurement sequence.
#[derive(Debug, Clone)]
struct RandomCase {
    phi: SMatrix<f64, 4, 4>,
    q_root: SMatrix<f64, 4, 4>,
    h: SMatrix<f64, 2, 4>,
    r_diag: [f64; 2],
    p0_root: SMatrix<f64, 4, 4>,
    /// Per epoch: a measurement, or none.
    z: Vec<Option<[f64; 2]>>,
}

fn random_case() -> impl Strategy<Value = RandomCase> {
    let m44 = || {
        proptest::array::uniform16(-1.0f64..1.0)
            .prop_map(|a| SMatrix::<f64, 4, 4>::from_column_slice(&a))
    };
    (
        m44(),
        m44(),
        proptest::array::uniform8(-2.0f64..2.0),
        [1e-3f64..10.0, 1e-3f64..10.0],
        m44(),
        proptest::collection::vec(
            proptest::option::of([-50.0f64..50.0, -50.0f64..50.0]),
            1..40,
        ),
        0.0f64..1.0,
    )
        .prop_map(|(phi, q_root, h, r_diag, p0_root, z, q_scale)| RandomCase {
            // Spectral radius below about 1.2: stable enough for 40 steps.
            phi: SMatrix::identity() * 0.8 + phi * 0.1,
            q_root: q_root * 10f64.powf(-4.0 * q_scale),
            h: SMatrix::<f64, 2, 4>::from_column_slice(&h),
            r_diag,
            p0_root,
            z,
        })
}

/// Whether `a − b` is positive semi-definite up to rounding relative to `a`.
fn dominates(a: &SMatrix<f64, 4, 4>, b: &SMatrix<f64, 4, 4>) -> bool {
    let d = a - b;
    let eig = d.symmetric_eigenvalues();
    eig.min() >= -1e-9 * a.abs().max().max(1e-300)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn smoothed_covariances_are_symmetric_definite_and_no_larger(case in random_case()) {
        let q = case.q_root * case.q_root.transpose() + SMatrix::<f64, 4, 4>::identity() * 1e-6;
        let p0 = case.p0_root * case.p0_root.transpose() + SMatrix::<f64, 4, 4>::identity() * 1e-3;
        let motion = LinearProcess::new(case.phi, q);
        let r = SMatrix::<f64, 2, 2>::from_diagonal(&case.r_diag.into());
        let sensor = LinearMeasurement::new(case.h, r);
        let mut filter = Ekf::new(SVector::zeros(), p0).unwrap();
        let mut storage = vec![RtsEpoch::default(); case.z.len() + 1];
        let mut record = RtsRecord::new(&mut storage);
        record.start(&filter).unwrap();
        for z in &case.z {
            record.predict(&mut filter, &motion, 1.0).unwrap();
            if let Some(z) = z {
                filter.update(&sensor, &(*z).into()).unwrap();
                record.observe(&filter).unwrap();
            }
        }
        let mut out = vec![Smoothed::default(); record.len()];
        record.smooth(&mut out).unwrap();
        for (k, (s, e)) in out.iter().zip(record.epochs()).enumerate() {
            prop_assert_eq!(s.covariance, s.covariance.transpose(), "symmetric at {}", k);
            prop_assert!(s.covariance.cholesky().is_some(), "definite at {}: {}", k, s.covariance);
            prop_assert!(
                dominates(&e.posterior_covariance, &s.covariance),
                "Pˢ ≤ P⁺ at {}: {} vs {}", k, s.covariance, e.posterior_covariance
            );
        }
    }
}

#[test]
fn misuse_and_bad_records_give_typed_errors() {
    let motion = LinearProcess::new(Matrix2::identity(), Matrix2::identity());
    let mut filter = Ekf::new(Vector2::zeros(), Matrix2::identity()).unwrap();
    let mut storage = [RtsEpoch::default(); 2];
    let mut record = RtsRecord::new(&mut storage);
    assert_eq!(
        record.predict(&mut filter, &motion, 1.0),
        Err(SmootherError::NotStarted)
    );
    assert_eq!(record.observe(&filter), Err(SmootherError::NotStarted));
    record.start(&filter).unwrap();
    record.predict(&mut filter, &motion, 1.0).unwrap();
    // Full: refused before the filter moves.
    let before = filter.covariance();
    assert_eq!(
        record.predict(&mut filter, &motion, 1.0),
        Err(SmootherError::Full { capacity: 2 })
    );
    assert_eq!(filter.covariance(), before);
    // A refused predict leaves the record unchanged.
    record.start(&filter).unwrap();
    assert_eq!(
        record.predict(&mut filter, &motion, -1.0),
        Err(SmootherError::Filter(FilterError::NegativeTimeStep))
    );
    assert_eq!(record.len(), 1);
    record.predict(&mut filter, &motion, 1.0).unwrap();
    let mut short = [Smoothed::default(); 1];
    assert_eq!(
        record.smooth(&mut short),
        Err(SmootherError::OutputTooShort {
            needed: 2,
            given: 1
        })
    );

    // Records built by hand: an indefinite prior, a NaN transition.
    let this = RtsEpoch::initial(Vector2::new(0.0, 0.0), Matrix2::identity());
    let mut bad = RtsEpoch::predicted(Matrix2::identity(), Vector2::zeros(), Matrix2::identity());
    bad.prior_covariance[(1, 1)] = -1.0;
    let mut storage = [this, bad];
    let mut out = [Smoothed::default(); 2];
    let record = RtsRecord::new(&mut storage);
    assert_eq!(record.smooth(&mut out), Ok(())); // nothing recorded: nothing to do
    let mut storage2 = [this, bad];
    let mut record = RtsRecord::new(&mut storage2);
    record.push(this).unwrap();
    record.push(bad).unwrap();
    let e = record.smooth(&mut out).unwrap_err();
    assert_eq!(
        e,
        SmootherError::Backward {
            epoch: 0,
            error: FilterError::NotPositiveDefinite {
                what: Quantity::PropagatedCovariance,
                index: 1
            }
        }
    );
    assert_eq!(
        e.to_string(),
        "smoothing epoch 0: propagated covariance is not positive semi-definite (first failing row and column: 1)"
    );
    let mut nan = RtsEpoch::predicted(Matrix2::identity(), Vector2::zeros(), Matrix2::identity());
    nan.transition[(0, 1)] = f64::NAN;
    let mut storage3 = [RtsEpoch::default(); 2];
    let mut record = RtsRecord::new(&mut storage3);
    record.push(this).unwrap();
    record.push(nan).unwrap();
    assert!(matches!(
        record.smooth(&mut out),
        Err(SmootherError::Backward {
            epoch: 0,
            error: FilterError::NonFinite {
                what: Quantity::SmoothedState | Quantity::SmoothedCovariance,
                ..
            }
        })
    ));
}

/// A smoother over an angle state with wrapped arithmetic: the correction
/// is taken across ±π, not the long way round.
#[test]
fn a_state_space_wraps_the_correction() {
    use kestrel::StateSpace;
    struct Wrapped;
    impl StateSpace<f64, 1> for Wrapped {
        fn add(&self, x: &Vector1<f64>, dx: &Vector1<f64>) -> Vector1<f64> {
            Vector1::new(wrap(x[0] + dx[0]))
        }
        fn difference(&self, a: &Vector1<f64>, b: &Vector1<f64>) -> Vector1<f64> {
            Vector1::new(wrap(a[0] - b[0]))
        }
    }
    fn wrap(a: f64) -> f64 {
        use std::f64::consts::PI;
        (a + PI).rem_euclid(2.0 * PI) - PI
    }
    let pi = std::f64::consts::PI;
    let mut storage = [
        RtsEpoch::initial(Vector1::new(pi - 0.1), SMatrix::from_element(1.0)),
        RtsEpoch::predicted(
            SMatrix::from_element(1.0),
            Vector1::new(pi - 0.1),
            SMatrix::from_element(2.0),
        ),
    ];
    storage[1].set_posterior(Vector1::new(-pi + 0.1), SMatrix::from_element(1.0));
    let mut slots = [RtsEpoch::default(); 2];
    let mut record = RtsRecord::new(&mut slots);
    for e in storage {
        record.push(e).unwrap();
    }
    let mut out = [Smoothed::default(); 2];
    record.smooth_in(&Wrapped, &mut out).unwrap();
    // C = ½; the later estimate is 0.2 rad ahead across π: +0.1 rad.
    assert_scalar(
        wrap(out[0].state[0] - (-pi)),
        0.0,
        1e-12,
        "smoothed angle at π",
    );
}
