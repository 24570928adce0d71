//! Strong-tracking fading (paper 004) on the planar constant-velocity target
//! of `support::cv` (`R = I`, innovation covariance `C = c I`), every form,
//! `f64`.
//!
//! `λ > 1` exactly when `tr V_k > tr C + (β − 1) tr R`. On a consistent
//! model `νᵀν / c ~ χ²(2)`, so `tr V_k / c` is the exponentially weighted
//! mean (`ρ`) of `χ²(2)` draws, whose tail the test estimates by Monte Carlo
//! independently of the filter. What is asserted, and why:
//! - **How often it would fade on a consistent model.** With `β = 1` and
//!   `λ_max = 1` (evaluated, never applied), the fraction of 5000 epochs
//!   with `tr N > tr M` matches `P(V > 2)` of the weighted mean within
//!   0.05: about 40 % — with `β = 1` strong tracking fades a consistent
//!   filter all the time, `β` is the margin.
//! - **λ = 1 on a consistent model.** With `β = 10` the Monte-Carlo
//!   probability `P(V > 2 + 2 (β − 1) / c)` gives fewer than 0.1 expected
//!   fades in 5000 epochs, and no epoch of the run fades. (The newest
//!   innovation carries weight `1 / (1 + ρ) ≈ 0.51`, so the test is close
//!   to a one-epoch test, hence the large `β`.)
//! - **Recovery after a step change.** The same adapter, after the true
//!   position jumps by (30, −30) at epoch 500 (`q = 10⁻⁴`): `λ > 1` at the
//!   jump, and within 20 epochs the NIS is back inside its 95 % bounds (see
//!   `support::recovery`).

use crate::support;

use kestrel_adaptive::StrongTracking;
use kestrel_core::nalgebra::Matrix2;
use rand::RngExt;
use support::{cv, CvForm, Make};

const STEPS: usize = 5000;
const JUMP: usize = 500;
const RHO: f64 = 0.95;
const BETA: f64 = 10.0;

/// `P(V > t)` for the stationary weighted mean `V = (ρ V + X) / (1 + ρ)` of
/// `X ~ χ²(2)` (exponential with mean 2), from `draws` Monte-Carlo steps.
fn weighted_mean_tail(t: f64, draws: usize) -> f64 {
    let mut rng = support::rng(99);
    let mut v: f64 = 2.0;
    let mut above = 0;
    for k in 0..draws + 100 {
        let u: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
        v = (RHO * v - 2.0 * u.ln()) / (1.0 + RHO);
        if k >= 100 && v > t {
            above += 1;
        }
    }
    above as f64 / draws as f64
}

fn consistent_stream() -> cv::Stream {
    cv::stream(&cv::Spec::new(31, STEPS, Matrix2::identity()))
}

/// Runs `adapter` over the consistent stream; returns the epochs with
/// `tr N > tr M`, those with `λ > 1`, and the final `c`.
fn consistent_run<F: CvForm<f64>>(
    name: &str,
    make: Make<F>,
    adapter: StrongTracking<f64>,
) -> (usize, usize, f64) {
    let mut f = make(cv::x0(), cv::p0()).with_adapter(adapter);
    let (mut would, mut faded, mut c) = (0, 0, 0.0);
    support::run_detailed(
        &mut f,
        &consistent_stream(),
        &cv::sensor(&Matrix2::identity()),
        |_, d, _| {
            let a = d.report.adapters;
            would += usize::from(a.n_trace > a.m_trace);
            faded += usize::from(a.fade > 1.0);
            c = d.nominal_innovation_covariance[(0, 0)];
        },
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    (would, faded, c)
}

fn fade_rate_with_unit_softening<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let monitor = StrongTracking::new(RHO, 1.0)
        .unwrap()
        .with_max_fade(1.0)
        .unwrap();
    let (would, faded, _) = consistent_run(name, make, monitor);
    assert_eq!(faded, 0, "{name}: λ_max = 1 never fades");
    let got = would as f64 / STEPS as f64;
    let want = weighted_mean_tail(2.0, 1_000_000);
    assert!(
        (got - want).abs() < 0.05,
        "{name}: tr N > tr M in {got} of the epochs, P(V > 2) = {want}"
    );
}

#[test]
fn with_unit_softening_a_consistent_model_fades_often() {
    each_form_f64!(fade_rate_with_unit_softening);
}

fn no_fade<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let (would, faded, c) = consistent_run(name, make, StrongTracking::new(RHO, BETA).unwrap());
    let threshold = 2.0 + 2.0 * (BETA - 1.0) / c;
    let expected = weighted_mean_tail(threshold, 2_000_000) * STEPS as f64;
    assert!(
        expected < 0.1,
        "{name}: {expected} fades expected (c = {c})"
    );
    assert_eq!((would, faded), (0, 0), "{name}");
}

#[test]
fn no_fade_on_a_consistent_model() {
    each_form_f64!(no_fade);
}

fn recovers<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let mut f = make(cv::x0(), cv::p0()).with_adapter(StrongTracking::new(RHO, BETA).unwrap());
    support::assert_fades_and_recovers(name, &mut f, JUMP, |a| a.fade);
}

#[test]
fn fades_and_recovers_after_a_step_change() {
    each_form_f64!(recovers);
}
