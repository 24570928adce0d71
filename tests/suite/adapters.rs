//! The noise-adapter hook, for every form: the order in which tuple members
//! run, and that each thing an adapter can do (replace `R`, fade, scale the
//! innovation, reject) has exactly the effect of the equivalent change to
//! the models or the measurement, on a linear model where every form is the
//! Kalman filter.
//!
//! The model is the 2-D constant-velocity case of `support::cv` with R = ¾:
//! the first predict gives x⁻ = (3, 2), Φ P₀ Φᵀ = [8 3; 3 2] and
//! P⁻ = [8.25 3.5; 3.5 3].

use crate::support;

use kestrel::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel::form::UpdateForm;
use kestrel::form::{SquareRootForm, TimeUpdate};
use kestrel::models::LinearMeasurement;
use kestrel::nalgebra::{Matrix1, Matrix2, SMatrix, SVector, Vector1, Vector2};
use kestrel::{Ekf, Filter, SrUkf, Ukf};
use support::cv::{
    assert_same_estimate, p0, phi, plain, position, process, q, two_sensors, LinForm, TOL, X0, ZS,
};
use support::{
    assert_close, assert_scalar, assert_slice, bits, log, Action, Event, Probe, ProbeReport,
};

// (a) ------------------------------------------------------------------------

fn members_in_order<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    use Event::{Gain, Predict, Update};
    let log = log();
    let a = Probe::<false>::new(1, &log).with_actions(&[Action::ScaleNoise(2.0)]);
    let b = Probe::<false>::new(2, &log).with_actions(&[Action::ScaleNoise(3.0)]);
    let c = Probe::<false>::new(3, &log);
    let mut f = f.with_adapter((a, b, c));

    f.predict(&process(), 1.0).unwrap();
    assert_eq!(
        *log.borrow(),
        [Predict(1), Predict(2), Predict(3)],
        "{name}"
    );
    let detail = f
        .update_detailed(&position(0.75), &Vector1::new(6.0))
        .unwrap();
    assert_eq!(
        log.borrow()[3..],
        [Gain(1), Gain(2), Gain(3), Update(1), Update(2), Update(3)],
        "{name}"
    );
    let at = |id, gain, update| ProbeReport {
        id,
        gain_at: Some(gain),
        update_at: Some(update),
    };
    assert_eq!(
        detail.report.adapters,
        (at(1, 3, 6), at(2, 4, 7), at(3, 5, 8)),
        "{name}"
    );

    // Each member sees what the one before left: R = ¾ → 1.5 → 4.5, and
    // C = 8.25 + R: 9 → 9.75 (first) → 12.75 (second).
    let (a, b, c) = f.adapter();
    assert_slice(&a.seen_noise[0], &[0.75], TOL, name);
    assert_slice(&b.seen_noise[0], &[1.5], TOL, name);
    assert_slice(&c.seen_noise[0], &[4.5], TOL, name);
    assert_slice(&a.seen_covariances[0].concat(), &[9.0, 9.75], TOL, name);
    assert_slice(&b.seen_covariances[0].concat(), &[9.75, 12.75], TOL, name);
    assert_slice(&c.seen_covariances[0].concat(), &[12.75], TOL, name);
    assert_scalar(detail.noise[0], 4.5, TOL, name);
    // All three saw the same posterior.
    assert_eq!(a.posteriors, c.posteriors, "{name}");
    assert_eq!(a.posteriors[0].noise, [4.5], "{name}");
}

#[test]
fn tuple_members_run_in_order() {
    each_form!(members_in_order);
}

// (b) ------------------------------------------------------------------------

fn scaled_noise<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    let k = 4.0;
    let probe = Probe::<false>::new(1, &log()).with_actions(&[Action::ScaleNoise(k)]);
    let r = Matrix1::new(0.75 * k);
    let z = |z| Vector1::new(z);
    same_as_noise_model(name, f, probe, &position(0.75), &position(0.75 * k), r, z);
}

/// Runs `f` with `adapter` on `sensor` and, from the same start, without an
/// adapter on `reference` (the model with the `R` the adapter should put in
/// place, `r`), over the measurements `to_z(ZS)`, and checks after every
/// update that both hold the same estimate and report the same `C` and NIS.
fn same_as_noise_model<F, A, const M: usize>(
    name: &str,
    f: Filter<f64, 2, F>,
    adapter: A,
    sensor: &LinearMeasurement<f64, 2, M>,
    reference: &LinearMeasurement<f64, 2, M>,
    r: SMatrix<f64, M, M>,
    to_z: impl Fn(f64) -> SVector<f64, M>,
) where
    F: LinForm + UpdateForm<f64, 2, LinearMeasurement<f64, 2, M>, M>,
    A: NoiseAdapter<f64, M>,
{
    let mut adapted = f.clone().with_adapter(adapter);
    let mut plain = f;
    for z in ZS.map(to_z) {
        adapted.predict(&process(), 1.0).unwrap();
        plain.predict(&process(), 1.0).unwrap();
        let got = adapted.update_detailed(sensor, &z).unwrap();
        let want = plain.update_detailed(reference, &z).unwrap();
        assert!(!want.report.sequential || M == 1, "{name}");
        assert_same_estimate(name, &adapted, &plain);
        assert_close(&got.noise, &r, 1e-15, name);
        assert_close(
            &got.innovation_covariance,
            &want.innovation_covariance,
            TOL,
            name,
        );
        assert_scalar(got.report.adapted_nis, want.report.nis, TOL, name);
    }
}

#[test]
fn scaling_r_equals_a_model_with_scaled_r() {
    each_form!(scaled_noise);
}

/// Gives `R` by its lower factor ([`GainStep::set_noise_factor`]).
#[derive(Clone, Debug)]
struct NoiseByFactor(Matrix2<f64>);

impl PriorAdapter<f64> for NoiseByFactor {}

impl NoiseAdapter<f64, 2> for NoiseByFactor {
    type Report = ();
    fn before_gain(&mut self, step: &mut GainStep<f64, 2>, _: &mut ()) {
        step.set_noise_factor(&self.0);
    }
}

/// An `R` given by its factor is the `R` of a model with `L Lᵀ`: the form
/// takes the factor into the Joseph update instead of factoring `R` itself.
fn noise_by_factor<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    // L = [1.2 0; 0.5 0.9] (the 7 above the diagonal is not read).
    let l = Matrix2::new(1.2, 7.0, 0.5, 0.9);
    let r = Matrix2::new(1.44, 0.6, 0.6, 1.06);
    let reference = LinearMeasurement::new(Matrix2::new(1.0, 0.0, 1.0, 1.0), r);
    let z = |z| Vector2::new(z, 2.0 * z - 1.0);
    same_as_noise_model(name, f, NoiseByFactor(l), &two_sensors(), &reference, r, z);
}

#[test]
fn noise_given_by_its_factor_equals_a_model_with_that_noise() {
    each_form!(noise_by_factor);
}

/// A factor that is not finite gives an `R` that is not finite: the update
/// is refused as for one given by `set_noise`, and the filter is unchanged.
fn non_finite_noise_factor<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    for bad in [f64::NAN, f64::INFINITY, -f64::INFINITY] {
        let l = Matrix2::new(1.0, 0.0, bad, 1.0);
        let mut f = f.clone().with_adapter(NoiseByFactor(l));
        f.predict(&process(), 1.0).unwrap();
        let (x, p) = (*f.state(), f.covariance());
        let err = f
            .update(&two_sensors(), &Vector2::new(6.0, 11.0))
            .unwrap_err();
        assert!(
            matches!(
                err,
                kestrel::FilterError::NonFinite {
                    what: kestrel::Quantity::MeasurementNoise,
                    ..
                }
            ),
            "{name}: {err:?}"
        );
        assert_eq!((*f.state(), f.covariance()), (x, p), "{name}");
    }
}

#[test]
fn a_non_finite_noise_factor_is_refused() {
    each_form!(non_finite_noise_factor);
}

/// Fades by `fade` (1: none), then puts `R = −100 I` in place: `C` is then
/// indefinite.
#[derive(Clone, Copy, Debug)]
struct IndefiniteNoise {
    fade: f64,
}

impl PriorAdapter<f64> for IndefiniteNoise {}

impl NoiseAdapter<f64, 2> for IndefiniteNoise {
    type Report = ();
    fn before_gain(&mut self, step: &mut GainStep<f64, 2>, _: &mut ()) {
        step.fade(self.fade);
        step.set_noise(Matrix2::identity() * -100.0);
    }
}

/// An `R` that leaves `C` indefinite is refused with the pivot the
/// factorisation of `C` failed at (the view's own `L D Lᵀ` when nothing
/// faded, one of `C` from the faded prior otherwise), or, in the
/// square-root form, as an `R` without a factor; the filter is unchanged.
fn indefinite_noise<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    use kestrel::{FilterError, Quantity};
    for fade in [1.0, 1.5] {
        let mut f = f.clone().with_adapter(IndefiniteNoise { fade });
        f.predict(&process(), 1.0).unwrap();
        let (x, p) = (*f.state(), f.covariance());
        let err = f
            .update(&two_sensors(), &Vector2::new(6.0, 11.0))
            .unwrap_err();
        let what = if name == "sr-ukf" || name == "sr-ukf rank-one" {
            Quantity::MeasurementNoise
        } else {
            Quantity::InnovationCovariance
        };
        assert_eq!(
            err,
            FilterError::NotPositiveDefinite { what, index: 0 },
            "{name}, fade {fade}"
        );
        assert_eq!((*f.state(), f.covariance()), (x, p), "{name}, fade {fade}");
    }
}

#[test]
fn a_noise_that_leaves_c_indefinite_is_refused() {
    each_form!(indefinite_noise);
}

// (c) and (g) -----------------------------------------------------------------

/// Where the fade comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
enum FadeAt {
    /// `PriorStep::fade` in `after_predict`.
    Predict,
    /// `GainStep::fade` in `before_gain`.
    Gain,
}

/// Runs four steps fading by λ = 1.5 and compares each update with the same
/// form started from the hand-built prior `λ Φ P Φᵀ + Q` (or, if `whole`,
/// `λ (Φ P Φᵀ + Q)`).
fn faded<F: LinForm, const SPLIT: bool>(name: &str, f: Filter<f64, 2, F>, at: FadeAt, whole: bool) {
    let lambda = 1.5;
    let probe = match at {
        FadeAt::Predict => Probe::<SPLIT>::new(1, &log()).with_predict_fade(lambda),
        FadeAt::Gain => Probe::<SPLIT>::new(1, &log()).with_actions(&[Action::Fade(lambda)]),
    };
    let mut f = f.with_adapter(probe);
    let name = format!("{name} {at:?} split={SPLIT}");
    for z in ZS {
        let (x, p) = (*f.state(), f.covariance());
        let propagated = phi() * p * phi().transpose();
        let prior = if whole {
            (propagated + q()) * lambda
        } else {
            propagated * lambda + q()
        };
        f.predict(&process(), 1.0).unwrap();
        if at == FadeAt::Predict {
            assert_close(&f.covariance(), &prior, TOL, &name);
        }
        let mut reference = plain(&f, phi() * x, prior);
        let z = Vector1::new(z);
        let got = f.update_detailed(&position(0.75), &z).unwrap();
        let want = reference.update_detailed(&position(0.75), &z).unwrap();
        assert_same_estimate(&name, &f, &reference);
        assert_close(
            &got.innovation_covariance,
            &want.innovation_covariance,
            TOL,
            &name,
        );
        assert_scalar(got.report.adapted_nis, want.report.nis, TOL, &name);
        assert_scalar(got.report.fade, lambda, TOL, &name);
    }
}

#[test]
fn fading_before_the_gain_equals_the_faded_prior() {
    for at in [FadeAt::Gain, FadeAt::Predict] {
        // The covariance and unscented forms keep Q apart until the update,
        // so they fade exactly with or without the split.
        faded::<_, false>("ekf", Ekf::new(X0, p0()).unwrap(), at, false);
        faded::<_, true>("ekf", Ekf::new(X0, p0()).unwrap(), at, false);
        faded::<_, false>("ukf", Ukf::new(X0, p0()).unwrap(), at, false);
        faded::<_, true>("ukf", Ukf::new(X0, p0()).unwrap(), at, false);
        for method in [TimeUpdate::Householder, TimeUpdate::RankOne] {
            let sr = || {
                let form = SquareRootForm::new(&p0()).unwrap().with_time_update(method);
                SrUkf::with_form(X0, form).unwrap()
            };
            faded::<_, true>("sr-ukf", sr(), at, false);
            // Without the split the square-root form merges Q into its factor
            // at the predict, so a fade at the gain scales all of P⁻; a fade
            // at the predict is still applied before Q is added.
            faded::<_, false>("sr-ukf", sr(), at, at == FadeAt::Gain);
        }
    }
}

// (d) ------------------------------------------------------------------------

fn scaled_innovation<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    let s = 0.5;
    let probe = Probe::<false>::new(1, &log()).with_actions(&[Action::ScaleInnovation(s)]);
    let mut adapted = f.clone().with_adapter(probe);
    let mut reference = f;
    for z in ZS {
        adapted.predict(&process(), 1.0).unwrap();
        reference.predict(&process(), 1.0).unwrap();
        // ẑ = H x⁻; the reference sees z' = ẑ + s ν.
        let z_hat = reference.state()[0];
        let moved = Vector1::new(z_hat + s * (z - z_hat));
        let got = adapted.update(&position(0.75), &Vector1::new(z)).unwrap();
        let want = reference.update(&position(0.75), &moved).unwrap();
        assert_same_estimate(name, &adapted, &reference);
        assert_scalar(got.innovation[0], z - z_hat, TOL, name);
        assert_close(&got.innovation_used, &want.innovation, TOL, name);
        assert_scalar(got.adapted_nis, want.nis, TOL, name);
    }
}

#[test]
fn scaling_the_innovation_equals_moving_the_measurement() {
    each_form!(scaled_innovation);
}

// (e) ------------------------------------------------------------------------

fn rejected<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    let log = log();
    let first = Probe::<false>::new(1, &log).with_actions(&[Action::ScaleNoise(2.0)]);
    let gate = Probe::<false>::new(2, &log).with_actions(&[Action::Reject]);
    let mut f = f.with_adapter((first, gate));
    f.predict(&process(), 1.0).unwrap();
    let (x, p) = (*f.state(), f.covariance());
    let skipped = f.clone();

    let detail = f
        .update_detailed(&position(0.75), &Vector1::new(6.0))
        .unwrap();
    assert!(detail.report.rejected, "{name}");
    assert_eq!(bits(f.state()), bits(&x), "{name}: state is the prior");
    assert_eq!(bits(&f.covariance()), bits(&p), "{name}: covariance");
    assert_scalar(detail.report.innovation[0], 3.0, TOL, name);
    assert_scalar(detail.report.innovation_used[0], 3.0, TOL, name);
    assert_scalar(detail.report.nis, 1.0, TOL, name);
    assert_scalar(detail.noise[0], 1.5, TOL, name);
    assert_eq!(detail.report.fade, 1.0, "{name}");
    // `after_update` runs only after an accepted update.
    assert_eq!(detail.report.adapters.1.update_at, None, "{name}");
    assert!(f.adapter().0.posteriors.is_empty(), "{name}");
    assert!(!log.borrow().contains(&Event::Update(1)), "{name}");

    // Afterwards the filter goes on as if the update had never been made.
    let mut skipped = skipped.with_adapter(());
    let mut f = f.with_adapter(());
    for g in [&mut f, &mut skipped] {
        g.predict(&process(), 1.0).unwrap();
        g.update(&position(0.75), &Vector1::new(8.5)).unwrap();
    }
    assert_same_estimate(name, &f, &skipped);
}

#[test]
fn rejection_keeps_the_prior() {
    each_form!(rejected);
}

// (f) ------------------------------------------------------------------------

/// After each update, the probe's posterior view must match the filter:
/// post-fit residual `z' − H x⁺` (with `z' = ẑ + ν_used`) and `H P⁺ Hᵀ`.
fn posterior_view<F: LinForm, const SPLIT: bool>(
    name: &str,
    f: Filter<f64, 2, F>,
    actions: &[Action],
) {
    let probe = Probe::<SPLIT>::new(1, &log()).with_actions(actions);
    let mut f = f.with_adapter(probe);
    let sensor = two_sensors();
    let h = sensor.matrix;
    let zs = [(6.0, 7.5), (8.5, 11.0), (9.0, 13.0), (13.0, 16.0)];
    for (k, (z0, z1)) in zs.into_iter().enumerate() {
        f.predict(&process(), 1.0).unwrap();
        let z_hat = h * f.state();
        let detail = f.update_detailed(&sensor, &Vector2::new(z0, z1)).unwrap();
        let seen = &f.adapter().posteriors[k];
        let used = z_hat + detail.report.innovation_used;
        let residual = used - h * f.state();
        let projected = h * f.covariance() * h.transpose();
        assert_slice(&seen.post_fit_residual, residual.as_slice(), TOL, name);
        assert_slice(&seen.posterior_covariance, projected.as_slice(), TOL, name);
        assert_slice(
            &seen.innovation,
            detail.report.innovation_used.as_slice(),
            TOL,
            name,
        );
        assert_slice(&seen.noise, detail.noise.as_slice(), TOL, name);
        let predicted = detail.innovation_covariance - detail.noise;
        assert_slice(&seen.predicted, predicted.as_slice(), TOL, name);
        // The two together (the residual through `Gᵀ L⁻¹ ν`) equal them
        // apart, and the whitened innovation gives the adapted NIS.
        assert_slice(&seen.together.0, residual.as_slice(), TOL, name);
        assert_slice(&seen.together.1, projected.as_slice(), TOL, name);
        assert_scalar(seen.whitened_norm2, detail.report.adapted_nis, TOL, name);
    }
}

fn posterior_views<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    posterior_view::<F, false>(name, f.clone(), &[]);
    let busy = [
        Action::ScaleNoise(2.0),
        Action::ScaleInnovation(0.5),
        Action::Fade(1.5),
    ];
    posterior_view::<F, true>(name, f.clone(), &busy);
    posterior_view::<F, false>(name, f, &busy);
}

#[test]
fn posterior_view_matches_the_update() {
    each_form!(posterior_views);
}

// (h) ------------------------------------------------------------------------

fn other_adapter<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    use Event::{Gain, Predict, Update};
    let log = log();
    let own = Probe::<false>::new(1, &log).with_actions(&[Action::ScaleNoise(100.0)]);
    let mut f = f.with_adapter(own);
    let mut reference = f.clone().with_adapter(());
    let z = Vector1::new(6.0);

    f.predict(&process(), 1.0).unwrap();
    reference.predict(&process(), 1.0).unwrap();
    let mut other = Probe::<false>::new(2, &log).with_actions(&[Action::ScaleNoise(4.0)]);
    let report = f.update_with(&position(0.75), &z, &mut other).unwrap();
    reference.update(&position(3.0), &z).unwrap();
    assert_same_estimate(name, &f, &reference);
    assert_eq!(*log.borrow(), [Predict(1), Gain(2), Update(2)], "{name}");
    assert_eq!(report.adapters.id, 2, "{name}");
    assert_eq!(other.posteriors.len(), 1, "{name}");
    assert!(f.adapter().seen_noise.is_empty(), "{name}");

    // `&mut ()`: a plain update.
    let report = f.update_with(&position(0.75), &z, &mut ()).unwrap();
    reference.update(&position(0.75), &z).unwrap();
    assert_same_estimate(name, &f, &reference);
    assert_eq!(report.adapters, (), "{name}");
    assert_eq!(log.borrow().len(), 3, "{name}");

    // And the filter's own adapter is still the one `update` runs.
    f.update(&position(0.75), &z).unwrap();
    reference.update(&position(75.0), &z).unwrap();
    assert_same_estimate(name, &f, &reference);
    assert_eq!(log.borrow()[3], Gain(1), "{name}");
}

#[test]
fn update_with_runs_the_given_adapter() {
    each_form!(other_adapter);
}

// (i) ------------------------------------------------------------------------

/// A predict fade of 2, then at the gain a fade of 1.5, `R` doubled and the
/// innovation halved. By hand, with z = 6 (ν = 3), H Φ P Φᵀ Hᵀ = 8,
/// H Q Hᵀ = ¼, R = ¾:
///
/// - nominal C (models and the predict fade) = 2·8 + ¼ + ¾ = 17, NIS = 9/17;
/// - the gain step sees the split (16, ¼); after the fade
///   C = 3·8 + ¼ + ¾ = 25, after doubling R C = 24.25 + 1.5 = 25.75,
///   unchanged by the innovation scaling;
/// - used: fade 3, R = 1.5, ν = 1.5, C = 25.75, NIS = 2.25/25.75.
///
/// Without the split the gain step can only fade all of H P⁻ Hᵀ:
/// 1.5·16.25 + ¾ = 25.125, then 24.375 + 1.5 = 25.875. The covariance and
/// unscented forms still fade only the propagated part; the square-root
/// form, whose factor already holds Q, fades all of it (C = 25.875).
fn report_fields<F: LinForm, const SPLIT: bool>(
    name: &str,
    f: Filter<f64, 2, F>,
    square_root: bool,
) {
    let log = log();
    let fader = Probe::<SPLIT>::new(1, &log).with_predict_fade(2.0);
    let busy = Probe::<false>::new(2, &log).with_actions(&[
        Action::Fade(1.5),
        Action::ScaleNoise(2.0),
        Action::ScaleInnovation(0.5),
    ]);
    let mut f = f.with_adapter((fader, busy));
    let name = &format!("{name} split={SPLIT}");
    f.predict(&process(), 1.0).unwrap();
    let detail = f
        .update_detailed(&position(0.75), &Vector1::new(6.0))
        .unwrap();

    let seen = &f.adapter().1;
    let (c, steps) = match (SPLIT, square_root) {
        (true, _) => (25.75, [17.0, 25.0, 25.75, 25.75]),
        (false, false) => (25.75, [17.0, 25.125, 25.875, 25.875]),
        (false, true) => (25.875, [17.0, 25.125, 25.875, 25.875]),
    };
    assert_slice(&seen.seen_covariances[0].concat(), &steps, TOL, name);
    let nis: Vec<f64> = seen.seen_nis[0].iter().map(|v| v.unwrap()).collect();
    let want_nis = [
        9.0 / steps[0],
        9.0 / steps[1],
        9.0 / steps[2],
        2.25 / steps[3],
    ];
    assert_slice(&nis, &want_nis, TOL, name);
    match &seen.seen_split[0] {
        Some((propagated, noise)) => {
            assert!(SPLIT, "{name}: split given without asking");
            assert_slice(propagated, &[16.0], TOL, name);
            assert_slice(noise, &[0.25], TOL, name);
        }
        None => assert!(!SPLIT, "{name}: split missing"),
    }

    assert_scalar(detail.report.innovation[0], 3.0, TOL, name);
    assert_scalar(detail.report.innovation_used[0], 1.5, TOL, name);
    assert_scalar(detail.nominal_innovation_covariance[0], 17.0, TOL, name);
    assert_scalar(detail.report.nis, 9.0 / 17.0, TOL, name);
    assert_scalar(detail.noise[0], 1.5, TOL, name);
    assert_scalar(detail.innovation_covariance[0], c, TOL, name);
    assert_scalar(detail.report.adapted_nis, 2.25 / c, TOL, name);
    assert_scalar(detail.report.fade, 3.0, TOL, name);
    assert!(
        !detail.report.rejected && !detail.report.sequential,
        "{name}"
    );
    assert_eq!(detail.report.adapters.0.id, 1, "{name}");
    assert_eq!(detail.report.adapters.1.id, 2, "{name}");
}

fn report_fields_both<F: LinForm>(name: &str, f: Filter<f64, 2, F>) {
    let square_root = name.starts_with("sr");
    report_fields::<F, true>(name, f.clone(), square_root);
    report_fields::<F, false>(name, f, square_root);
}

#[test]
fn report_reflects_the_adapters() {
    each_form!(report_fields_both);
}

// GainStep ---------------------------------------------------------------------

/// `GainStep` keeps `C`, its factor and the NIS consistent after every
/// change, with the split (only the propagated part fades) and without.
#[test]
fn gain_step_keeps_the_innovation_covariance_consistent() {
    // ν = (1, 2), H P⁻ Hᵀ = [2 1; 1 2] = propagated [1 1; 1 1] + noise I,
    // R = I: C = [3 1; 1 3], C⁻¹ = [3 −1; −1 3]/8, NIS = (1·1 + 2·5)/8.
    let nu = Vector2::new(1.0, 2.0);
    let predicted = Matrix2::new(2.0, 1.0, 1.0, 2.0);
    let split = (Matrix2::new(1.0, 1.0, 1.0, 1.0), Matrix2::identity());
    let r = Matrix2::identity();
    let mut step = GainStep::new(nu, predicted, Some(split), r).unwrap();
    #[track_caller]
    fn consistent(step: &GainStep<f64, 2>, c: Matrix2<f64>, nis: f64) {
        assert_close(step.innovation_covariance(), &c, TOL, "C");
        let l = step.innovation_factor().unwrap();
        assert_close(&(l * l.transpose()), &c, TOL, "factor");
        assert_scalar(step.mahalanobis().unwrap(), nis, TOL, "NIS");
    }
    consistent(&step, Matrix2::new(3.0, 1.0, 1.0, 3.0), 11.0 / 8.0);

    // Fade 3: [2 1; 1 2] + 2·[1 1; 1 1] = [4 3; 3 4]; C = [5 3; 3 5],
    // C⁻¹ = [5 −3; −3 5]/16, NIS = (1·(−1) + 2·7)/16.
    step.fade(3.0);
    consistent(&step, Matrix2::new(5.0, 3.0, 3.0, 5.0), 13.0 / 16.0);
    assert_close(
        &step.predicted_covariance(),
        &Matrix2::new(4.0, 3.0, 3.0, 4.0),
        TOL,
        "H P⁻ Hᵀ",
    );

    // R = 2I (upper triangle ignored): C = [6 3; 3 6], C⁻¹ = [6 −3; −3 6]/27,
    // NIS = (1·0 + 2·9)/27 = 2/3.
    step.set_noise(Matrix2::new(2.0, 99.0, 0.0, 2.0));
    assert!(step.noise_changed());
    assert_close(step.noise(), &(Matrix2::identity() * 2.0), 0.0, "R");
    assert_close(step.nominal_noise(), &r, 0.0, "nominal R");
    consistent(&step, Matrix2::new(6.0, 3.0, 3.0, 6.0), 2.0 / 3.0);

    // ν doubled: NIS × 4, C unchanged.
    step.scale_innovation(2.0);
    consistent(&step, Matrix2::new(6.0, 3.0, 3.0, 6.0), 8.0 / 3.0);
    assert_close(step.raw_innovation(), &nu, 0.0, "raw ν");
    assert_eq!(step.innovation_scale(), 2.0);

    // Total fade 1.5: [2 1; 1 2] + 0.5·[1 1; 1 1]; C = [4.5 1.5; 1.5 4.5],
    // det 18, NIS = (2·3 + 4·15)/18 = 11/3. Invalid fades are ignored.
    step.fade(0.5);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        step.fade(bad);
    }
    assert_eq!(step.fade_factor(), 1.5);
    consistent(&step, Matrix2::new(4.5, 1.5, 1.5, 4.5), 11.0 / 3.0);

    // An indefinite C has no factor and no NIS.
    step.set_noise(Matrix2::identity() * -10.0);
    assert!(step.innovation_factor().is_none() && step.mahalanobis().is_none());

    // Without the split the view fades all of H P⁻ Hᵀ: 3·[2 1; 1 2] + I.
    let mut step = GainStep::new(nu, predicted, None, r).unwrap();
    step.fade(3.0);
    consistent(
        &step,
        Matrix2::new(7.0, 3.0, 3.0, 7.0),
        (7.0 - 12.0 + 28.0) / 40.0,
    );
    assert!(GainStep::new(nu, predicted, None, -r * 4.0).is_none());
}

/// The tuple's `NEEDS_SPLIT` is the `or` of its members', and
/// `IS_IDENTITY` holds only for tuples of `()`.
#[test]
fn tuple_flags() {
    fn split<A: PriorAdapter<f64>>() -> bool {
        A::NEEDS_SPLIT
    }
    fn identity<A: NoiseAdapter<f64, 1>>() -> bool {
        A::IS_IDENTITY
    }
    assert!(!split::<(Probe<false>, Probe<false>)>());
    assert!(split::<(Probe<false>, Probe<true>, Probe<false>)>());
    assert!(identity::<((), (), ())>());
    assert!(!identity::<((), Probe<false>)>());
}
