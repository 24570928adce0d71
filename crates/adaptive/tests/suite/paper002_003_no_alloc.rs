//! The adapters of papers 002 / 003 never touch the heap in predict or
//! update: a counting global allocator records every allocation,
//! reallocation and deallocation of the current thread while armed, and
//! runs of every form (EKF, UKF, SR-UKF with both time updates) in `f32` and
//! `f64` carrying each adapter — through the branches that change
//! something: inflation, rejection, applied and unusable fuzzy gains, a
//! full window with floored eigenvalues — make none. A positive control
//! shows an allocation while armed is counted.

use crate::support;

use kestrel_adaptive::{
    ChiSquareGate, FuzzyGain, GainDecision, HuberInflation, OdometerInputs, WindowedNoise,
};
use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::form::{SquareRootForm, TimeUpdate};
use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector, Vector2};
use kestrel_core::{Ekf, Filter, Real, SrUkf, Ukf};
use kestrel_testkit::heap_calls;
use support::{cv, to, CvForm};

#[test]
fn positive_control_counts_an_allocation_made_while_armed() {
    kestrel_testkit::positive_control();
}

const STEPS: usize = 120;

/// The measurements (10 % outliers of 30σ) and per-epoch odometer inputs,
/// made before arming: dm₁ cycles through normal, small, tiny (with a big
/// innovation only at outliers) and big-while-turning values.
struct Data<T: Real> {
    z: Vec<SVector<T, 2>>,
    inputs: Vec<OdometerInputs<T, 2>>,
}

fn data<T: Real>() -> Data<T> {
    let spec = cv::Spec::new(3, STEPS, Matrix2::identity()).with_outliers(0.1, 30.0);
    let stream = cv::stream(&spec);
    let cycle = [(1.0, 0.0), (0.9, 5.0), (0.6, 0.0), (1.15, 40.0)];
    Data {
        z: stream.z.iter().map(|z| z.map(to::<T>)).collect(),
        inputs: (0..STEPS)
            .map(|k| {
                let (dm1, heading) = cycle[k % cycle.len()];
                OdometerInputs::new(to(dm1), to(heading), Vector2::new(to(0.5), to(-0.25)))
            })
            .collect(),
    }
}

/// Predicts and updates over `data`, armed, setting the odometer inputs
/// through `set` before each update; returns the reports and the number of
/// heap calls.
fn armed<T: Real, F: CvForm<T>, A: NoiseAdapter<T, 2>>(
    filter: &mut Filter<T, 4, F, A>,
    data: &Data<T>,
    set: fn(&mut A, OdometerInputs<T, 2>),
) -> (Vec<(bool, A::Report)>, usize) {
    let process = cv::process::<T>(0.01);
    let sensor = cv::sensor::<T>(&Matrix2::identity());
    let mut reports = Vec::with_capacity(STEPS);
    let ((), calls) = heap_calls(|| {
        for (z, inputs) in data.z.iter().zip(&data.inputs) {
            filter.predict(&process, T::one()).unwrap();
            set(filter.adapter_mut(), *inputs);
            let report = filter.update(&sensor, z).unwrap();
            // Within capacity: no allocation.
            reports.push((report.rejected, report.adapters));
        }
    });
    (reports, calls)
}

fn no_inputs<A, T: Real>(_: &mut A, _: OdometerInputs<T, 2>) {}

/// Each form with `adapter`, in turn.
fn every_form<T: Real, A: NoiseAdapter<T, 2> + Clone>(
    adapter: A,
    set: fn(&mut A, OdometerInputs<T, 2>),
    check: impl Fn(&str, &[(bool, A::Report)]),
) {
    let data = data::<T>();
    let (x0, p0): (SVector<T, 4>, SMatrix<T, 4, 4>) = (cv::x0(), cv::p0());
    let mut ekf = Ekf::new(x0, p0).unwrap().with_adapter(adapter.clone());
    let (reports, calls) = armed(&mut ekf, &data, set);
    assert_eq!(calls, 0, "EKF");
    check("EKF", &reports);
    let mut ukf = Ukf::new(x0, p0).unwrap().with_adapter(adapter.clone());
    let (reports, calls) = armed(&mut ukf, &data, set);
    assert_eq!(calls, 0, "UKF");
    check("UKF", &reports);
    for method in [TimeUpdate::Householder, TimeUpdate::RankOne] {
        let form = SquareRootForm::new(&p0).unwrap().with_time_update(method);
        let mut sr = SrUkf::with_form(x0, form)
            .unwrap()
            .with_adapter(adapter.clone());
        let (reports, calls) = armed(&mut sr, &data, set);
        assert_eq!(calls, 0, "SR-UKF {method:?}");
        check("SR-UKF", &reports);
    }
}

fn all_adapters<T: Real>() {
    every_form(
        HuberInflation::<T, 2>::as_published().unwrap(),
        no_inputs,
        |name, reports| {
            let inflated = reports.iter().filter(|(_, a)| a.inflated > 0).count();
            assert!(inflated >= 8, "{name}: {inflated} inflated");
        },
    );
    every_form(
        ChiSquareGate::<T, 2>::new(kestrel_core::real::lit(0.01)).unwrap(),
        no_inputs,
        |name, reports| {
            let rejected = reports.iter().filter(|(r, _)| *r).count();
            assert!(rejected >= 8, "{name}: {rejected} rejected");
        },
    );
    every_form(
        FuzzyGain::<T, 2>::odometer().unwrap(),
        |a, i| a.set_inputs(i),
        |name, reports| {
            for decision in [GainDecision::Applied, GainDecision::Unusable] {
                let n = reports
                    .iter()
                    .filter(|(_, a)| a.decision == decision)
                    .count();
                assert!(n >= 10, "{name}: {n} × {decision:?}");
            }
        },
    );
    every_form(
        WindowedNoise::<T, 2, 10>::new(to(0.5)).unwrap(),
        no_inputs,
        |name, reports| {
            let estimated = reports.iter().filter(|(_, a)| a.estimated).count();
            assert_eq!(estimated, STEPS - 9, "{name}");
            assert!(reports.iter().any(|(_, a)| a.raised > 0), "{name}: floor");
        },
    );
    every_form(
        (
            ChiSquareGate::<T, 2>::new(kestrel_core::real::lit(0.01)).unwrap(),
            FuzzyGain::<T, 2>::odometer().unwrap(),
            WindowedNoise::<T, 2, 10>::new(to(0.5)).unwrap(),
            HuberInflation::<T, 2>::as_published().unwrap(),
        ),
        |a, i| a.1.set_inputs(i),
        |name, reports| {
            assert!(reports.iter().any(|(r, _)| !r), "{name}: accepted");
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
