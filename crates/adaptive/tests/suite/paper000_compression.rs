//! χ² outlier compression (paper 000, eq. 13–14) on the planar
//! constant-velocity target of `support::cv`, every form, `f64`:
//!
//! - on an outlier-free, consistent stream, every epoch with `τ ≤ c` has a
//!   factor of exactly 1 and an untouched innovation; the others (a fraction
//!   `α` of a consistent filter's epochs, asserted within ±0.015 of 0.05
//!   over 5000 epochs, 5 standard deviations) are compressed onto the
//!   threshold, `ν'ᵀ C⁻¹ ν' = c`;
//! - on the stream of `support::outlier_stream` (5 % outliers of ±20 σ),
//!   the position RMS with compression is within 50 % of the plain filter's
//!   on the same truth without outliers, while the plain filter's RMS on
//!   the outliers is at least 3 times that.

use crate::support;

use kestrel_adaptive::OutlierCompression;
use kestrel_core::nalgebra::Matrix2;
use support::{cv, CvForm, Make};

const ALPHA: f64 = 0.05;

fn exact_one_without_outliers<F: CvForm<f64>>(name: &str, make: Make<F>) {
    const STEPS: usize = 5000;
    let stream = cv::stream(&cv::Spec::new(41, STEPS, Matrix2::identity()));
    let compression = OutlierCompression::<f64, 2>::new(ALPHA).unwrap();
    let c = compression.threshold();
    let mut f = make(cv::x0(), cv::p0()).with_adapter(compression);
    let mut compressed = 0;
    support::run(
        &mut f,
        &stream,
        &cv::sensor(&Matrix2::identity()),
        |k, r, _| {
            let a = r.adapters;
            // The statistic is the NIS of the raw innovation.
            assert!(
                (a.statistic - r.nis).abs() <= 1e-12 * r.nis.max(1.0),
                "{name} {k}"
            );
            if a.statistic <= c {
                assert!(!a.compressed, "{name} {k}");
                assert_eq!(a.factor, 1.0, "{name} {k}");
                assert_eq!(r.innovation_used, r.innovation, "{name} {k}");
            } else {
                compressed += 1;
                assert!(a.compressed && a.factor < 1.0, "{name} {k}");
                assert!(
                    (r.adapted_nis - c).abs() < 1e-9 * c,
                    "{name} {k}: {}",
                    r.adapted_nis
                );
            }
        },
    )
    .unwrap();
    let rate = compressed as f64 / STEPS as f64;
    assert!((rate - ALPHA).abs() < 0.015, "{name}: compressed {rate}");
}

#[test]
fn factor_is_exactly_one_without_an_outlier() {
    each_form_f64!(exact_one_without_outliers);
}

fn rms_with_outliers<F: CvForm<f64>>(name: &str, make: Make<F>) {
    let stream = support::outlier_stream(7);
    let outliers = stream.outlier.iter().filter(|o| **o).count();
    assert!(
        (80..=120).contains(&outliers),
        "{outliers} outliers in 2000"
    );
    let sensor = cv::sensor(&Matrix2::identity());

    let mut f = make(cv::x0(), cv::p0());
    let clean = support::position_rms(
        &support::run(&mut f, &stream.without_outliers(), &sensor, |_, _, _| {}).unwrap(),
    );
    let mut f = make(cv::x0(), cv::p0());
    let plain =
        support::position_rms(&support::run(&mut f, &stream, &sensor, |_, _, _| {}).unwrap());
    let compression = OutlierCompression::<f64, 2>::new(ALPHA).unwrap();
    let mut f = make(cv::x0(), cv::p0()).with_adapter(compression);
    let mut flagged = 0;
    let compressed = support::position_rms(
        &support::run(&mut f, &stream, &sensor, |k, r, _| {
            if stream.outlier[k] {
                assert!(r.adapters.compressed, "{name}: outlier {k} not compressed");
                flagged += 1;
            }
        })
        .unwrap(),
    );
    assert_eq!(flagged, outliers);
    assert!(
        compressed <= 1.5 * clean,
        "{name}: RMS {compressed} with compression, {clean} without outliers"
    );
    assert!(
        plain >= 3.0 * clean,
        "{name}: plain RMS {plain} with outliers, {clean} without"
    );
}

#[test]
fn compression_keeps_the_rms_near_the_outlier_free_run() {
    each_form_f64!(rms_with_outliers);
}
