//! The federated filter never touches the heap: a counting global allocator
//! records every allocation, reallocation and deallocation of the current
//! thread while armed, and a whole run — construction with isolation,
//! predicting the KF, SR-UKF and UKF locals with their shared noise,
//! updating, recording the innovation tests, fusing, isolating and
//! re-admitting a biased local, and the error paths — makes none, in `f32`
//! and in `f64`. A positive control shows an allocation while armed is
//! counted.

use crate::federated_common;

use std::hint::black_box;

use federated_common::{cast, p0, process, sensor_a, sensor_b, sensor_c, simulate, x0};
use kestrel_adaptive::federated::{FederatedFilter, FusionError, Isolation, Sharing};
use kestrel_core::nalgebra::{Matrix4, Vector1, Vector2, Vector3};
use kestrel_core::real::lit;
use kestrel_core::{Ekf, Real, SrUkf, Ukf};
use kestrel_testkit::heap_calls;

#[test]
fn positive_control_counts_an_allocation_made_while_armed() {
    kestrel_testkit::positive_control();
}

/// Measurements in `T`, made before arming.
type Readings<T> = Vec<(Vector2<T>, Vector3<T>, Vector1<T>)>;

fn readings<T: Real>() -> Readings<T> {
    simulate(40, 31)
        .iter()
        .enumerate()
        .map(|(k, e)| {
            // Sensor A biased from epoch 10 to 19: isolated, then re-admitted.
            let bias = if (10..20).contains(&k) { 40.0 } else { 0.0 };
            let a = e.a + Vector2::new(bias, 0.0);
            (cast(&a), cast(&e.b), cast(&e.c))
        })
        .collect()
}

/// A whole federated run; returns (isolations seen, re-admissions seen).
fn run<T: Real>(zs: &Readings<T>) -> (usize, usize) {
    let model = process::<T>();
    let (ma, mb, mc) = (sensor_a::<T>(), sensor_b::<T>(), sensor_c::<T>());
    let locals = (
        Ekf::new(x0::<T>(), p0()).unwrap(),
        SrUkf::new(x0::<T>(), p0()).unwrap(),
        Ukf::new(x0::<T>(), p0()).unwrap(),
    );
    let mut fed = FederatedFilter::new(locals, Sharing::edop(), x0(), p0())
        .unwrap()
        .with_isolation(Isolation::new(kestrel_core::real::lit(0.01), 2, 2).unwrap());
    let (mut isolated, mut readmitted) = (0, 0);
    let mut was = [true; 3];
    for (za, zb, zc) in zs {
        fed.predict(&model, T::one()).unwrap();
        let r = fed.locals_mut().0.update(&ma, za).unwrap();
        fed.record(0, &r).unwrap();
        let r = fed.locals_mut().1.update(&mb, zb).unwrap();
        fed.record(1, &r).unwrap();
        let r = fed.locals_mut().2.update(&mc, zc).unwrap();
        fed.record(2, &r).unwrap();
        let report = black_box(fed.fuse().unwrap());
        for (w, now) in was.iter_mut().zip(report.admitted()) {
            isolated += usize::from(*w && !now);
            readmitted += usize::from(!*w && now);
            *w = now;
        }
    }
    // Error paths: a dimension beyond the precomputed thresholds, an
    // indefinite local (refused), a singular local, everything isolated.
    fed.record_nis(1, T::one(), 20).unwrap();
    let mut bad = Matrix4::<T>::identity();
    bad[(3, 3)] = -T::one();
    assert!(fed.locals_mut().2.set_covariance(&bad).is_err());
    bad[(3, 3)] = T::zero();
    fed.locals_mut().2.set_covariance(&bad).unwrap();
    assert_eq!(
        fed.fuse().unwrap_err(),
        FusionError::NotPositiveDefinite { local: 2, index: 3 }
    );
    for i in 0..3 {
        fed.record_nis(i, lit(1e6), 3).unwrap();
        fed.record_nis(i, lit(1e6), 3).unwrap();
    }
    fed.locals_mut().2.set_covariance(&p0()).unwrap();
    fed.fuse().unwrap();
    for i in 0..3 {
        fed.record_nis(i, lit(1e6), 3).unwrap();
    }
    assert_eq!(fed.fuse().unwrap_err(), FusionError::AllIsolated);
    (isolated, readmitted)
}

/// A whole run armed: no heap calls, and the run went through isolation
/// and re-admission.
fn never_allocates<T: Real>() {
    let zs = readings::<T>();
    let ((isolated, readmitted), calls) = heap_calls(|| run(&zs));
    assert_eq!(
        (isolated, readmitted),
        (1, 1),
        "the biased local was isolated and re-admitted"
    );
    assert_eq!(calls, 0);
}

#[test]
fn a_federated_run_never_allocates_in_f64() {
    never_allocates::<f64>();
}

#[test]
fn a_federated_run_never_allocates_in_f32() {
    never_allocates::<f32>();
}
