//! Sage-Husa estimation of `R` (paper 000, eq. 9) on the planar
//! constant-velocity target of `support::cv`:
//!
//! - the filter assumes `R_a` while the measurements have `R = 4 R_a`; the
//!   mean of `R̂` over steps 1000–2000 must be within 10 % of `4 R_a`
//!   (Frobenius norm, and each diagonal element), for every form and for
//!   both ends of the paper's range of `b`. The plain filter's NIS, for
//!   contrast, averages near 4 × its nominal mean: the mismatch is real.
//! - `R̂` is exactly symmetric and positive definite (an independent
//!   Cholesky factorisation succeeds) after every update, for random seeds,
//!   random `b ∈ [0.01, 0.999]`, random true and assumed `R`, with and
//!   without a floor.
//! - The gain takes `R̂` itself, bit for bit, with the Cholesky factor that
//!   checked it.

use crate::support;

use kestrel_adaptive::SageHusa;
use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector, Vector2};
use kestrel_core::{Filter, Real};
use proptest::prelude::*;
use support::{cv, CvForm};

/// The assumed `R`: correlated, unequal variances.
fn r_assumed() -> Matrix2<f64> {
    Matrix2::new(1.0, 0.3, 0.3, 0.5)
}

fn mean_estimate<T: Real, F: CvForm<T>>(
    name: &str,
    make: fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>,
    b: f64,
) {
    let truth = r_assumed() * 4.0;
    let stream = cv::stream(&cv::Spec::new(11, 2000, truth));
    let mut f = make(cv::x0(), cv::p0()).with_adapter(SageHusa::new(support::to(b)).unwrap());
    let mut sum = Matrix2::zeros();
    let mut count = 0;
    support::run(
        &mut f,
        &stream,
        &cv::sensor(&r_assumed()),
        |k, report, f| {
            assert!(report.adapters.estimated, "{name}: step {k}");
            if k >= 1000 {
                sum += support::mat64(f.adapter().estimate());
                count += 1;
            }
        },
    )
    .unwrap();
    let mean = sum / count as f64;
    let error = (mean - truth).norm() / truth.norm();
    assert!(
        error < 0.1,
        "{name}, b = {b}: mean R̂ {mean} vs {truth}: {error:.3}"
    );
    for i in 0..2 {
        let e = (mean[(i, i)] - truth[(i, i)]).abs() / truth[(i, i)];
        assert!(e < 0.1, "{name}, b = {b}: R̂[{i}{i}] off by {e:.3}");
    }
}

fn converges<T: Real, F: CvForm<T>>(
    name: &str,
    make: fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>,
) {
    mean_estimate(name, make, 0.95);
    mean_estimate(name, make, 0.99);
}

#[test]
fn estimate_converges_to_four_times_the_assumed_noise() {
    each_form_f64!(converges);
}

#[test]
fn the_mismatch_is_visible_to_the_plain_filter() {
    // Control: without the estimator the NIS averages ≈ 4 × its nominal
    // mean (m = 2) once the filter has converged; with it, the NIS against
    // the covariance the gain used (`adapted_nis`, with `R̂`) averages ≈ 2.
    let stream = cv::stream(&cv::Spec::new(11, 2000, r_assumed() * 4.0));
    let sensor = cv::sensor(&r_assumed());
    let mut nis = Vec::new();
    let mut f = support::ekf(cv::x0(), cv::p0());
    support::run(&mut f, &stream, &sensor, |k, r, _| {
        if k >= 1000 {
            nis.push(r.nis)
        }
    })
    .unwrap();
    let plain = nis.iter().sum::<f64>() / nis.len() as f64;
    nis.clear();
    let mut f = support::ekf(cv::x0(), cv::p0()).with_adapter(SageHusa::new(0.99).unwrap());
    support::run(&mut f, &stream, &sensor, |k, r, _| {
        if k >= 1000 {
            nis.push(r.adapted_nis)
        }
    })
    .unwrap();
    let adapted = nis.iter().sum::<f64>() / nis.len() as f64;
    assert!(plain > 6.0, "plain mean NIS {plain}");
    assert!((adapted - 2.0).abs() < 0.3, "adapted mean NIS {adapted}");
}

fn spd2(a: f64, b: f64, rho: f64) -> Matrix2<f64> {
    let c = rho * (a * b).sqrt();
    Matrix2::new(a, c, c, b)
}

fn psd_every_step<T: Real, F: CvForm<T>>(
    name: &str,
    make: fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>,
    (seed, b, truth, assumed, floor): (u64, f64, Matrix2<f64>, Matrix2<f64>, Option<f64>),
) {
    let stream = cv::stream(&cv::Spec::new(seed, 300, truth));
    let mut sh = SageHusa::new(support::to::<T>(b)).unwrap();
    if let Some(floor) = floor {
        sh = sh
            .with_floor(Vector2::repeat(floor).map(support::to))
            .unwrap();
    }
    let mut f = make(cv::x0(), cv::p0()).with_adapter(sh);
    // The estimate the next update's gain must use (the first takes the
    // model's `R`).
    let mut previous = support::mat64(&assumed.map(support::to::<T>));
    support::run_detailed(&mut f, &stream, &cv::sensor(&assumed), |k, detail, f| {
        // `R̂` reaches the gain by the factor of its check: `L Lᵀ`, `R̂` to
        // rounding.
        let used = support::mat64(&detail.noise);
        let tolerance = 64.0 * support::from(T::default_epsilon()) * previous.norm();
        assert!(
            (used - previous).norm() <= tolerance,
            "{name} step {k}: R used {used}, R̂ {previous}"
        );
        previous = support::mat64(f.adapter().estimate());
        let r = f.adapter().estimate();
        assert!(support::symmetric_pd(r), "{name} step {k}: R̂ = {r}");
        if let Some(floor) = floor {
            // The floor as rounded to T.
            let floor = support::from(support::to::<T>(floor));
            let d = support::mat64(r).diagonal();
            assert!(d.min() >= floor, "{name} step {k}: R̂ = {r}");
        }
        let p = f.covariance();
        assert!(support::symmetric_pd(&p), "{name} step {k}: P = {p}");
    })
    .unwrap_or_else(|e| panic!("{name}: {e}"));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn estimate_stays_symmetric_positive_definite(
        seed in any::<u64>(),
        b in 0.01..0.999f64,
        truth in (0.01..100.0f64, 0.01..100.0f64, -0.9..0.9f64),
        assumed in (0.01..100.0f64, 0.01..100.0f64, -0.9..0.9f64),
        floor in proptest::option::of(0.0..1.0f64),
    ) {
        let truth = spd2(truth.0, truth.1, truth.2);
        let assumed = spd2(assumed.0, assumed.1, assumed.2);
        each_form!(psd_every_step, (seed, b, truth, assumed, floor));
    }
}

/// Records the `R` and its factor that reach the gain.
#[derive(Debug, Default)]
struct NoiseProbe {
    noise: Option<Matrix2<f64>>,
    factor: Option<Matrix2<f64>>,
}

impl kestrel_core::adapter::PriorAdapter<f64> for NoiseProbe {}

impl kestrel_core::adapter::NoiseAdapter<f64, 2> for NoiseProbe {
    type Report = ();
    fn before_gain(&mut self, step: &mut kestrel_core::adapter::GainStep<f64, 2>, _: &mut ()) {
        self.noise = Some(*step.noise());
        self.factor = step.noise_factor().copied();
    }
}

/// After the first estimate the gain takes `R̂` itself (not `L Lᵀ`, which
/// equals it only to rounding) with the Cholesky factor that checked it.
#[test]
fn the_gain_takes_the_estimate_itself_with_its_factor() {
    use kestrel_core::linalg::cholesky;
    use kestrel_core::Ekf;
    use kestrel_models::{LinearMeasurement, LinearProcess};

    let process = LinearProcess::new(Matrix2::new(1.0, 0.1, 0.0, 1.0), Matrix2::identity() * 0.01);
    let sensor = LinearMeasurement::new(Matrix2::new(1.0, 0.0, 0.3, 1.0), r_assumed());
    let mut f = Ekf::new(Vector2::zeros(), Matrix2::identity())
        .unwrap()
        .with_adapter((SageHusa::new(0.9).unwrap(), NoiseProbe::default()));
    for k in 0..6 {
        let before = *f.adapter().0.estimate();
        f.predict(&process, 1.0).unwrap();
        let z = Vector2::new(0.7 * (k as f64).sin() + 0.3, 0.2 - 0.5 * (k as f64).cos());
        f.update(&sensor, &z).unwrap();
        let probe = &f.adapter().1;
        if k == 0 {
            // R̂₀ is the model's R, taken as it is, unfactored.
            assert_eq!(probe.noise, Some(r_assumed()));
            assert_eq!(probe.factor, None);
        } else {
            let noise = probe.noise.unwrap();
            assert_eq!(noise, before, "update {k}");
            assert_ne!(noise, r_assumed(), "update {k}: the estimate moved");
            assert_eq!(probe.factor, Some(cholesky(&before).unwrap()), "update {k}");
        }
    }
}

/// `b = 1` (documented as valid) forgets nothing: the weights are the
/// formula's limit 1/(k + 1), and R̂ is the plain mean of R̂₀ and the
/// samples (the formula itself is 0/0 there).
#[test]
fn forgetting_one_is_the_plain_mean() {
    use kestrel_core::nalgebra::{Matrix1, Vector1};
    use kestrel_models::{LinearMeasurement, LinearProcess};
    let process = LinearProcess::new(Matrix1::new(1.0), Matrix1::new(0.0));
    let sensor = LinearMeasurement::new(Matrix1::new(1.0), Matrix1::new(1.0));
    let mut kf = kestrel_core::Ekf::new(Vector1::new(0.0), Matrix1::new(1.0))
        .unwrap()
        .with_adapter(SageHusa::new(1.0).unwrap());
    let mut samples = vec![1.0];
    for (k, z) in [2.0, -1.0, 0.5, 3.0].into_iter().enumerate() {
        kf.predict(&process, 1.0).unwrap();
        let p_prior = kf.covariance()[(0, 0)];
        // R̂₀ is the R of the first update.
        let r = if k == 0 {
            1.0
        } else {
            kf.adapter().estimate()[(0, 0)]
        };
        let x_prior = kf.state()[0];
        let report = kf.update(&sensor, &Vector1::new(z)).unwrap();
        let w = report.adapters.weight;
        assert!((w - 1.0 / (k as f64 + 2.0)).abs() < 1e-15, "k {k}: {w}");
        // The sample: post-fit residual squared plus H P Hᵀ.
        let gain = p_prior / (p_prior + r);
        let e = (1.0 - gain) * (z - x_prior);
        samples.push(e * e + (1.0 - gain) * p_prior);
        let mean = samples.iter().sum::<f64>() / samples.len() as f64;
        let estimate = kf.adapter().estimate()[(0, 0)];
        assert!(
            (estimate - mean).abs() < 1e-12,
            "k {k}: {estimate} vs {mean}"
        );
    }
}
