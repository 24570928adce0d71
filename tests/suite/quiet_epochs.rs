//! Epochs the adapters leave as they were. When no adapter faded, set `R`,
//! changed the innovation or rejected the measurement, the covariance and
//! unscented forms update as they do without adapters, on the same
//! `L D Lᵀ` of `C`, and hand the adapters a posterior view on it that
//! computes what an adapter reads only when it reads it. So an adapter that
//! changes nothing gives the filter without adapters bit for bit (state,
//! covariance, report), and what it reads from the posterior view equals
//! what it reads after an adapter round that restated `R` to rounding (bit
//! for bit, as it happens: the view's own `L D Lᵀ` of the same `C`).

use crate::common;

use common::{dispatch, Make, SIZES};
use kestrel::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter};
use kestrel::form::{Form, PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::{Filter, UpdateDetail};

/// Relative agreement of the two rounds' posterior views (the factor of
/// `C` as `L √D` of the form's `L D Lᵀ` or by a Cholesky factorisation;
/// observed below `1e-14` on these models). `H P⁺ Hᵀ = H P⁻ Hᵀ − GᵀG` and
/// the post-fit residual `ν − Gᵀ L⁻¹ ν` are differences, so their rounding
/// is relative to what they are the difference of.
const ROUNDING: f64 = 1e-13;

/// What an adapter read from the posterior view at its last update.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Seen<const M: usize> {
    innovation: SVector<f64, M>,
    predicted: SMatrix<f64, M, M>,
    whitened: SVector<f64, M>,
    residual: SVector<f64, M>,
    covariance: SMatrix<f64, M, M>,
    solved: SVector<f64, M>,
}

/// Changes nothing unless `restate` (then it puts the model's own `R` back,
/// which makes the form run its full adapter round); with `whiten` its test
/// factors `C` before the gain, as a χ² test would. Reads the whole
/// posterior view and counts its updates.
#[derive(Debug, Clone, Copy)]
struct Observer<const M: usize> {
    restate: bool,
    whiten: bool,
    updates: usize,
    seen: Option<Seen<M>>,
}

impl<const M: usize> Observer<M> {
    fn new(restate: bool, whiten: bool) -> Self {
        Self {
            restate,
            whiten,
            updates: 0,
            seen: None,
        }
    }
}

impl<const M: usize> PriorAdapter<f64> for Observer<M> {}

impl<const M: usize> NoiseAdapter<f64, M> for Observer<M> {
    type Report = ();

    fn before_gain(&mut self, step: &mut GainStep<f64, M>, _report: &mut ()) {
        if self.whiten {
            assert!(step.mahalanobis().is_some());
        }
        if self.restate {
            let r = *step.noise();
            step.set_noise(r);
        }
    }

    fn after_update(&mut self, posterior: &Posterior<'_, f64, M>, _report: &mut ()) {
        self.updates += 1;
        self.seen = Some(Seen {
            innovation: *posterior.innovation(),
            predicted: *posterior.predicted_covariance(),
            whitened: *posterior.whitened_innovation(),
            residual: posterior.post_fit_residual(),
            covariance: posterior.posterior_covariance(),
            solved: posterior.solve(posterior.innovation()),
        });
    }
}

/// `a` and `b` agree within `ROUNDING` times the largest element of `b`.
fn close<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    what: &str,
) {
    close_to_scale(a, b, b.amax(), what);
}

/// `a` and `b` agree within `ROUNDING` times `scale`.
fn close_to_scale<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    scale: f64,
    what: &str,
) {
    let scale = scale.max(f64::MIN_POSITIVE);
    let diff = (a - b).amax();
    assert!(
        diff <= ROUNDING * scale,
        "{what}: {a} vs {b} (difference {diff:e})"
    );
}

/// Everything the detailed update returns, compared exactly.
fn same<const M: usize>(a: &UpdateDetail<f64, M>, b: &UpdateDetail<f64, M>, what: &str) {
    let (ra, rb) = (&a.report, &b.report);
    assert_eq!(
        (ra.innovation, ra.innovation_used, ra.nis, ra.adapted_nis),
        (rb.innovation, rb.innovation_used, rb.nis, rb.adapted_nis),
        "{what}"
    );
    assert_eq!(
        (ra.fade, ra.rejected, ra.sequential),
        (rb.fade, rb.rejected, rb.sequential),
        "{what}"
    );
    assert_eq!(a.innovation_covariance, b.innovation_covariance, "{what}");
    assert_eq!(
        a.nominal_innovation_covariance, b.nominal_innovation_covariance,
        "{what}"
    );
    assert_eq!(a.noise, b.noise, "{what}");
}

fn run<F, const N: usize, const M: usize>(make: Make<F, N>, seed: u64)
where
    F: Form<f64, N>
        + Clone
        + PredictForm<f64, N, LinearProcess<f64, N>>
        + UpdateForm<f64, N, LinearMeasurement<f64, N, M>, M>,
{
    let case = common::linear_case::<N, M>(seed, 30, false);
    let mut plain = make(case.x0, case.p0);
    let mut quiet = plain.clone().with_adapter(Observer::<M>::new(false, false));
    let mut tested = plain.clone().with_adapter(Observer::<M>::new(false, true));
    for (k, z) in case.measurements.iter().enumerate() {
        // Every third step a scaled R, as in `unadapted`: the form's cached
        // factor of R applies and then does not.
        let scale = if k % 3 == 2 { 1.5 } else { 1.0 };
        let process = LinearProcess::new(case.process.transition, case.process.noise);
        let measurement =
            LinearMeasurement::new(case.measurement.matrix, case.measurement.noise * scale);
        plain.predict(&process, 1.0).expect("predict");
        quiet.predict(&process, 1.0).expect("predict");
        tested.predict(&process, 1.0).expect("predict");
        // The full round, from the same prior.
        let mut full = quiet.clone();
        full.adapter_mut().restate = true;

        let a = plain.update_detailed(&measurement, z).expect("update");
        let b = quiet.update_detailed(&measurement, z).expect("update");
        let c = tested.update_detailed(&measurement, z).expect("update");
        let d = full.update_detailed(&measurement, z).expect("update");
        let what = format!("N = {N}, M = {M}, seed {seed}, step {k}");

        // Bit for bit the filter without adapters, with a test or without.
        for (f, detail, name) in [
            (&quiet.state(), &b, "quiet"),
            (&tested.state(), &c, "tested"),
        ] {
            assert_eq!(*f, plain.state(), "{what}: {name} state");
            same(&a, detail, &format!("{what}: {name}"));
        }
        assert_eq!(quiet.covariance(), plain.covariance(), "{what}");
        assert_eq!(tested.covariance(), plain.covariance(), "{what}");
        assert_eq!(b.report.adapted_nis, b.report.nis, "{what}");

        // The full round agrees to rounding, and so does what the adapters
        // read; a factor made by the adapter's test is the one the view
        // would form, so those two read the same bits.
        close(full.state(), plain.state(), &format!("{what}: state"));
        close(
            &full.covariance(),
            &plain.covariance(),
            &format!("{what}: P"),
        );
        let nis = |d: &UpdateDetail<f64, M>| SMatrix::<f64, 1, 1>::new(d.report.adapted_nis);
        close(&nis(&d), &nis(&b), &format!("{what}: adapted NIS"));
        let seen = |f: &Filter<f64, N, F, Observer<M>>| f.adapter().seen.expect("after_update ran");
        let (q, t, r) = (seen(&quiet), seen(&tested), seen(&full));
        assert_eq!(q, t, "{what}: the view's factor");
        close(&q.whitened, &r.whitened, &format!("{what}: L⁻¹ ν"));
        let (nu, hph) = (r.innovation.amax(), r.predicted.amax());
        close_to_scale(
            &q.residual,
            &r.residual,
            nu,
            &format!("{what}: post-fit residual"),
        );
        close_to_scale(
            &q.covariance,
            &r.covariance,
            hph,
            &format!("{what}: H P⁺ Hᵀ"),
        );
        close(&q.solved, &r.solved, &format!("{what}: C⁻¹ ν"));
        assert_eq!(
            (quiet.adapter().updates, tested.adapter().updates),
            (k + 1, k + 1),
            "{what}: after_update runs in every epoch"
        );
    }
}

fn covariance<const N: usize, const M: usize>(seed: u64) {
    run::<_, N, M>(common::batch_ekf, seed);
}

fn unscented<const N: usize, const M: usize>(seed: u64) {
    run::<_, N, M>(common::ukf, seed);
}

#[test]
fn an_adapter_that_changes_nothing_gives_the_filter_without_adapters() {
    for seed in 0..3u64 {
        for &size in SIZES {
            dispatch!(size, covariance(seed));
        }
    }
}

#[test]
fn the_unscented_form_too() {
    for seed in 0..3u64 {
        for &size in SIZES {
            dispatch!(size, unscented(seed));
        }
    }
}
