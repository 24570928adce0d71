//! The batch update of the covariance, unscented and square-root forms
//! without an adapter (the fast path `()` takes) gives what the general
//! adapter round gives when the adapter changes nothing: state, covariance
//! and every field of the report, on random stable linear models of 2 to 24
//! states with dense `R` — including a process noise and a measurement noise
//! that change from step to step, so the cached factor of `R` is exercised
//! both when it applies and when it does not.
//!
//! The fast paths of the covariance and unscented forms solve with
//! `C = L D Lᵀ` (no square roots), the general one with the Cholesky factor
//! `C = L Lᵀ` the adapters read; the square-root form's general round forms
//! the nominal `C` as `(C − R) + R`. So the paths agree to rounding, not bit
//! for bit: within `1e-13` relative to the largest element of each quantity,
//! with the filters stepped in lockstep from the same prior each step (no
//! accumulation). The innovations, `R` and the flags are compared exactly.

use crate::common;

use common::{dispatch, srukf, ukf, Make, SIZES};
use kestrel::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel::form::{Form, PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::SMatrix;
use kestrel::UpdateDetail;

/// Relative agreement of two solves of the same system by different
/// factorisations (observed: below `1e-14` on these models, a tenfold margin).
const ROUNDING: f64 = 1e-13;

/// `a` and `b` agree within `ROUNDING` times the largest element of `b`.
fn close<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    what: &str,
) {
    let scale = b.amax().max(f64::MIN_POSITIVE);
    let diff = (a - b).amax();
    assert!(
        diff <= ROUNDING * scale,
        "{what}: {a} vs {b} (difference {diff:e})"
    );
}

/// An adapter that puts the model's own `R` back in place: nothing changes
/// in value, but the view counts `R` as set, so every form runs its whole
/// adapter round (the covariance form takes an epoch left as it was the
/// way without adapters; `quiet_epochs` tests that).
struct Restated;

impl PriorAdapter<f64> for Restated {}

impl<const M: usize> NoiseAdapter<f64, M> for Restated {
    type Report = ();
    fn before_gain(&mut self, step: &mut GainStep<f64, M>, _report: &mut ()) {
        let r = *step.noise();
        step.set_noise(r);
    }
}

fn linear<F, const N: usize, const M: usize>(make: Make<F, N>, seed: u64)
where
    F: Form<f64, N>
        + Clone
        + PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, M>, M>,
{
    let case = common::linear_case::<N, M>(seed, 40, false);
    let mut fast = make(case.x0, case.p0);
    let mut general = fast.clone();
    for (k, z) in case.measurements.iter().enumerate() {
        // Every third step a scaled Q and R: a changed noise is checked and
        // factored again, the same one comes from the cache.
        let scale = if k % 3 == 2 { 1.5 } else { 1.0 };
        let process = LinearProcess::new(case.process.transition, case.process.noise * scale);
        let measurement =
            LinearMeasurement::new(case.measurement.matrix, case.measurement.noise * scale);
        fast.predict(&process, 1.0).expect("predict");
        general.predict(&process, 1.0).expect("predict");
        // A filter built from the prior has nothing cached: it checks and
        // factors R itself.
        let mut fresh = make(*fast.state(), fast.covariance());
        let c = fresh.update_detailed(&measurement, z).expect("update");
        let a = fast.update_detailed(&measurement, z).expect("update");
        let b = general
            .update_detailed_with(&measurement, z, &mut Restated)
            .expect("update");
        let what = format!("N = {N}, M = {M}, seed {seed}, step {k}");
        close(fast.state(), general.state(), &format!("{what}: state"));
        close(
            &fast.covariance(),
            &general.covariance(),
            &format!("{what}: covariance"),
        );
        let nis = |d: &UpdateDetail<f64, M>| {
            SMatrix::<f64, 2, 1>::new(d.report.nis, d.report.adapted_nis)
        };
        close(&nis(&a), &nis(&b), &format!("{what}: NIS"));
        let (ra, rb) = (&a.report, &b.report);
        assert_eq!(ra.innovation, rb.innovation, "{what}");
        assert_eq!(ra.innovation_used, rb.innovation_used, "{what}");
        // To rounding for the square-root form, whose general round forms
        // the nominal `C` as `(C − R) + R`.
        close(
            &a.innovation_covariance,
            &b.innovation_covariance,
            &format!("{what}: C"),
        );
        close(
            &a.nominal_innovation_covariance,
            &b.nominal_innovation_covariance,
            &format!("{what}: nominal C"),
        );
        assert_eq!(a.noise, b.noise, "{what}");
        assert_eq!(
            (ra.fade, ra.rejected, ra.sequential),
            (rb.fade, rb.rejected, rb.sequential),
            "{what}"
        );
        // Lockstep: the next step starts both from the same prior.
        general = fast.clone();
        // (To rounding: the square-root form factors the covariance it is
        // built from again.)
        let cached = format!("{what}: cached R");
        close(&fresh.covariance(), &fast.covariance(), &cached);
        close(fresh.state(), fast.state(), &cached);
        close(&c.innovation_covariance, &a.innovation_covariance, &cached);
        close(&nis(&c), &nis(&a), &cached);
        assert_eq!(c.noise, a.noise, "{cached}");
        assert!(!ra.sequential && !ra.rejected, "{what}");
    }
}

fn linear_ekf<const N: usize, const M: usize>(seed: u64) {
    linear::<_, N, M>(common::batch_ekf::<N>, seed);
}

fn linear_ukf<const N: usize, const M: usize>(seed: u64) {
    linear::<_, N, M>(ukf::<N>, seed);
}

fn linear_srukf<const N: usize, const M: usize>(seed: u64) {
    linear::<_, N, M>(srukf::<N>, seed);
}

#[test]
fn the_unadapted_batch_update_equals_the_general_path() {
    for seed in 0..3u64 {
        for &size in SIZES {
            dispatch!(size, linear_ekf(seed));
        }
    }
}

#[test]
fn the_unadapted_unscented_update_equals_the_general_path() {
    for seed in 0..3u64 {
        for &size in SIZES {
            dispatch!(size, linear_ukf(seed));
        }
    }
}

#[test]
fn the_unadapted_square_root_update_equals_the_general_path() {
    for seed in 0..3u64 {
        for &size in SIZES {
            dispatch!(size, linear_srukf(seed));
        }
    }
}
