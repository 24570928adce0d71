//! The adapters of papers 000 / 004 and their compositions never touch the
//! heap in predict or update: a counting global allocator records every
//! allocation, reallocation and deallocation of the current thread while
//! armed, and runs of every form (EKF, UKF, SR-UKF with both time updates)
//! in `f32` and `f64` carrying each adapter make none — through the
//! branches that change something (checked from the reports: compression,
//! fading, estimates and skipped estimates) and through a refused NaN
//! measurement. A positive control shows an allocation while armed is
//! counted.

use crate::support;

use kestrel_adaptive::{
    DivergenceFading, ImprovedAdaptive, OutlierCompression, SageHusa, SageHusaFading,
    StrongTracking,
};
use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::form::{SquareRootForm, TimeUpdate};
use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector, Vector4};
use kestrel_core::{Ekf, Filter, Real, SrUkf, Ukf};
use kestrel_testkit::heap_calls;
use support::{cv, to, CvForm};

#[test]
fn positive_control_counts_an_allocation_made_while_armed() {
    kestrel_testkit::positive_control();
}

const STEPS: usize = 120;

/// Measurements with `R = 4 I` (the filter assumes `I`), 10 % outliers of
/// 30 σ and a jump of (20, −20) at epoch 60, made before arming.
fn data<T: Real>() -> Vec<SVector<T, 2>> {
    let spec = cv::Spec::new(8, STEPS, Matrix2::identity() * 4.0)
        .with_outliers(0.1, 30.0)
        .with_jump(60, Vector4::new(20.0, -20.0, 0.0, 0.0));
    cv::stream(&spec).z.iter().map(|z| z.map(to::<T>)).collect()
}

/// Predicts and updates over `z` armed, then offers a NaN measurement;
/// returns the reports, whether the NaN was refused, and the heap calls.
fn armed<T: Real, F: CvForm<T>, A: NoiseAdapter<T, 2>>(
    filter: &mut Filter<T, 4, F, A>,
    z: &[SVector<T, 2>],
) -> ((Vec<A::Report>, bool), usize) {
    let process = cv::process::<T>(0.01);
    let sensor = cv::sensor::<T>(&Matrix2::identity());
    let mut reports = Vec::with_capacity(STEPS);
    let nan = SVector::<T, 2>::repeat(to(f64::NAN));
    heap_calls(|| {
        for z in z {
            filter.predict(&process, T::one()).unwrap();
            let report = filter.update(&sensor, z).unwrap();
            // Within capacity: no allocation.
            reports.push(report.adapters);
        }
        let refused = filter.update(&sensor, &nan).is_err();
        (reports, refused)
    })
}

/// Each form with `adapter`, in turn; `check` sees each run's reports.
fn every_form<T: Real, A: NoiseAdapter<T, 2> + Clone>(
    adapter: A,
    check: impl Fn(&str, &[A::Report]),
) {
    let z = data::<T>();
    let (x0, p0): (SVector<T, 4>, SMatrix<T, 4, 4>) = (cv::x0(), cv::p0());
    let run = |name: &str, outcome: ((Vec<A::Report>, bool), usize)| {
        let ((reports, refused), calls) = outcome;
        assert_eq!(calls, 0, "{name}: heap calls");
        assert!(refused, "{name}: NaN refused");
        check(name, &reports);
    };
    let mut ekf = Ekf::new(x0, p0).unwrap().with_adapter(adapter.clone());
    run("EKF", armed(&mut ekf, &z));
    let mut ukf = Ukf::new(x0, p0).unwrap().with_adapter(adapter.clone());
    run("UKF", armed(&mut ukf, &z));
    for (name, method) in [
        ("SR-UKF Householder", TimeUpdate::Householder),
        ("SR-UKF rank-one", TimeUpdate::RankOne),
    ] {
        let form = SquareRootForm::new(&p0).unwrap().with_time_update(method);
        let mut sr = SrUkf::with_form(x0, form)
            .unwrap()
            .with_adapter(adapter.clone());
        run(name, armed(&mut sr, &z));
    }
}

fn all_adapters<T: Real>() {
    every_form(
        SageHusa::<T, 2>::as_published().unwrap(),
        |name, reports| {
            assert!(reports.iter().all(|a| a.estimated), "{name}");
        },
    );
    every_form(
        DivergenceFading::<T>::new(to(3.0), to(100.0)).unwrap(),
        |name, reports| {
            let faded = reports.iter().filter(|a| a.fade > T::one()).count();
            assert!(faded >= 5, "{name}: {faded} fades");
        },
    );
    every_form(
        StrongTracking::<T>::new(to(0.95), to(1.0)).unwrap(),
        |name, reports| {
            let faded = reports.iter().filter(|a| a.fade > T::one()).count();
            assert!(faded >= 5, "{name}: {faded} fades");
        },
    );
    every_form(
        OutlierCompression::<T, 2>::as_published().unwrap(),
        |name, reports| {
            let compressed = reports.iter().filter(|a| a.compressed).count();
            assert!(compressed >= 5, "{name}: {compressed} compressed");
        },
    );
    every_form(
        ImprovedAdaptive::<T, 2>::as_published().unwrap(),
        |name, reports| {
            let compressed = reports.iter().filter(|a| a.tests.0.compressed).count();
            let skipped = reports
                .iter()
                .filter(|a| a.sage_husa.skipped_for_fade)
                .count();
            let estimated = reports.iter().filter(|a| a.sage_husa.estimated).count();
            assert!(compressed >= 5, "{name}: {compressed} compressed");
            assert!(skipped >= 1, "{name}: {skipped} skipped");
            assert!(estimated >= 50, "{name}: {estimated} estimated");
        },
    );
    every_form(
        SageHusaFading::<T, 2>::as_published().unwrap(),
        |name, reports| {
            let skipped = reports
                .iter()
                .filter(|a| a.sage_husa.skipped_for_fade)
                .count();
            assert!(skipped >= 1, "{name}: {skipped} skipped");
        },
    );
    every_form(
        (
            OutlierCompression::<T, 2>::as_published().unwrap(),
            StrongTracking::<T>::new(to(0.95), to(1.0)).unwrap(),
            SageHusa::<T, 2>::as_published().unwrap(),
        ),
        |name, reports| {
            let skipped = reports.iter().filter(|a| a.2.skipped_for_fade).count();
            assert!(skipped >= 1, "{name}: {skipped} skipped");
        },
    );
}

#[test]
fn no_heap_use_f64() {
    all_adapters::<f64>();
}

#[test]
fn no_heap_use_f32() {
    all_adapters::<f32>();
}
