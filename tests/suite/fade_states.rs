//! Block fades (`P⁻ = D Φ P Φᵀ D + Q`, `D = diag(√λ on the selected states,
//! 1 elsewhere)`): hand-computed values in the covariance form, the default
//! (every state) identical bit for bit to the scalar fade, the three forms
//! agreeing under a block fade on a linear model (at the update, and at the
//! predict with and without the split; the square-root form with both time
//! updates), f32, and no heap call.

use crate::common;

use std::hint::black_box;

use kestrel::adapter::{GainStep, NoiseAdapter, PriorAdapter, PriorStep};
use kestrel::form::{
    CovarianceForm, FadeStates, Form, PredictForm, SquareRootForm, TimeUpdate, UnscentedForm,
    UpdateForm,
};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix1, Matrix1x2, Matrix2, Matrix4, SVector, Vector1};
use kestrel::nalgebra::{Vector2, Vector4};
use kestrel::real::lit;
use kestrel::{Ekf, Filter, Real, SrUkf, Ukf};
use kestrel_testkit::heap_calls;

/// Fades by a fixed factor after every predict.
struct PriorFade(f64);
impl<T: Real> PriorAdapter<T> for PriorFade {
    const NEEDS_SPLIT: bool = true;
    fn after_predict(&mut self, prior: &mut PriorStep<T>) {
        prior.fade(lit(self.0));
    }
}
impl<T: Real, const M: usize> NoiseAdapter<T, M> for PriorFade {
    type Report = ();
    fn before_gain(&mut self, _: &mut GainStep<T, M>, _: &mut ()) {}
}

/// Fades by a fixed factor after every predict, without the split (the
/// square-root form then folds the fade into its factor at the predict).
struct PriorFadeMerged(f64);
impl<T: Real> PriorAdapter<T> for PriorFadeMerged {
    fn after_predict(&mut self, prior: &mut PriorStep<T>) {
        prior.fade(lit(self.0));
    }
}
impl<T: Real, const M: usize> NoiseAdapter<T, M> for PriorFadeMerged {
    type Report = ();
    fn before_gain(&mut self, _: &mut GainStep<T, M>, _: &mut ()) {}
}

/// Fades at the update by a fixed factor.
struct GainFade(f64);
impl<T: Real> PriorAdapter<T> for GainFade {
    const NEEDS_SPLIT: bool = true;
}
impl<T: Real, const M: usize> NoiseAdapter<T, M> for GainFade {
    type Report = ();
    fn before_gain(&mut self, step: &mut GainStep<T, M>, _: &mut ()) {
        step.fade(lit(self.0));
    }
}

/// Fades at the update by the divergence-test factor computed from the
/// measurement-space split, `λ = max(1, (νᵀν − tr(HQHᵀ + R)) / tr(HΦPΦᵀHᵀ))`,
/// after a fixed fade of 1.1 at every predict.
struct TestFade;
impl<T: Real> PriorAdapter<T> for TestFade {
    const NEEDS_SPLIT: bool = true;
    fn after_predict(&mut self, prior: &mut PriorStep<T>) {
        prior.fade(lit(1.1));
    }
}
impl<T: Real, const M: usize> NoiseAdapter<T, M> for TestFade {
    type Report = Option<T>;
    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Option<T>) {
        let Some((prop, q)) = step.split() else {
            return;
        };
        let excess = step.innovation().norm_squared() - q.trace() - step.noise().trace();
        let lambda = (excess / prop.trace()).max(T::one());
        step.fade(lambda);
        *report = Some(lambda);
    }
}

fn scalar_models() -> (LinearProcess<f64, 2>, LinearMeasurement<f64, 2, 1>) {
    (
        LinearProcess::new(Matrix2::identity(), Matrix2::identity()),
        LinearMeasurement::new(Matrix1x2::new(0.0, 1.0), Matrix1::new(1.0)),
    )
}

fn p0() -> Matrix2<f64> {
    Matrix2::new(4.0, 2.0, 2.0, 9.0)
}

#[test]
fn block_fade_after_predict_matches_hand_computed_prior_and_posterior() {
    // D = diag(1, 2): D P D = [[4, 4], [4, 36]], + Q = [[5, 4], [4, 37]].
    // Update with H = [0 1], R = 1: C = 38, K = [4, 37] / 38,
    // P⁺ = P⁻ − K H P⁻ = [[5 − 16/38, 4 − 148/38], [·, 37 − 37²/38]].
    let (process, sensor) = scalar_models();
    let mut f = Ekf::new(Vector2::zeros(), p0())
        .unwrap()
        .with_adapter(PriorFade(4.0));
    f.form_mut().set_fade_states(FadeStates::range(1..2));
    f.predict(&process, 1.0).unwrap();
    assert_eq!(f.covariance(), Matrix2::new(5.0, 4.0, 4.0, 37.0));
    let detail = f.update_detailed(&sensor, &Vector1::new(3.8)).unwrap();
    assert_eq!(detail.innovation_covariance[0], 38.0);
    let p = f.covariance();
    let expected = Matrix2::new(
        5.0 - 16.0 / 38.0,
        4.0 - 148.0 / 38.0,
        4.0 - 148.0 / 38.0,
        37.0 - 37.0 * 37.0 / 38.0,
    );
    assert!((p - expected).abs().max() < 1e-13, "{p}");
    // x = K ν = [4, 37] · 3.8 / 38.
    assert!((f.state() - Vector2::new(0.4, 3.7)).abs().max() < 1e-13);
}

#[test]
fn block_fade_at_the_update_matches_hand_computed_gain() {
    // Φ P Φᵀ = P0, λ = 4 on state 1 at the update: prior [[5, 4], [4, 37]]
    // as above, so the same posterior.
    let (process, sensor) = scalar_models();
    let mut f = Ekf::new(Vector2::zeros(), p0())
        .unwrap()
        .with_adapter(GainFade(4.0));
    f.form_mut().set_fade_states(FadeStates::range(1..2));
    f.predict(&process, 1.0).unwrap();
    // Before the update nothing is faded yet: P0 + Q.
    assert_eq!(f.covariance(), Matrix2::new(5.0, 2.0, 2.0, 10.0));
    let detail = f.update_detailed(&sensor, &Vector1::new(3.8)).unwrap();
    assert_eq!(detail.report.fade, 4.0);
    assert_eq!(detail.innovation_covariance[0], 38.0);
    let expected = Matrix2::new(
        5.0 - 16.0 / 38.0,
        4.0 - 148.0 / 38.0,
        4.0 - 148.0 / 38.0,
        37.0 - 37.0 * 37.0 / 38.0,
    );
    assert!((f.covariance() - expected).abs().max() < 1e-13);
}

#[test]
fn default_selection_is_the_scalar_fade_bit_for_bit() {
    // Scalar fade: λ P + Q = [[17, 8], [8, 37]].
    let (process, sensor) = scalar_models();
    let mut f = Ekf::new(Vector2::zeros(), p0())
        .unwrap()
        .with_adapter(PriorFade(4.0));
    assert!(f.form().fade_states().is_all());
    f.predict(&process, 1.0).unwrap();
    assert_eq!(f.covariance(), Matrix2::new(17.0, 8.0, 8.0, 37.0));

    // The default, every state selected explicitly (from a range and a
    // mask) and a block selection: the first three agree exactly, over a
    // run with fades at predict and update, in every form; the block differs.
    fn run<F>(mut f: Filter<f64, 4, F, TestFade>, states: Option<FadeStates<4>>) -> Matrix4<f64>
    where
        F: PredictForm<f64, 4, LinearProcess<f64, 4>>
            + UpdateForm<f64, 4, LinearMeasurement<f64, 4, 2>, 2>
            + SetStates,
    {
        if let Some(s) = states {
            f.form_mut().set(s);
        }
        let (process, sensor) = cv_models();
        for z in measurements() {
            f.predict(&process, 0.1).unwrap();
            f.update(&sensor, &z).unwrap();
        }
        f.covariance()
    }
    let selections = [
        None,
        Some(FadeStates::range(0..4)),
        Some(FadeStates::from_mask([true; 4])),
    ];
    let block = Some(FadeStates::range(0..2));
    let ekf = || Ekf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade);
    let ukf = || Ukf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade);
    let sr = || SrUkf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade);
    let e: Vec<_> = selections.iter().map(|s| run(ekf(), *s)).collect();
    let u: Vec<_> = selections.iter().map(|s| run(ukf(), *s)).collect();
    let q: Vec<_> = selections.iter().map(|s| run(sr(), *s)).collect();
    for v in [&e, &u, &q] {
        assert_eq!(v[0], v[1]);
        assert_eq!(v[0], v[2]);
    }
    assert!((run(ekf(), block) - e[0]).abs().max() > 1e-3);
    let _ = sensor;
}

/// Lets the generic run set the selection on any form.
trait SetStates {
    fn set(&mut self, s: FadeStates<4>);
}
impl SetStates for CovarianceForm<f64, 4> {
    fn set(&mut self, s: FadeStates<4>) {
        self.set_fade_states(s);
    }
}
impl SetStates for UnscentedForm<f64, 4> {
    fn set(&mut self, s: FadeStates<4>) {
        self.set_fade_states(s);
    }
}
impl SetStates for SquareRootForm<f64, 4> {
    fn set(&mut self, s: FadeStates<4>) {
        self.set_fade_states(s);
    }
}

/// Constant velocity in two axes, observed in position (the block the
/// fade selects) with correlated `R`.
fn cv_models<T: Real>() -> (LinearProcess<T, 4>, LinearMeasurement<T, 4, 2>) {
    common::constant_velocity(Matrix2::new(0.25, 0.05, 0.05, 0.5))
}

fn x0<T: Real>() -> Vector4<T> {
    Vector4::new(0.0, 1.0, 3.0, -2.0).cast()
}

fn cv_p0<T: Real>() -> Matrix4<T> {
    Matrix4::from_diagonal(&Vector4::new(4.0, 4.0, 1.0, 1.0)).cast()
}

/// Position fixes of a target that turns at step 10 (so the tests fade).
fn measurements<T: Real>() -> [SVector<T, 2>; 30] {
    core::array::from_fn(|k| {
        let t = 0.1 * k as f64;
        let turn = if k > 10 {
            (t - 1.0) * (t - 1.0) * 8.0
        } else {
            0.0
        };
        let wobble = 0.3 * ((k * 7 % 5) as f64 - 2.0);
        Vector2::new(3.0 * t + wobble, 1.0 - 2.0 * t + turn - 0.5 * wobble).cast()
    })
}

#[test]
fn square_root_and_unscented_forms_equal_the_covariance_form_under_a_block_fade() {
    let block = FadeStates::range(0..2);
    let (process, sensor) = cv_models::<f64>();
    let mut ekf = Ekf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade);
    ekf.form_mut().set_fade_states(block);
    let mut ukf = Ukf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade);
    ukf.form_mut().set_fade_states(block);
    let mut srs = [TimeUpdate::Householder, TimeUpdate::RankOne].map(|m| {
        let mut form = SquareRootForm::new(&cv_p0()).unwrap().with_time_update(m);
        form.set_fade_states(block);
        SrUkf::with_form(x0(), form).unwrap().with_adapter(TestFade)
    });
    let mut faded = 0;
    for z in measurements() {
        ekf.predict(&process, 0.1).unwrap();
        ukf.predict(&process, 0.1).unwrap();
        let e = ekf.update(&sensor, &z).unwrap().adapters.unwrap();
        let u = ukf.update(&sensor, &z).unwrap().adapters.unwrap();
        faded += usize::from(e > 1.0);
        assert!((e - u).abs() < 1e-9 * e);
        for sr in &mut srs {
            sr.predict(&process, 0.1).unwrap();
            let s = sr.update(&sensor, &z).unwrap().adapters.unwrap();
            assert!((e - s).abs() < 1e-9 * e);
            assert!((ekf.state() - sr.state()).abs().max() < 1e-9);
            assert!((ekf.covariance() - sr.covariance()).abs().max() < 1e-9);
        }
        assert!((ekf.state() - ukf.state()).abs().max() < 1e-9);
        assert!((ekf.covariance() - ukf.covariance()).abs().max() < 1e-9);
    }
    // The comparison is not vacuous: the update-time fade fired.
    assert!(faded >= 3, "{faded}");
}

#[test]
fn block_fade_at_the_predict_is_the_same_in_every_form_with_and_without_split() {
    let block = FadeStates::range(1..3);
    let (process, sensor) = cv_models::<f64>();
    let mut ekf = Ekf::new(x0(), cv_p0())
        .unwrap()
        .with_adapter(PriorFadeMerged(1.7));
    ekf.form_mut().set_fade_states(block);
    let mut ukf = Ukf::new(x0(), cv_p0())
        .unwrap()
        .with_adapter(PriorFadeMerged(1.7));
    ukf.form_mut().set_fade_states(block);
    let mut split = SrUkf::new(x0(), cv_p0())
        .unwrap()
        .with_adapter(PriorFade(1.7));
    split.form_mut().set_fade_states(block);
    let mut merged = [TimeUpdate::Householder, TimeUpdate::RankOne].map(|m| {
        let mut form = SquareRootForm::new(&cv_p0()).unwrap().with_time_update(m);
        form.set_fade_states(block);
        SrUkf::with_form(x0(), form)
            .unwrap()
            .with_adapter(PriorFadeMerged(1.7))
    });
    // One predict by hand: D Φ P0 Φᵀ D + Q with D = diag(1, √1.7, √1.7, 1).
    let phi = process.transition;
    let d = Matrix4::from_diagonal(&Vector4::new(1.0, 1.7f64.sqrt(), 1.7f64.sqrt(), 1.0));
    let expected = d * phi * cv_p0::<f64>() * phi.transpose() * d + process.noise;
    ekf.predict(&process, 0.1).unwrap();
    assert!((ekf.covariance() - expected).abs().max() < 1e-12);
    ukf.predict(&process, 0.1).unwrap();
    split.predict(&process, 0.1).unwrap();
    for f in &mut merged {
        f.predict(&process, 0.1).unwrap();
        assert!((f.covariance() - expected).abs().max() < 1e-12);
    }
    assert!((ukf.covariance() - expected).abs().max() < 1e-12);
    assert!((split.covariance() - expected).abs().max() < 1e-12);
    for (k, z) in measurements().iter().enumerate() {
        if k > 0 {
            ekf.predict(&process, 0.1).unwrap();
            ukf.predict(&process, 0.1).unwrap();
            split.predict(&process, 0.1).unwrap();
            merged
                .iter_mut()
                .for_each(|f| f.predict(&process, 0.1).unwrap());
        }
        ekf.update(&sensor, z).unwrap();
        ukf.update(&sensor, z).unwrap();
        split.update(&sensor, z).unwrap();
        let p = ekf.covariance();
        let others =
            [ukf.covariance(), split.covariance()]
                .into_iter()
                .chain(merged.iter_mut().map(|f| {
                    f.update(&sensor, z).unwrap();
                    f.covariance()
                }));
        for q in others {
            assert!((p - q).abs().max() < 1e-9, "{p} {q}");
        }
    }
}

#[test]
fn block_fades_make_no_heap_call() {
    fn armed<F>(mut f: Filter<f64, 4, F, TestFade>) -> usize
    where
        F: PredictForm<f64, 4, LinearProcess<f64, 4>>
            + UpdateForm<f64, 4, LinearMeasurement<f64, 4, 2>, 2>
            + SetStates,
    {
        f.form_mut().set(FadeStates::range(0..2));
        let (process, sensor) = cv_models();
        let zs = measurements();
        let (accepted, calls) = heap_calls(|| {
            let mut n = 0;
            for z in &zs {
                f.predict(&process, 0.1).unwrap();
                n += usize::from(f.update(&sensor, z).is_ok());
                black_box(f.covariance());
            }
            n
        });
        assert_eq!(accepted, 30);
        calls
    }
    assert_eq!(
        armed(Ekf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade)),
        0
    );
    assert_eq!(
        armed(Ukf::new(x0(), cv_p0()).unwrap().with_adapter(TestFade)),
        0
    );
    for m in [TimeUpdate::Householder, TimeUpdate::RankOne] {
        let form = SquareRootForm::new(&cv_p0()).unwrap().with_time_update(m);
        let f = SrUkf::with_form(x0(), form).unwrap().with_adapter(TestFade);
        assert_eq!(armed(f), 0);
    }
}

#[test]
fn block_fades_work_in_f32() {
    let (process, sensor) = cv_models::<f32>();
    let mut form = SquareRootForm::<f32, 4>::new(&cv_p0()).unwrap();
    form.set_fade_states(FadeStates::range(0..2));
    let mut sr = SrUkf::with_form(x0(), form).unwrap().with_adapter(TestFade);
    let mut ekf = Ekf::<f32, 4, _>::new(x0(), cv_p0())
        .unwrap()
        .with_adapter(TestFade);
    ekf.form_mut().set_fade_states(FadeStates::range(0..2));
    for z in measurements::<f32>() {
        sr.predict(&process, 0.1).unwrap();
        ekf.predict(&process, 0.1).unwrap();
        sr.update(&sensor, &z).unwrap();
        ekf.update(&sensor, &z).unwrap();
    }
    assert!((ekf.state() - sr.state()).abs().max() < 1e-3);
    let _ = ekf.form().covariance();
}
