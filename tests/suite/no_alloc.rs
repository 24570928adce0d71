//! Predict and update never touch the heap: a counting global allocator
//! records every allocation, reallocation and deallocation made by the
//! current thread while it is armed, and every form (covariance with batch
//! and with sequential updates, UKF, square-root UKF with both time-update
//! methods), in `f32` and `f64`, with no adapter and with an adapter tuple,
//! runs its predict / update loop (`update` and `update_detailed` in turn)
//! and its error paths (NaN measurement, NaN transition) armed with a count
//! of zero.
//!
//! The flag and the counter are thread-local, so the test harness's own
//! threads (output capture, other tests) cannot disturb a count; a positive
//! control shows an allocation made while armed is counted.

use crate::common;

use std::hint::black_box;

use kestrel::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use kestrel::form::{PredictForm, SquareRootForm, TimeUpdate, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix2, Matrix4, SVector, Vector2, Vector4};
use kestrel::real::lit;
use kestrel::{Ekf, Filter, FilterError, Real, SrUkf, Ukf};
use kestrel_testkit::heap_calls;

#[test]
fn positive_control_counts_an_allocation_made_while_armed() {
    kestrel_testkit::positive_control();
}

/// A test adapter touching every hook: fades the prior and the gain step,
/// replaces `R` by a multiple of itself, scales the innovation, and reads
/// the posterior view.
#[derive(Debug, Clone, Copy)]
struct Tuner<T> {
    prior_fade: T,
    gain_fade: T,
    noise_scale: T,
    innovation_scale: T,
    updates: u32,
}

impl<T: Real> Tuner<T> {
    fn new(prior_fade: f64, gain_fade: f64, noise_scale: f64, innovation_scale: f64) -> Self {
        Self {
            prior_fade: lit(prior_fade),
            gain_fade: lit(gain_fade),
            noise_scale: lit(noise_scale),
            innovation_scale: lit(innovation_scale),
            updates: 0,
        }
    }
}

impl<T: Real> PriorAdapter<T> for Tuner<T> {
    const NEEDS_SPLIT: bool = true;
    fn after_predict(&mut self, prior: &mut PriorStep<T>) {
        prior.fade(self.prior_fade);
    }
}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for Tuner<T> {
    type Report = (u32, Option<T>);
    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        step.fade(self.gain_fade);
        let r = step.noise() * self.noise_scale;
        step.set_noise(r);
        step.scale_innovation(self.innovation_scale);
        report.1 = step.mahalanobis();
    }
    fn after_update(&mut self, posterior: &Posterior<'_, T, M>, report: &mut Self::Report) {
        let residual = posterior.post_fit_residual();
        let covariance = posterior.posterior_covariance();
        black_box((residual, covariance));
        self.updates += 1;
        report.0 = self.updates;
    }
}

/// A test adapter that changes nothing and reads the posterior view: its
/// epochs take the covariance form's way for epochs left as they were, with
/// the view's factor and `L⁻¹ ν` formed on demand.
#[derive(Debug, Clone, Copy, Default)]
struct Onlooker {
    updates: u32,
}

impl<T: Real> PriorAdapter<T> for Onlooker {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for Onlooker {
    type Report = ();
    fn before_gain(&mut self, _step: &mut GainStep<T, M>, _report: &mut ()) {}
    fn after_update(&mut self, posterior: &Posterior<'_, T, M>, _report: &mut ()) {
        let whitened = *posterior.whitened_innovation();
        black_box((whitened, posterior.post_fit_residual()));
        black_box(posterior.posterior_covariance());
        self.updates += 1;
    }
}

/// An adapter that allocates in every hook: the positive control for the
/// filter runs.
struct Leaky;

impl<T: Real> PriorAdapter<T> for Leaky {
    fn after_predict(&mut self, _prior: &mut PriorStep<T>) {
        drop(black_box(Vec::<u8>::with_capacity(8)));
    }
}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for Leaky {
    type Report = ();
    fn before_gain(&mut self, _step: &mut GainStep<T, M>, _report: &mut ()) {
        drop(black_box(Vec::<u8>::with_capacity(8)));
    }
}

#[test]
fn positive_control_counts_allocations_made_inside_a_filter_step() {
    let mut ukf = Ukf::<f64, 4>::new(x0(), p0())
        .expect("finite")
        .with_adapter(Leaky);
    let (outcome, calls) = armed_run(&mut ukf);
    assert_eq!(outcome.accepted, 30);
    // 30 predicts and 30 updates, each hook allocating and freeing once; the
    // NaN inputs are refused before any hook runs.
    assert_eq!(calls, 2 * 60);
}

/// A 4-state constant-velocity model observed in position, diagonal `R`.
fn models<T: Real>() -> (LinearProcess<T, 4>, LinearMeasurement<T, 4, 2>) {
    common::constant_velocity(Matrix2::new(0.25, 0.0, 0.0, 0.5))
}

/// What an armed run did.
#[derive(Debug)]
struct Outcome {
    accepted: usize,
    sequential: usize,
    nan_measurement: Option<FilterError>,
    nan_transition: Option<FilterError>,
}

/// Thirty predict / update steps, then a NaN measurement and a NaN
/// transition, all armed; returns what happened and the heap call count.
fn armed_run<T, F, A>(filter: &mut Filter<T, 4, F, A>) -> (Outcome, usize)
where
    T: Real,
    F: PredictForm<T, 4, LinearProcess<T, 4>> + UpdateForm<T, 4, LinearMeasurement<T, 4, 2>, 2>,
    A: NoiseAdapter<T, 2>,
{
    let (process, sensor) = models::<T>();
    let zs: [SVector<T, 2>; 30] =
        core::array::from_fn(|k| Vector2::new(0.3 * k as f64, 1.0 - 0.2 * k as f64).cast());
    let mut broken = process;
    broken.transition[(0, 1)] = lit::<T>(f64::NAN);
    heap_calls(|| {
        let mut outcome = Outcome {
            accepted: 0,
            sequential: 0,
            nan_measurement: None,
            nan_transition: None,
        };
        for (k, z) in zs.iter().enumerate() {
            if filter.predict(&process, lit(0.1)).is_err() {
                continue;
            }
            // Every other step returns the detail (the matrices too).
            let report = if k % 2 == 0 {
                filter.update(&sensor, z)
            } else {
                filter
                    .update_detailed(&sensor, z)
                    .map(|d| black_box(d).report)
            };
            if let Ok(report) = report {
                outcome.accepted += 1;
                outcome.sequential += usize::from(report.sequential);
                black_box(report);
            }
        }
        let nan = Vector2::new(lit::<T>(f64::NAN), T::one());
        outcome.nan_measurement = filter.update(&sensor, &nan).err();
        outcome.nan_transition = filter.predict(&broken, lit(0.1)).err();
        outcome
    })
}

fn x0<T: Real>() -> Vector4<T> {
    Vector4::new(0.0, 1.0, 3.0, -2.0).cast()
}

fn p0<T: Real>() -> Matrix4<T> {
    Matrix4::from_diagonal(&Vector4::new(4.0, 4.0, 1.0, 1.0)).cast()
}

fn sr_ukf<T: Real>(method: TimeUpdate) -> SrUkf<T, 4> {
    let form = SquareRootForm::new(&p0())
        .expect("PSD")
        .with_time_update(method);
    SrUkf::with_form(x0(), form).expect("finite")
}

fn tuple<T: Real>() -> (Tuner<T>, Tuner<T>) {
    (
        Tuner::new(1.01, 1.02, 1.5, 0.9),
        Tuner::new(1.0, 1.0, 0.8, 1.0),
    )
}

/// Asserts a run made no heap call, accepted every step (`sequential` of
/// them by scalar updates) and refused both NaN inputs.
#[track_caller]
fn assert_clean((outcome, calls): (Outcome, usize), sequential: bool, what: &str) {
    assert_eq!(calls, 0, "{what}: {calls} heap calls");
    assert_eq!(outcome.accepted, 30, "{what}: {outcome:?}");
    let expected = if sequential { 30 } else { 0 };
    assert_eq!(outcome.sequential, expected, "{what}: {outcome:?}");
    assert!(
        matches!(outcome.nan_measurement, Some(FilterError::NonFinite { .. })),
        "{what}: {outcome:?}"
    );
    assert!(
        matches!(outcome.nan_transition, Some(FilterError::NonFinite { .. })),
        "{what}: {outcome:?}"
    );
}

fn every_form_without_adapter<T: Real>() {
    let mut batch = Ekf::<T, 4>::new(x0(), p0()).expect("finite");
    batch.form_mut().set_sequential(false);
    assert_clean(armed_run(&mut batch), false, "EKF batch");
    let mut seq = Ekf::<T, 4>::new(x0(), p0()).expect("finite");
    seq.form_mut().set_sequential(true);
    assert_clean(armed_run(&mut seq), true, "EKF sequential");
    let mut ukf = Ukf::<T, 4>::new(x0(), p0()).expect("finite");
    assert_clean(armed_run(&mut ukf), false, "UKF");
    let mut sr = sr_ukf::<T>(TimeUpdate::Householder);
    assert_clean(armed_run(&mut sr), false, "SR-UKF Householder");
    let mut sr = sr_ukf::<T>(TimeUpdate::RankOne);
    assert_clean(armed_run(&mut sr), false, "SR-UKF rank-one");
}

fn every_form_with_adapter_tuple<T: Real>() {
    let mut batch = Ekf::<T, 4>::new(x0(), p0())
        .expect("finite")
        .with_adapter(tuple::<T>());
    batch.form_mut().set_sequential(false);
    assert_clean(armed_run(&mut batch), false, "EKF batch + adapters");
    // Sequential updates stay enabled but an adapter forces the batch path.
    let mut ekf = Ekf::<T, 4>::new(x0(), p0())
        .expect("finite")
        .with_adapter(tuple::<T>());
    ekf.form_mut().set_sequential(true);
    assert_clean(armed_run(&mut ekf), false, "EKF + adapters");
    let mut ukf = Ukf::<T, 4>::new(x0(), p0())
        .expect("finite")
        .with_adapter(tuple::<T>());
    assert_clean(armed_run(&mut ukf), false, "UKF + adapters");
    let mut sr = sr_ukf::<T>(TimeUpdate::Householder).with_adapter(tuple::<T>());
    assert_clean(armed_run(&mut sr), false, "SR-UKF Householder + adapters");
    assert_eq!(sr.adapter().0.updates, 30, "the adapter ran");
    let mut sr = sr_ukf::<T>(TimeUpdate::RankOne).with_adapter(tuple::<T>());
    assert_clean(armed_run(&mut sr), false, "SR-UKF rank-one + adapters");
}

fn every_form_with_an_adapter_that_changes_nothing<T: Real>() {
    let mut batch = Ekf::<T, 4>::new(x0(), p0())
        .expect("finite")
        .with_adapter(Onlooker::default());
    assert_clean(armed_run(&mut batch), false, "EKF + onlooker");
    assert_eq!(
        batch.adapter().updates,
        30,
        "the adapter read every posterior"
    );
    let mut ukf = Ukf::<T, 4>::new(x0(), p0())
        .expect("finite")
        .with_adapter(Onlooker::default());
    assert_clean(armed_run(&mut ukf), false, "UKF + onlooker");
    let mut sr = sr_ukf::<T>(TimeUpdate::Householder).with_adapter(Onlooker::default());
    assert_clean(armed_run(&mut sr), false, "SR-UKF + onlooker");
}

#[test]
fn no_heap_use_with_an_adapter_that_changes_nothing() {
    every_form_with_an_adapter_that_changes_nothing::<f64>();
    every_form_with_an_adapter_that_changes_nothing::<f32>();
}

#[test]
fn no_heap_use_without_adapter_f64() {
    every_form_without_adapter::<f64>();
}

#[test]
fn no_heap_use_without_adapter_f32() {
    every_form_without_adapter::<f32>();
}

#[test]
fn no_heap_use_with_adapter_tuple_f64() {
    every_form_with_adapter_tuple::<f64>();
}

#[test]
fn no_heap_use_with_adapter_tuple_f32() {
    every_form_with_adapter_tuple::<f32>();
}

/// The RTS record and backward pass in caller storage: thirty recorded
/// predict / update epochs and the smoothing of all of them, armed, in
/// `f32` and `f64`.
fn smoother_run<T: Real>() {
    use kestrel::smoother::{RtsEpoch, RtsRecord, Smoothed};
    let (process, sensor) = models::<T>();
    let zs: [SVector<T, 2>; 30] =
        core::array::from_fn(|k| Vector2::new(0.3 * k as f64, 1.0 - 0.2 * k as f64).cast());
    let mut filter = Ekf::<T, 4>::new(x0(), p0()).expect("finite");
    let mut storage = [RtsEpoch::<T, 4>::default(); 31];
    let mut out = [Smoothed::<T, 4>::default(); 31];
    let (result, calls) = heap_calls(|| {
        let mut record = RtsRecord::new(&mut storage);
        record.start(&filter)?;
        for z in &zs {
            record.predict(&mut filter, &process, lit(0.1))?;
            black_box(filter.update(&sensor, z)?);
            record.observe(&filter)?;
        }
        record.smooth(&mut out)?;
        Ok::<usize, kestrel::smoother::SmootherError>(record.len())
    });
    assert_eq!(result, Ok(31));
    assert_eq!(calls, 0, "{calls} heap calls");
    assert_ne!(out[0].state, storage[0].posterior_state);
}

#[test]
fn no_heap_use_in_the_smoother_f64() {
    smoother_run::<f64>();
}

#[test]
fn no_heap_use_in_the_smoother_f32() {
    smoother_run::<f32>();
}
