//! A scenario after paper 000's experiment, on the planar constant-velocity
//! target of `support::cv` (the filter assumes `R = I`): the measurement
//! noise standard deviation steps from 1 to 5 during epochs 500–999 and to
//! 10 during 1500–1999 (the paper: 0.3 → 1.5 and → 3 m/s), and every third
//! epoch of 2500–2599 carries an outlier of (+50, −50) (the paper's "patchy
//! outliers"). Position RMS over epochs 100–2999, every form, `f64`, for
//! the plain filter, the "Sage-Husa + fading" baseline and the improved
//! adaptive filter, both with [`ImprovedAdaptive::as_published`]'s parameters.
//!
//! Asserted, as in the paper's table 1: the improved filter is the most
//! accurate of the three overall (RMS below 0.8 × the plain filter's and
//! 0.5 × the baseline's); through the outliers its RMS is below 0.2 × the
//! plain filter's, while the baseline does worse than the plain filter
//! there (the paper: its velocity "diverges seriously").
//!
//! Not asserted, because it does not hold here: during the noise-level
//! steps the improved filter is no more accurate than the plain one (with
//! `γ = 3` the larger innovations still trigger fades, and faded epochs do
//! not update `R̂`).

use crate::support;

use kestrel_adaptive::{ImprovedAdaptive, SageHusaFading};
use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::nalgebra::{Matrix2, Vector2, Vector4};
use kestrel_core::Filter;
use support::{cv, normal, rng, CvForm, Make};

const STEPS: usize = 3000;

fn stream() -> cv::Stream {
    let mut rng = rng(77);
    let q = 0.01;
    let lq = cv::q(q).cholesky().expect("SPD").l();
    let mut x = Vector4::zeros();
    let mut out = cv::Stream {
        q,
        truth: Vec::with_capacity(STEPS),
        z: Vec::with_capacity(STEPS),
        clean: Vec::with_capacity(STEPS),
        outlier: Vec::with_capacity(STEPS),
    };
    for k in 0..STEPS {
        x = cv::phi() * x + lq * normal::<4>(&mut rng);
        let sigma = match k {
            500..=999 => 5.0,
            1500..=1999 => 10.0,
            _ => 1.0,
        };
        let clean = cv::h() * x + normal::<2>(&mut rng) * sigma;
        let outlier = (2500..2600).contains(&k) && k % 3 == 0;
        let z = if outlier {
            clean + Vector2::new(50.0, -50.0)
        } else {
            clean
        };
        out.truth.push(x);
        out.z.push(z);
        out.clean.push(clean);
        out.outlier.push(outlier);
    }
    out
}

/// Position errors of `filter` over the scenario.
fn errors<F: CvForm<f64>, A: NoiseAdapter<f64, 2>>(mut filter: Filter<f64, 4, F, A>) -> Vec<f64> {
    support::run(
        &mut filter,
        &stream(),
        &cv::sensor(&Matrix2::identity()),
        |_, _, _| {},
    )
    .expect("every update succeeds")
}

fn ordering<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let new = || make(cv::x0(), cv::p0());
    let plain = errors(new());
    let baseline = errors(new().with_adapter(SageHusaFading::as_published().unwrap()));
    let improved = errors(new().with_adapter(ImprovedAdaptive::as_published().unwrap()));
    let overall = |e: &[f64]| support::rms(&e[100..]);
    let outliers = |e: &[f64]| support::rms(&e[2500..2700]);
    let (p, b, i) = (overall(&plain), overall(&baseline), overall(&improved));
    assert!(i < 0.8 * p, "{name}: improved {i}, plain {p}");
    assert!(i < 0.5 * b, "{name}: improved {i}, baseline {b}");
    let (p, b, i) = (outliers(&plain), outliers(&baseline), outliers(&improved));
    assert!(i < 0.2 * p, "{name}: outliers: improved {i}, plain {p}");
    assert!(b > p, "{name}: outliers: baseline {b}, plain {p}");
}

#[test]
fn improved_adaptive_beats_plain_and_baseline() {
    each_form_f64!(ordering);
}
