//! The classic equivalence of the federated filter: with shares summing to
//! one, a reset after every fusion, `P_i(0) = P(0) / β_i` and
//! `Q_i = Q / β_i`, linear locals that each process their own sensor fuse to
//! exactly the centralised Kalman filter that processes every measurement.
//! Checked to 1e-9 (relative, or absolute for entries below one) at every
//! epoch for covariance-form locals, a master filter, adaptive EDOP shares,
//! and heterogeneous locals (KF + SR-UKF as in the paper, KF + SR-UKF + UKF),
//! with every covariance positive definite throughout; and an `f32` run.

use crate::federated_common;

use approx::assert_relative_eq;
use federated_common::{
    cast, is_pd, p0, process, sensor_a, sensor_b, sensor_c, simulate, x0, Epoch,
};
use kestrel_adaptive::federated::{FederatedFilter, FusionReport, PredictSet, Sharing};
use kestrel_core::nalgebra::{Matrix4, Vector4};
use kestrel_core::{Ekf, SrUkf, Ukf};
use kestrel_models::LinearProcess;

const EPOCHS: usize = 60;

/// Runs `fed` next to the centralised KF: both predict with the common
/// model, `locals` updates each local with its sensor, `central` updates the
/// centralised filter with all of them; after every fusion the fused
/// estimate must equal the centralised one and every covariance must be
/// positive definite. Returns the fusion reports.
fn against_central<'m, Locals, const L: usize>(
    model: &'m LinearProcess<f64, 4>,
    fed: &mut FederatedFilter<f64, 4, L, Locals>,
    epochs: &[Epoch],
    mut locals: impl FnMut(&mut Locals, &Epoch),
    mut central_update: impl FnMut(&mut Ekf<f64, 4>, &Epoch),
) -> Vec<FusionReport<f64, L>>
where
    Locals: PredictSet<'m, f64, 4, L, LinearProcess<f64, 4>>,
{
    let mut central = Ekf::new(x0(), p0()).unwrap();
    let mut reports = Vec::new();
    for (k, e) in epochs.iter().enumerate() {
        fed.predict(model, 1.0).unwrap();
        central.predict(model, 1.0).unwrap();
        locals(fed.locals_mut(), e);
        central_update(&mut central, e);
        for i in 0..L {
            let (_, p) = fed.locals().estimate(i).unwrap();
            assert!(is_pd(&p), "local {i} at epoch {k}");
        }
        reports.push(fed.fuse().unwrap());
        assert!(is_pd(fed.covariance()), "fused at epoch {k}");
        assert_relative_eq!(
            *fed.state(),
            *central.state(),
            epsilon = 1e-9,
            max_relative = 1e-9
        );
        assert_relative_eq!(
            *fed.covariance(),
            central.covariance(),
            epsilon = 1e-9,
            max_relative = 1e-9
        );
    }
    // The filter converged: the estimate is near the truth (not a vacuous
    // equality of two diverged filters).
    let last = epochs.last().unwrap();
    assert!((fed.state() - last.truth).norm() < 5.0);
    reports
}

fn central_ab(f: &mut Ekf<f64, 4>, e: &Epoch) {
    f.update(&sensor_a(), &e.a).unwrap();
    f.update(&sensor_b(), &e.b).unwrap();
}

#[test]
fn two_kf_locals_with_fixed_shares_equal_the_centralised_kf() {
    let model = process();
    let locals = (Ekf::new(x0(), p0()).unwrap(), Ekf::new(x0(), p0()).unwrap());
    let sharing = Sharing::fixed([0.4, 0.6]).unwrap();
    let mut fed = FederatedFilter::new(locals, sharing, x0(), p0()).unwrap();
    let reports = against_central(
        &model,
        &mut fed,
        &simulate(EPOCHS, 1),
        |(a, b), e| {
            a.update(&sensor_a(), &e.a).unwrap();
            b.update(&sensor_b(), &e.b).unwrap();
        },
        central_ab,
    );
    assert!(reports.iter().all(|r| r.shares() == [0.4, 0.6]));
}

#[test]
fn a_master_filter_is_a_local_that_is_only_predicted() {
    // Carlson's master keeps β_m = 0.2 of the information and no sensor.
    let model = process();
    let locals = (
        Ekf::new(x0(), p0()).unwrap(),
        Ekf::new(x0(), p0()).unwrap(),
        Ekf::new(x0(), p0()).unwrap(),
    );
    let sharing = Sharing::fixed([0.3, 0.5, 0.2]).unwrap();
    let mut fed = FederatedFilter::new(locals, sharing, x0(), p0()).unwrap();
    against_central(
        &model,
        &mut fed,
        &simulate(EPOCHS, 2),
        |(a, b, _master), e| {
            a.update(&sensor_a(), &e.a).unwrap();
            b.update(&sensor_b(), &e.b).unwrap();
        },
        central_ab,
    );
    // The master holds P_g / β_m after the reset.
    assert_relative_eq!(
        fed.locals().2.covariance(),
        fed.covariance() * 5.0,
        max_relative = 1e-14
    );
}

#[test]
fn adaptive_edop_shares_also_equal_the_centralised_kf() {
    // Any shares summing to one keep the equivalence, so the adaptive ones do.
    let model = process();
    let locals = (Ekf::new(x0(), p0()).unwrap(), Ekf::new(x0(), p0()).unwrap());
    let mut fed = FederatedFilter::new(locals, Sharing::edop(), x0(), p0()).unwrap();
    let reports = against_central(
        &model,
        &mut fed,
        &simulate(EPOCHS, 3),
        |(a, b), e| {
            a.update(&sensor_a(), &e.a).unwrap();
            b.update(&sensor_b(), &e.b).unwrap();
        },
        central_ab,
    );
    let mut range = (1.0f64, 0.0f64);
    for r in &reports {
        let [b1, b2] = r.shares();
        assert_relative_eq!(b1 + b2, 1.0, epsilon = 1e-15);
        range = (range.0.min(b1), range.1.max(b1));
    }
    // The shares really moved (sensor B never sees py, so local 2's EDOP
    // grows and its share shrinks): the equivalence held under changing β.
    assert!(range.0 < 0.65 && range.1 > 0.95, "{range:?}");
}

#[test]
fn kf_and_srukf_locals_equal_the_centralised_kf() {
    // The paper's set-up: local 1 a covariance-form KF, local 2 an SR-UKF,
    // adaptive shares.
    let model = process();
    let locals = (
        Ekf::new(x0(), p0()).unwrap(),
        SrUkf::new(x0(), p0()).unwrap(),
    );
    let mut fed = FederatedFilter::new(locals, Sharing::edop(), x0(), p0()).unwrap();
    against_central(
        &model,
        &mut fed,
        &simulate(EPOCHS, 4),
        |(kf, sr), e| {
            kf.update(&sensor_a(), &e.a).unwrap();
            sr.update(&sensor_b(), &e.b).unwrap();
        },
        central_ab,
    );
}

#[test]
fn kf_srukf_and_ukf_locals_equal_the_centralised_kf() {
    let model = process();
    let locals = (
        SrUkf::new(x0(), p0()).unwrap(),
        Ukf::new(x0(), p0()).unwrap(),
        Ekf::new(x0(), p0()).unwrap(),
    );
    let sharing = Sharing::fixed([0.5, 0.25, 0.25]).unwrap();
    let mut fed = FederatedFilter::new(locals, sharing, x0(), p0()).unwrap();
    against_central(
        &model,
        &mut fed,
        &simulate(EPOCHS, 5),
        |(sr, ukf, kf), e| {
            sr.update(&sensor_a(), &e.a).unwrap();
            ukf.update(&sensor_b(), &e.b).unwrap();
            kf.update(&sensor_c(), &e.c).unwrap();
        },
        |f, e| {
            central_ab(f, e);
            f.update(&sensor_c(), &e.c).unwrap();
        },
    );
}

#[test]
fn locals_predicted_by_hand_with_their_shared_noise_give_the_same_result() {
    // What a user with different process models per local does: wrap each
    // local's model with its share.
    let model = process();
    let make = || {
        (
            Ekf::new(x0(), p0()).unwrap(),
            SrUkf::new(x0(), p0()).unwrap(),
        )
    };
    let sharing = Sharing::edop();
    let mut auto = FederatedFilter::new(make(), sharing, x0(), p0()).unwrap();
    let mut by_hand = FederatedFilter::new(make(), sharing, x0(), p0()).unwrap();
    for e in simulate(20, 6) {
        auto.predict(&model, 1.0).unwrap();
        let q0 = by_hand.shared_noise(0, &model).unwrap();
        let q1 = by_hand.shared_noise(1, &model).unwrap();
        by_hand.locals_mut().0.predict(&q0, 1.0).unwrap();
        by_hand.locals_mut().1.predict(&q1, 1.0).unwrap();
        for f in [&mut auto, &mut by_hand] {
            f.locals_mut().0.update(&sensor_a(), &e.a).unwrap();
            f.locals_mut().1.update(&sensor_b(), &e.b).unwrap();
            f.fuse().unwrap();
        }
        assert_eq!(auto.state(), by_hand.state());
        assert_eq!(auto.covariance(), by_hand.covariance());
    }
}

#[test]
fn f32_kf_and_srukf_federation_tracks_the_f64_one() {
    let epochs = simulate(EPOCHS, 4);
    let (m64, m32) = (process::<f64>(), process::<f32>());
    let mut f64_fed = FederatedFilter::new(
        (
            Ekf::new(x0(), p0()).unwrap(),
            SrUkf::new(x0(), p0()).unwrap(),
        ),
        Sharing::edop(),
        x0(),
        p0(),
    )
    .unwrap();
    let mut f32_fed = FederatedFilter::new(
        (
            Ekf::new(x0::<f32>(), p0()).unwrap(),
            SrUkf::new(x0::<f32>(), p0()).unwrap(),
        ),
        Sharing::edop(),
        x0(),
        p0(),
    )
    .unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for e in &epochs {
        f64_fed.predict(&m64, 1.0).unwrap();
        f32_fed.predict(&m32, 1.0).unwrap();
        f64_fed.locals_mut().0.update(&sensor_a(), &e.a).unwrap();
        f64_fed.locals_mut().1.update(&sensor_b(), &e.b).unwrap();
        f32_fed
            .locals_mut()
            .0
            .update(&sensor_a(), &cast(&e.a))
            .unwrap();
        f32_fed
            .locals_mut()
            .1
            .update(&sensor_b(), &cast(&e.b))
            .unwrap();
        f64_fed.fuse().unwrap();
        f32_fed.fuse().unwrap();
        assert!(is_pd(f32_fed.covariance()));
        let x32: Vector4<f64> = f32_fed.state().map(f64::from);
        let p32: Matrix4<f64> = f32_fed.covariance().map(f64::from);
        let p64 = f64_fed.covariance();
        // Errors relative to the size of the state and of the covariance.
        let dx = (x32 - f64_fed.state()).norm() / f64_fed.state().norm();
        let dp = (p32 - p64).norm() / p64.norm();
        worst = (worst.0.max(dx), worst.1.max(dp));
    }
    // f32 resolves about 6e-8 relative: the fused state stays within a few
    // of its units in the last place (measured 1.4e-7), the covariance,
    // through the information-form inversions, within 1e-4 of its norm
    // (measured 7.7e-6).
    assert!(worst.0 < 1e-6 && worst.1 < 1e-4, "{worst:?}");
}
