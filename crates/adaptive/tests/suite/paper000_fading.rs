//! Divergence-tested fading (paper 000, eq. 10–12) on the planar
//! constant-velocity target of `support::cv` (`R = I`, so the innovation
//! covariance is `c I` with the same `c` on both axes), every form, `f64`.
//!
//! What is asserted, and why:
//! - **How often the test fails on a consistent model.** With `C = c I`,
//!   `νᵀν / c ~ χ²(2)`, so the test `νᵀν ≤ γ tr C = 2 γ c` fails with
//!   probability `P(χ²(2) > 2γ) = e^{−γ}`: 37 % of the epochs at the paper's
//!   strictest `γ = 1`. A run with `λ_max = 1` (the test is evaluated but
//!   never fades, so the filter stays consistent) must fail it in
//!   `e^{−γ} ± 0.03` of 5000 epochs for `γ = 1` and `γ = 2` (±4 standard
//!   deviations). So "λ = 1 on a consistent model" is a matter of `γ`.
//! - **λ = 1 on a consistent model.** With `γ = χ²_{1−α}(2)`, `α = 10⁻⁴`
//!   (`with_false_alarm`; here `e^{−γ} = 10⁻⁸` per epoch), no epoch of a
//!   5000-epoch consistent run fades.
//! - **Recovery after a step change.** The same adapter, after the true
//!   position jumps by (30, −30) (30 σ per axis) at epoch 500 with
//!   `q = 10⁻⁴`: `λ > 1` at the jump, and within 20 epochs the NIS is back
//!   inside `χ²_0.95(2)` and the mean NIS of epochs 511–520 inside the 95 %
//!   bound of such a mean. The plain filter, for contrast, is not back
//!   inside the window bound.

use crate::support;

use kestrel_adaptive::DivergenceFading;
use kestrel_core::nalgebra::Matrix2;
use support::{cv, CvForm, Make};

const STEPS: usize = 5000;
const JUMP: usize = 500;

/// The adapter of the last two claims.
fn adapter() -> DivergenceFading<f64> {
    DivergenceFading::with_false_alarm(1e-4, 2, 100.0).unwrap()
}

fn consistent_stream() -> cv::Stream {
    cv::stream(&cv::Spec::new(21, STEPS, Matrix2::identity()))
}

fn failure_rate<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let stream = consistent_stream();
    for gamma in [1.0_f64, 2.0] {
        let monitor = DivergenceFading::new(gamma, 1.0).unwrap();
        let mut f = make(cv::x0(), cv::p0()).with_adapter(monitor);
        let mut failed = 0;
        support::run_detailed(
            &mut f,
            &stream,
            &cv::sensor(&Matrix2::identity()),
            |k, d, _| {
                assert_eq!(d.report.adapters.fade, 1.0, "{name}: λ_max = 1 never fades");
                // The premise: C = c I (to rounding).
                let c = d.innovation_covariance;
                let isotropic =
                    (c[(0, 0)] - c[(1, 1)]).abs() <= 1e-9 * c[(0, 0)] && c[(0, 1)].abs() <= 1e-9;
                assert!(isotropic, "{name} epoch {k}: C = {c}");
                failed += usize::from(d.report.adapters.diverged);
            },
        )
        .unwrap();
        let got = failed as f64 / STEPS as f64;
        let want = (-gamma).exp();
        assert!(
            (got - want).abs() < 0.03,
            "{name}, γ = {gamma}: fails in {got} of the epochs, e^−γ = {want}"
        );
    }
}

#[test]
fn the_test_fails_on_a_consistent_model_at_the_predicted_rate() {
    each_form_f64!(failure_rate);
}

fn no_fade_when_consistent<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let mut f = make(cv::x0(), cv::p0()).with_adapter(adapter());
    let stream = consistent_stream();
    support::run(
        &mut f,
        &stream,
        &cv::sensor(&Matrix2::identity()),
        |k, r, _| {
            assert!(!r.adapters.diverged, "{name}: epoch {k} {:?}", r.adapters);
            assert_eq!(r.adapters.fade, 1.0, "{name}: epoch {k}");
            assert_eq!(r.fade, 1.0, "{name}: epoch {k}");
        },
    )
    .unwrap();
}

#[test]
fn no_fade_on_a_consistent_model() {
    let gamma = adapter().reserve();
    assert!((gamma + 2.0 * 1e-4_f64.ln()).abs() < 1e-6, "γ = {gamma}");
    each_form_f64!(no_fade_when_consistent);
}

fn recovers<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let mut f = make(cv::x0(), cv::p0()).with_adapter(adapter());
    support::assert_fades_and_recovers(name, &mut f, JUMP, |a| a.fade);

    let mut plain_nis = Vec::new();
    let mut plain = make(cv::x0(), cv::p0());
    let sensor = cv::sensor(&Matrix2::identity());
    support::run(
        &mut plain,
        &support::jump_stream(JUMP),
        &sensor,
        |_, r, _| plain_nis.push(r.nis),
    )
    .unwrap();
    let plain = support::recovery(&plain_nis, JUMP, 2);
    assert!(
        plain.window_mean > 10.0 * plain.window_bound,
        "{name}: the plain filter {plain:?}"
    );
}

#[test]
fn fades_and_recovers_after_a_step_change() {
    each_form_f64!(recovers);
}
