//! Federated fusion on hand-computed numbers: the information-form fusion of
//! two 2-D estimates, the reset by sharing factors (including the
//! square-root local's refactorisation), arrays of locals, the shared
//! process noise, parameter validation and the typed errors naming a local.

use approx::assert_relative_eq;
use kestrel_adaptive::federated::{
    fuse, FederatedFilter, FusionError, Information, Isolation, LocalFilter, SharedNoise, Sharing,
};
use kestrel_core::nalgebra::{Matrix1, Matrix2, Matrix4, Vector1, Vector2, Vector4};
use kestrel_core::{Ekf, FilterError, LinearizedProcess, ProcessModel, SrUkf, Ukf};
use kestrel_models::LinearProcess;

/// Local 1: x₁ = (1, 2), P₁ = diag(2, 1), so P₁⁻¹ = diag(1/2, 1).
fn first() -> (Vector2<f64>, Matrix2<f64>) {
    (Vector2::new(1.0, 2.0), Matrix2::new(2.0, 0.0, 0.0, 1.0))
}

/// Local 2: x₂ = (3, 1), P₂ = [[2, 1], [1, 1]] (det 1), P₂⁻¹ = [[1, −1], [−1, 2]].
fn second() -> (Vector2<f64>, Matrix2<f64>) {
    (Vector2::new(3.0, 1.0), Matrix2::new(2.0, 1.0, 1.0, 1.0))
}

/// By hand: Σ P⁻¹ = [[3/2, −1], [−1, 3]] (det 7/2), so
/// P_g = (2/7) [[3, 1], [1, 3/2]] = [[6/7, 2/7], [2/7, 3/7]];
/// Σ P⁻¹ x = (1/2, 2) + (3 − 1, −3 + 2) = (5/2, 1), so
/// x_g = P_g (5/2, 1) = ((15 + 2)/7, (5 + 3)/7) = (17/7, 8/7).
fn hand_fused() -> (Vector2<f64>, Matrix2<f64>) {
    (
        Vector2::new(17.0 / 7.0, 8.0 / 7.0),
        Matrix2::new(6.0, 2.0, 2.0, 3.0) / 7.0,
    )
}

#[test]
fn two_2d_estimates_fuse_to_the_hand_computed_result() {
    let (xg, pg) = hand_fused();
    let (x, p) = fuse(&[first(), second()]).unwrap();
    assert_relative_eq!(x, xg, epsilon = 1e-15);
    assert_relative_eq!(p, pg, epsilon = 1e-15);
    // Symmetric to the last bit: the inverse is formed as Wᵀ W.
    assert_eq!(p[(0, 1)], p[(1, 0)]);
    // The order of the locals does not matter.
    let (x, p) = fuse(&[second(), first()]).unwrap();
    assert_relative_eq!(x, xg, epsilon = 1e-15);
    assert_relative_eq!(p, pg, epsilon = 1e-15);

    // The accumulator's sums are the hand-computed information.
    let mut info = Information::new();
    info.add(0, &first().0, &first().1).unwrap();
    info.add(1, &second().0, &second().1).unwrap();
    assert_relative_eq!(
        *info.matrix(),
        Matrix2::new(1.5, -1.0, -1.0, 3.0),
        epsilon = 1e-15
    );
    assert_relative_eq!(*info.vector(), Vector2::new(2.5, 1.0), epsilon = 1e-15);
    assert_eq!(info.count(), 2);
}

#[test]
fn federated_filter_fuses_and_resets_by_the_shares() {
    let (xg, pg) = hand_fused();
    let locals = (
        Ekf::new(Vector2::zeros(), Matrix2::identity()).unwrap(),
        SrUkf::new(Vector2::zeros(), Matrix2::identity()).unwrap(),
    );
    let sharing = Sharing::fixed([0.25, 0.75]).unwrap();
    let mut fed =
        FederatedFilter::new(locals, sharing, Vector2::zeros(), Matrix2::identity()).unwrap();
    // The constructor distributed P(0) / β_i.
    assert_relative_eq!(fed.locals().0.covariance(), Matrix2::identity() * 4.0);
    assert_relative_eq!(
        fed.locals().1.covariance(),
        Matrix2::identity() / 0.75,
        epsilon = 1e-15
    );

    let (a, b) = fed.locals_mut();
    a.reset(&first().0, &first().1).unwrap();
    b.reset(&second().0, &second().1).unwrap();
    let report = fed.fuse().unwrap();
    assert_eq!(report.fused, 2);
    assert_eq!(report.admitted(), [true, true]);
    assert_eq!(report.shares(), [0.25, 0.75]);
    // EDOP = sqrt(tr(P Pᵀ)): sqrt(4 + 1) and sqrt(4 + 1 + 1 + 1).
    assert_relative_eq!(report.edops()[0], 5f64.sqrt(), epsilon = 1e-15);
    assert_relative_eq!(report.edops()[1], 7f64.sqrt(), epsilon = 1e-15);
    assert_relative_eq!(*fed.state(), xg, epsilon = 1e-14);
    assert_relative_eq!(*fed.covariance(), pg, epsilon = 1e-14);

    // Reset: x_i = x_g, P_i = P_g / β_i; the square-root local holds the
    // Cholesky factor of P_g / 0.75.
    let (a, b) = fed.locals();
    assert_relative_eq!(*a.state(), xg, epsilon = 1e-14);
    assert_relative_eq!(*b.state(), xg, epsilon = 1e-14);
    assert_relative_eq!(a.covariance(), pg * 4.0, epsilon = 1e-14);
    let s = b.form().factor();
    assert_eq!(s[(0, 1)], 0.0);
    // chol([[6, 2], [2, 3]] / 5.25) = [[√(6/5.25), 0], [2/√(6·5.25), √((3 − 4/6)/5.25)]].
    let expected = Matrix2::new(
        (6.0f64 / 5.25).sqrt(),
        0.0,
        2.0 / (6.0f64 * 5.25).sqrt(),
        ((3.0 - 4.0 / 6.0) / 5.25f64).sqrt(),
    );
    assert_relative_eq!(s, expected, epsilon = 1e-14);
}

#[test]
fn no_reset_fuses_without_touching_the_locals() {
    let (xg, pg) = hand_fused();
    let locals = (
        Ukf::new(Vector2::zeros(), Matrix2::identity()).unwrap(),
        Ekf::new(Vector2::zeros(), Matrix2::identity()).unwrap(),
    );
    let sharing = Sharing::no_reset([0.5, 0.5]).unwrap();
    let mut fed =
        FederatedFilter::new(locals, sharing, Vector2::zeros(), Matrix2::identity()).unwrap();
    // Carlson's no-reset start: P_i(0) = P(0) / β_i.
    assert_eq!(fed.locals().0.covariance(), Matrix2::identity() * 2.0);
    let (a, b) = fed.locals_mut();
    a.reset(&first().0, &first().1).unwrap();
    b.reset(&second().0, &second().1).unwrap();
    let report = fed.fuse().unwrap();
    assert_eq!(report.shares(), [0.5, 0.5]);
    assert_relative_eq!(*fed.state(), xg, epsilon = 1e-14);
    assert_relative_eq!(*fed.covariance(), pg, epsilon = 1e-14);
    assert_eq!(fed.locals().0.estimate(), first());
    assert_eq!(fed.locals().1.estimate(), second());
}

#[test]
fn an_array_of_locals_fuses_three_scalars() {
    // Three scalar estimates 1, 2, 4 with variances 1, 2, 4: information
    // 1 + 1/2 + 1/4 = 7/4, so P_g = 4/7 and x_g = (4/7)(1 + 1 + 1) = 12/7.
    let locals: [Ekf<f64, 1>; 3] =
        core::array::from_fn(|_| Ekf::new(Vector1::zeros(), Matrix1::new(1.0)).unwrap());
    let mut fed = FederatedFilter::new(
        locals,
        Sharing::equal(),
        Vector1::zeros(),
        Matrix1::new(1.0),
    )
    .unwrap();
    assert_eq!(fed.locals()[2].covariance()[0], 3.0);
    for (i, f) in fed.locals_mut().iter_mut().enumerate() {
        let v = (1 << i) as f64;
        f.reset(&Vector1::new(v), &Matrix1::new(v)).unwrap();
    }
    let report = fed.fuse().unwrap();
    assert_eq!(report.fused, 3);
    assert_relative_eq!(fed.state()[0], 12.0 / 7.0, epsilon = 1e-15);
    assert_relative_eq!(fed.covariance()[0], 4.0 / 7.0, epsilon = 1e-15);
    for f in fed.locals() {
        assert_relative_eq!(f.covariance()[0], 12.0 / 7.0, epsilon = 1e-14);
    }
}

#[test]
fn shared_noise_divides_only_the_noise_by_the_share() {
    let phi = Matrix2::new(1.0, 0.5, 0.0, 1.0);
    let q = Matrix2::new(0.3, 0.1, 0.1, 0.2);
    let model = LinearProcess::new(phi, q);
    let shared = SharedNoise::new(&model, 0.4).unwrap();
    let x = Vector2::new(1.0, -2.0);
    assert_eq!(shared.propagate(&x, 1.0), Vector2::new(0.0, -2.0));
    assert_eq!(shared.transition(&x, 1.0), phi);
    assert_relative_eq!(shared.noise(&x, 1.0), q * 2.5, epsilon = 1e-15);
    assert_eq!(shared.share(), 0.4);
    assert_eq!(SharedNoise::new(&model, 1.0).unwrap().noise(&x, 1.0), q);
    for bad in [0.0, -0.5, 1.5, f64::NAN, f64::INFINITY, 1e-320] {
        assert_eq!(
            SharedNoise::new(&model, bad).unwrap_err(),
            FilterError::InvalidParameter {
                name: "share",
                valid: "0 < share ≤ 1, with a finite reciprocal"
            },
            "share {bad}"
        );
    }
}

#[test]
fn parameters_are_validated() {
    let shares = FilterError::InvalidParameter {
        name: "shares",
        valid: "L finite shares, each in (0, 1], summing to 1",
    };
    for bad in [
        [0.5, 0.0],
        [0.5, -0.1],
        [0.5, f64::NAN],
        [0.6, 0.5],
        [1.5, 0.1],
    ] {
        assert_eq!(Sharing::fixed(bad).unwrap_err(), shares, "{bad:?}");
        assert_eq!(Sharing::no_reset(bad).unwrap_err(), shares, "{bad:?}");
    }
    // A sum of exactly 1 up to rounding (0.1 + 0.2 + 0.7 > 1 in binary), and
    // a sum below 1, are valid.
    assert!(Sharing::fixed([0.1, 0.2, 0.7]).is_ok());
    assert!(Sharing::fixed([0.2, 0.3]).is_ok());
    assert!(Sharing::fixed([1.0, 1e-9]).is_err());

    assert_eq!(
        Isolation::<f64>::new(0.0, 2, 2).unwrap_err(),
        FilterError::InvalidParameter {
            name: "alpha",
            valid: "0 < alpha < 1"
        }
    );
    assert!(Isolation::<f64>::new(1.0, 2, 2).is_err());
    assert!(Isolation::<f64>::new(f64::NAN, 2, 2).is_err());
    assert_eq!(
        Isolation::<f64>::new(0.01, 0, 2).unwrap_err(),
        FilterError::InvalidParameter {
            name: "fail_after",
            valid: "at least 1"
        }
    );
    assert_eq!(
        Isolation::<f64>::new(0.01, 2, 0).unwrap_err(),
        FilterError::InvalidParameter {
            name: "readmit_after",
            valid: "at least 1"
        }
    );
    let iso = Isolation::<f64>::new(0.05, 2, 2).unwrap();
    assert_eq!(
        iso.threshold(0).unwrap_err(),
        FilterError::InvalidParameter {
            name: "dof",
            valid: "at least 1 (the measurement dimension M)"
        }
    );
    // χ²_{0.95}(2) = −2 ln 0.05; beyond the precomputed dimensions the
    // quantile is computed on demand: χ²_{0.95}(20) = 31.4104 (tables).
    assert_relative_eq!(
        iso.threshold(2).unwrap(),
        -2.0 * 0.05f64.ln(),
        epsilon = 1e-9
    );
    assert_relative_eq!(iso.threshold(20).unwrap(), 31.4104, epsilon = 1e-4);
}

#[test]
fn errors_name_the_local_and_change_nothing() {
    // Indefinite second covariance: pivot 1 of [[1, 2], [2, 1]] is −3.
    let bad = (Vector2::new(0.0, 0.0), Matrix2::new(1.0, 2.0, 2.0, 1.0));
    assert_eq!(
        fuse(&[first(), bad]).unwrap_err(),
        FusionError::NotPositiveDefinite { local: 1, index: 1 }
    );
    let nan = (Vector2::new(f64::NAN, 0.0), Matrix2::identity());
    assert_eq!(
        fuse(&[first(), second(), nan]).unwrap_err(),
        FusionError::NonFinite { local: 2 }
    );
    assert_eq!(fuse::<f64, 2>(&[]).unwrap_err(), FusionError::AllIsolated);
    let mut info = Information::new();
    info.add(0, &first().0, &first().1).unwrap();
    let before = info;
    assert!(info.add(1, &bad.0, &bad.1).is_err());
    assert_eq!(info, before);

    let locals = (
        Ekf::new(Vector2::zeros(), Matrix2::identity()).unwrap(),
        Ekf::new(Vector2::zeros(), Matrix2::identity()).unwrap(),
    );
    let iso = Isolation::new(0.01, 1, 1).unwrap();
    let mut fed = FederatedFilter::new(
        locals,
        Sharing::equal(),
        Vector2::zeros(),
        Matrix2::identity(),
    )
    .unwrap()
    .with_isolation(iso);
    // A failing test is recorded, then the fusion fails on local 1.
    fed.record_nis(0, 1e3, 2).unwrap();
    // A local accepts only a positive semi-definite covariance; a singular
    // one still cannot be inverted for the fusion (pivot 1 of [[1, 1],
    // [1, 1]] is 0).
    assert!(fed.locals_mut().1.set_covariance(&bad.1).is_err());
    let singular = Matrix2::new(1.0, 1.0, 1.0, 1.0);
    fed.locals_mut().1.set_covariance(&singular).unwrap();
    let locals_before = fed.locals().clone();
    assert_eq!(
        fed.fuse().unwrap_err(),
        FusionError::NotPositiveDefinite { local: 1, index: 1 }
    );
    assert_eq!(*fed.state(), Vector2::zeros());
    assert_eq!(*fed.covariance(), Matrix2::identity());
    assert!(fed.statuses()[0].admitted);
    assert_eq!(fed.locals().0.estimate(), locals_before.0.estimate());
    assert_eq!(fed.locals().1.estimate(), locals_before.1.estimate());
    // The recorded failure was kept: once the covariance is repaired, the
    // fusion applies it and isolates local 0 (K = 1), fusing local 1 alone.
    fed.locals_mut()
        .1
        .set_covariance(&Matrix2::identity())
        .unwrap();
    let report = fed.fuse().unwrap();
    assert_eq!(report.admitted(), [false, true]);
    assert_eq!(report.fused, 1);

    assert_eq!(
        fed.record_nis(2, 1.0, 1).unwrap_err(),
        FusionError::NoSuchLocal { local: 2 }
    );
    assert!(matches!(
        fed.record_nis(0, 1.0, 0).unwrap_err(),
        FusionError::Local {
            local: 0,
            error: FilterError::InvalidParameter {
                name: "dof",
                valid: "at least 1 (the measurement dimension M)"
            }
        }
    ));
    let model = LinearProcess::new(Matrix2::<f64>::identity(), Matrix2::identity());
    assert_eq!(
        fed.shared_noise(5, &model).unwrap_err(),
        FusionError::NoSuchLocal { local: 5 }
    );

    // The initial estimate must be a valid one.
    let locals = (
        Ekf::new(Vector4::zeros(), Matrix4::identity()).unwrap(),
        Ekf::new(Vector4::zeros(), Matrix4::identity()).unwrap(),
    );
    let mut p0 = Matrix4::identity();
    p0[(2, 2)] = -1.0;
    assert_eq!(
        FederatedFilter::new(locals, Sharing::equal(), Vector4::zeros(), p0).unwrap_err(),
        FusionError::FusedNotPositiveDefinite { index: 2 }
    );
}
