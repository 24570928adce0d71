//! The covariance form's batch update without an adapter (the fast path
//! `()` takes) gives exactly what the general adapter round gives when the
//! adapter changes nothing: state, covariance and every field of the
//! report, bit for bit, on random stable linear models of 2 to 24 states
//! with dense `R` — including a process noise and a measurement noise that
//! change from step to step, so the cached factor of `R` is exercised both
//! when it applies and when it does not.

mod common;

use common::{dispatch, SIZES};
use kestrel::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::Ekf;

/// An adapter that does nothing but is not declared an identity: the form
/// runs its whole adapter round for it.
struct Passive;

impl PriorAdapter<f64> for Passive {}

impl<const M: usize> NoiseAdapter<f64, M> for Passive {
    type Report = ();
    fn before_gain(&mut self, _step: &mut GainStep<f64, M>, _report: &mut ()) {}
}

fn linear<const N: usize, const M: usize>(seed: u64) {
    let case = common::linear_case::<N, M>(seed, 40, false);
    let mut fast = Ekf::new(case.x0, case.p0).expect("finite");
    fast.form_mut().set_sequential(false);
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
        let mut fresh = Ekf::new(*fast.state(), fast.covariance()).expect("finite");
        fresh.form_mut().set_sequential(false);
        let c = fresh.update(&measurement, z).expect("update");
        let a = fast.update(&measurement, z).expect("update");
        let b = general
            .update_with(&measurement, z, &mut Passive)
            .expect("update");
        let what = format!("N = {N}, M = {M}, seed {seed}, step {k}");
        assert_eq!(fast.state(), general.state(), "{what}");
        assert_eq!(fast.covariance(), general.covariance(), "{what}");
        assert_eq!(a, b, "{what}");
        assert_eq!(fresh.covariance(), fast.covariance(), "{what}: cached R");
        assert_eq!(c, a, "{what}: cached R");
        assert!(!a.sequential && !a.rejected, "{what}");
    }
}

#[test]
fn the_unadapted_batch_update_equals_the_general_path() {
    for seed in 0..3u64 {
        for &size in SIZES {
            dispatch!(size, linear(seed));
        }
    }
}
