//! Information-sharing factors: the paper's adaptive two-filter shares
//! `β_1 = EDOP_2 / (EDOP_1 + EDOP_2)` with `EDOP_i = sqrt(tr(P_i P_iᵀ))`,
//! their normalisation for N locals (`β_i ∝ 1 / EDOP_i`, summing to one), the
//! reset `P_i = P_g / β_i` they drive, and the renormalisation of fixed
//! shares over the admitted locals.

use crate::federated_common;

use approx::assert_relative_eq;
use federated_common::{p0, process, sensor_a, sensor_b, sensor_c, simulate, x0};
use kestrel_adaptive::federated::{
    edop, edop_shares, FederatedFilter, FusionError, Isolation, LocalSet, Sharing,
};
use kestrel_core::nalgebra::Matrix4;
use kestrel_core::{Ekf, SrUkf, Ukf};

/// The paper's definition, computed independently of the crate.
fn paper_edop(p: &Matrix4<f64>) -> f64 {
    (p * p.transpose()).trace().sqrt()
}

#[test]
fn two_filter_shares_are_the_papers_formula() {
    let model = process();
    let locals = (
        Ekf::new(x0(), p0()).unwrap(),
        SrUkf::new(x0(), p0()).unwrap(),
    );
    let mut fed = FederatedFilter::new(locals, Sharing::edop(), x0(), p0()).unwrap();
    // The first reset, before any EDOP is known, splits equally.
    assert_eq!(fed.shares(), &[0.5, 0.5]);
    assert_eq!(fed.locals().0.covariance(), p0::<f64>() * 2.0);
    for e in simulate(30, 11) {
        fed.predict(&model, 1.0).unwrap();
        fed.locals_mut().0.update(&sensor_a(), &e.a).unwrap();
        fed.locals_mut().1.update(&sensor_b(), &e.b).unwrap();
        let e1 = paper_edop(&fed.locals().0.covariance());
        let e2 = paper_edop(&fed.locals().1.covariance());
        let report = fed.fuse().unwrap();

        assert_relative_eq!(report.edops()[0], e1, max_relative = 1e-14);
        assert_relative_eq!(report.edops()[1], e2, max_relative = 1e-14);
        let [b1, b2] = report.shares();
        assert_relative_eq!(b1, e2 / (e1 + e2), max_relative = 1e-14);
        assert_relative_eq!(b2, e1 / (e1 + e2), max_relative = 1e-14);
        assert_eq!(fed.shares(), &[b1, b2]);
        // The reset they drive: x_i = x_g, P_i = P_g / β_i.
        let (x1, p1) = fed.locals().estimate(0).unwrap();
        let (x2, p2) = fed.locals().estimate(1).unwrap();
        assert_eq!(x1, *fed.state());
        assert_eq!(x2, *fed.state());
        assert_relative_eq!(p1, fed.covariance() / b1, max_relative = 1e-14);
        assert_relative_eq!(p2, fed.covariance() / b2, max_relative = 1e-12);
    }
}

#[test]
fn n_filter_shares_are_normalised_inverse_edops() {
    // By hand: inverse EDOPs 1, 1/2, 1/4 sum to 7/4.
    let b = edop_shares(&[1.0, 2.0, 4.0], &[true; 3]).unwrap();
    for (got, want) in b.iter().zip([4.0 / 7.0, 2.0 / 7.0, 1.0 / 7.0]) {
        assert_relative_eq!(*got, want, max_relative = 1e-15);
    }
    // Only the admitted locals share: 1 and 1/4 sum to 5/4.
    let b = edop_shares(&[1.0, 2.0, 4.0], &[true, false, true]).unwrap();
    assert_relative_eq!(b[0], 0.8, max_relative = 1e-15);
    assert_eq!(b[1], 0.0);
    assert_relative_eq!(b[2], 0.2, max_relative = 1e-15);
    assert_eq!(
        edop_shares(&[1.0, f64::INFINITY], &[true; 2]).unwrap_err(),
        FusionError::NonFinite { local: 1 }
    );
    assert_eq!(
        edop_shares(&[0.0, 1.0], &[true; 2]).unwrap_err(),
        FusionError::NonFinite { local: 0 }
    );
    assert_eq!(
        edop_shares(&[1.0, 1.0], &[false; 2]).unwrap_err(),
        FusionError::AllIsolated
    );

    // Three heterogeneous locals: the shares sum to one and β_i · EDOP_i is
    // the same for every local.
    let model = process();
    let locals = (
        Ekf::new(x0(), p0()).unwrap(),
        SrUkf::new(x0(), p0()).unwrap(),
        Ukf::new(x0(), p0()).unwrap(),
    );
    let mut fed = FederatedFilter::new(locals, Sharing::edop(), x0(), p0()).unwrap();
    assert_eq!(fed.locals().2.covariance(), p0::<f64>() * 3.0);
    for e in simulate(30, 12) {
        fed.predict(&model, 1.0).unwrap();
        let (a, b, c) = fed.locals_mut();
        a.update(&sensor_a(), &e.a).unwrap();
        b.update(&sensor_b(), &e.b).unwrap();
        c.update(&sensor_c(), &e.c).unwrap();
        let edops: [f64; 3] =
            core::array::from_fn(|i| paper_edop(&fed.locals().estimate(i).unwrap().1));
        let report = fed.fuse().unwrap();
        let shares = report.shares();
        assert_relative_eq!(shares.iter().sum::<f64>(), 1.0, epsilon = 1e-15);
        let harmonic = 1.0 / edops.iter().map(|e| 1.0 / e).sum::<f64>();
        for i in 0..3 {
            assert_relative_eq!(report.edops()[i], edops[i], max_relative = 1e-14);
            assert_relative_eq!(shares[i] * edops[i], harmonic, max_relative = 1e-14);
        }
    }
}

#[test]
fn edop_is_the_frobenius_norm() {
    let p = Matrix4::new(
        4.0, 1.0, 0.0, 0.0, //
        1.0, 2.0, 0.0, 0.0, //
        0.0, 0.0, 1.0, -2.0, //
        0.0, 0.0, -2.0, 5.0,
    );
    // tr(P Pᵀ) = 16 + 1 + 1 + 4 + 1 + 4 + 4 + 25 = 56.
    assert_relative_eq!(edop(&p), 56f64.sqrt(), max_relative = 1e-15);
    assert_relative_eq!(paper_edop(&p), 56f64.sqrt(), max_relative = 1e-15);
}

#[test]
fn fixed_shares_are_renormalised_over_the_admitted_locals() {
    // Shares 0.2, 0.3, 0.4 (sum 0.9). Local 2 fails its test and is isolated
    // (K = 1): locals 0 and 1 take the whole 0.9 as 0.2 · 0.9 / 0.5 = 0.36
    // and 0.3 · 0.9 / 0.5 = 0.54; local 2 is reset with the fused covariance
    // (share 1) to monitor its sensor.
    let locals: [Ekf<f64, 4>; 3] = core::array::from_fn(|_| Ekf::new(x0(), p0()).unwrap());
    let sharing = Sharing::fixed([0.2, 0.3, 0.4]).unwrap();
    let mut fed = FederatedFilter::new(locals, sharing, x0(), p0())
        .unwrap()
        .with_isolation(Isolation::new(0.01, 1, 1).unwrap());
    fed.record_nis(2, 100.0, 2).unwrap();
    let report = fed.fuse().unwrap();
    assert_eq!(report.admitted(), [true, true, false]);
    let shares = report.shares();
    assert_relative_eq!(shares[0], 0.36, max_relative = 1e-15);
    assert_relative_eq!(shares[1], 0.54, max_relative = 1e-15);
    assert_eq!(shares[2], 1.0);
    // This fusion had locals 0 and 1 at P(0) / 0.2 and P(0) / 0.3: the
    // information 0.5 P(0)⁻¹.
    assert_relative_eq!(*fed.covariance(), p0::<f64>() * 2.0, max_relative = 1e-14);
    assert_relative_eq!(
        fed.locals()[0].covariance(),
        fed.covariance() / 0.36,
        max_relative = 1e-14
    );
    assert_eq!(fed.locals()[2].covariance(), *fed.covariance());
    // Passing again re-admits it (K_r = 1): the original shares return.
    fed.record_nis(2, 0.1, 2).unwrap();
    let report = fed.fuse().unwrap();
    assert_eq!(report.admitted(), [true; 3]);
    assert!(!report.locals[2].fused, "joins at the next fusion");
    assert_eq!(report.shares(), [0.2, 0.3, 0.4]);
}
