//! Every adapter of papers 000 / 004 and both compositions run with the EKF,
//! UKF and SR-UKF, in `f32` and `f64`, on hostile streams (a mismatched
//! `R`, outliers, an unmodelled jump), with random parameters drawn from
//! their documented ranges. After every update: the update succeeded (the
//! one accepted exception: `f32` refusing an innovation covariance whose
//! condition number exceeds 10⁴ after a Sage–Husa estimate ran away; see
//! [`f32_limit`]), the
//! covariance `P` and any estimate `R̂` are exactly symmetric and positive
//! definite (an independent `f64` Cholesky factorisation succeeds), and
//! every reported number is finite.

use crate::support;

use kestrel_adaptive::{
    DivergenceFading, ImprovedAdaptive, OutlierCompression, SageHusa, SageHusaComposition,
    SageHusaFading, StrongTracking,
};
use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector4};
use kestrel_core::{Filter, FilterError, Quantity, Real};
use proptest::prelude::*;
use support::{cv, to, CvForm};

/// An adapter configuration that can be built in any precision.
trait Build: Copy + core::fmt::Debug {
    type A<T: Real>: NoiseAdapter<T, 2> + Copy;
    fn build<T: Real>(&self) -> Self::A<T>;
    /// The `R` estimate the adapter holds, if any.
    fn estimate<T: Real>(_: &Self::A<T>) -> Option<Matrix2<T>> {
        None
    }
}

/// The random scenario.
#[derive(Debug, Clone, Copy)]
struct Scenario {
    seed: u64,
    /// True `R` = `scale` × assumed `R`.
    scale: f64,
    outlier_rate: f64,
    outlier_size: f64,
    jump: f64,
}

fn check<T: Real, F: CvForm<T>, B: Build>(
    name: &str,
    make: fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>,
    (config, s): (B, Scenario),
) {
    let assumed = Matrix2::new(1.0, 0.2, 0.2, 0.5);
    let spec = cv::Spec::new(s.seed, 300, assumed * s.scale)
        .with_outliers(s.outlier_rate, s.outlier_size)
        .with_jump(150, Vector4::new(s.jump, -s.jump, 0.0, 0.0));
    let stream = cv::stream(&spec);
    let mut f = make(cv::x0(), cv::p0()).with_adapter(config.build::<T>());
    support::run_detailed(&mut f, &stream, &cv::sensor(&assumed), |k, d, f| {
        let r = &d.report;
        let what = format!("{name}, {config:?}, {s:?}, epoch {k}");
        let p = f.covariance();
        assert!(support::symmetric_pd(&p), "{what}: P = {p}");
        if let Some(r_hat) = B::estimate(f.adapter()) {
            assert!(support::symmetric_pd(&r_hat), "{what}: R̂ = {r_hat}");
        }
        let finite = |m: &[T]| m.iter().all(|v| v.is_finite());
        assert!(finite(d.noise.as_slice()), "{what}");
        assert!(finite(r.innovation_used.as_slice()), "{what}");
        assert!(r.fade.is_finite() && r.fade >= T::one(), "{what}");
        assert!(
            format!("{:?}", r.adapters).find("NaN").is_none(),
            "{what}: {:?}",
            r.adapters
        );
        assert!(
            format!("{:?}", r.adapters).find("inf").is_none(),
            "{what}: {:?}",
            r.adapters
        );
    })
    .map(|_| ())
    .or_else(|e| f32_limit(&f, B::estimate(f.adapter()), e))
    .unwrap_or_else(|e| panic!("{name}, {config:?}, {s:?}: {e}"));
}

/// Smallest condition number of the innovation covariance at which an
/// `f32` factorisation may fail: `10⁴` is `ε_f32 ≈ 1.2e-7` away from `1/ε`
/// by three orders of magnitude, so a failure below it is a defect.
const F32_CONDITION: f64 = 1e4;

/// Accepts one failure only: in `f32`, the innovation covariance is refused
/// as not positive definite when the `R̂` the adapter holds has run away
/// along one direction (the known divergence of the unbounded Sage–Husa
/// estimator under outliers, which the paper's fading exists to stop), so
/// that `C = H P⁻ Hᵀ + R̂`, recomputed in `f64` from the filter's unchanged
/// prior, has a condition number above [`F32_CONDITION`]. Anything else
/// stays the error it was.
fn f32_limit<T: Real, F: CvForm<T>, A>(
    f: &Filter<T, 4, F, A>,
    estimate: Option<Matrix2<T>>,
    e: FilterError,
) -> Result<(), FilterError> {
    let single = kestrel_core::real::to_f64(kestrel_core::real::epsilon::<T>()) > 1e-10;
    let refused_c = e
        == FilterError::NotPositiveDefinite {
            what: Quantity::InnovationCovariance,
            index: 1,
        };
    let Some(r_hat) = estimate.filter(|_| single && refused_c) else {
        return Err(e);
    };
    let h = cv::sensor::<f64>(&Matrix2::identity()).matrix;
    let p = f.covariance().map(kestrel_core::real::to_f64);
    let c = h * p * h.transpose() + r_hat.map(kestrel_core::real::to_f64);
    let (mean, half) = ((c[(0, 0)] + c[(1, 1)]) / 2.0, {
        let d = (c[(0, 0)] - c[(1, 1)]) / 2.0;
        (d * d + c[(0, 1)] * c[(1, 0)]).sqrt()
    });
    let condition = (mean + half) / (mean - half);
    if condition > F32_CONDITION || mean - half <= 0.0 {
        Ok(())
    } else {
        Err(e)
    }
}

#[derive(Debug, Clone, Copy)]
struct ShConfig {
    b: f64,
    floor: Option<f64>,
}

impl ShConfig {
    fn sage_husa<T: Real>(&self) -> SageHusa<T, 2> {
        let sh = SageHusa::new(to(self.b)).unwrap();
        match self.floor {
            Some(f) => sh.with_floor(Vector2::repeat(to(f))).unwrap(),
            None => sh,
        }
    }
}

impl Build for ShConfig {
    type A<T: Real> = SageHusa<T, 2>;
    fn build<T: Real>(&self) -> Self::A<T> {
        self.sage_husa()
    }
    fn estimate<T: Real>(a: &Self::A<T>) -> Option<Matrix2<T>> {
        Some(*a.estimate())
    }
}

#[derive(Debug, Clone, Copy)]
struct FadingConfig {
    reserve: f64,
    max_fade: f64,
}

impl FadingConfig {
    fn fading<T: Real>(&self) -> DivergenceFading<T> {
        DivergenceFading::new(to(self.reserve), to(self.max_fade)).unwrap()
    }
}

impl Build for FadingConfig {
    type A<T: Real> = DivergenceFading<T>;
    fn build<T: Real>(&self) -> Self::A<T> {
        self.fading()
    }
}

#[derive(Debug, Clone, Copy)]
struct StConfig {
    rho: f64,
    softening: f64,
    max_fade: Option<f64>,
}

impl Build for StConfig {
    type A<T: Real> = StrongTracking<T>;
    fn build<T: Real>(&self) -> Self::A<T> {
        let st = StrongTracking::new(to(self.rho), to(self.softening)).unwrap();
        match self.max_fade {
            Some(m) => st.with_max_fade(to(m)).unwrap(),
            None => st,
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct CompressionConfig {
    alpha: f64,
}

impl Build for CompressionConfig {
    type A<T: Real> = OutlierCompression<T, 2>;
    fn build<T: Real>(&self) -> Self::A<T> {
        OutlierCompression::new(kestrel_core::real::lit(self.alpha)).unwrap()
    }
}

#[derive(Debug, Clone, Copy)]
struct ImprovedConfig {
    sh: ShConfig,
    fading: FadingConfig,
    alpha: f64,
}

impl Build for ImprovedConfig {
    type A<T: Real> = ImprovedAdaptive<T, 2>;
    fn build<T: Real>(&self) -> Self::A<T> {
        SageHusaComposition::new(
            (
                OutlierCompression::new(kestrel_core::real::lit(self.alpha)).unwrap(),
                self.fading.fading(),
            ),
            self.sh.sage_husa(),
        )
    }
    fn estimate<T: Real>(a: &Self::A<T>) -> Option<Matrix2<T>> {
        Some(*a.sage_husa.estimate())
    }
}

#[derive(Debug, Clone, Copy)]
struct BaselineConfig {
    sh: ShConfig,
    fading: FadingConfig,
}

impl Build for BaselineConfig {
    type A<T: Real> = SageHusaFading<T, 2>;
    fn build<T: Real>(&self) -> Self::A<T> {
        SageHusaComposition::new(self.fading.fading(), self.sh.sage_husa())
    }
    fn estimate<T: Real>(a: &Self::A<T>) -> Option<Matrix2<T>> {
        Some(*a.sage_husa.estimate())
    }
}

/// A plain tuple: compression, strong tracking, then Sage-Husa (skipping
/// faded epochs).
#[derive(Debug, Clone, Copy)]
struct TupleConfig {
    alpha: f64,
    st: StConfig,
    sh: ShConfig,
}

impl Build for TupleConfig {
    type A<T: Real> = (OutlierCompression<T, 2>, StrongTracking<T>, SageHusa<T, 2>);
    fn build<T: Real>(&self) -> Self::A<T> {
        (
            OutlierCompression::new(kestrel_core::real::lit(self.alpha)).unwrap(),
            self.st.build(),
            self.sh.sage_husa(),
        )
    }
    fn estimate<T: Real>(a: &Self::A<T>) -> Option<Matrix2<T>> {
        Some(*a.2.estimate())
    }
}

fn scenario() -> impl Strategy<Value = Scenario> {
    (
        any::<u64>(),
        0.1..10.0f64,
        0.0..0.1f64,
        5.0..50.0f64,
        0.0..50.0f64,
    )
        .prop_map(|(seed, scale, outlier_rate, outlier_size, jump)| Scenario {
            seed,
            scale,
            outlier_rate,
            outlier_size,
            jump,
        })
}

/// `b` in the paper's range `[0.95, 0.99]`.
fn sh() -> impl Strategy<Value = ShConfig> {
    sh_in(0.95..=0.99f64)
}

fn sh_in(b: impl Strategy<Value = f64>) -> impl Strategy<Value = ShConfig> {
    (b, proptest::option::of(0.0..0.5f64)).prop_map(|(b, floor)| ShConfig { b, floor })
}

fn fading() -> impl Strategy<Value = FadingConfig> {
    (1.0..30.0f64, prop_oneof![1.0..1e4f64, Just(f64::INFINITY)])
        .prop_map(|(reserve, max_fade)| FadingConfig { reserve, max_fade })
}

fn st() -> impl Strategy<Value = StConfig> {
    (
        0.0..=1.0f64,
        1.0..20.0f64,
        proptest::option::of(1.0..1e4f64),
    )
        .prop_map(|(rho, softening, max_fade)| StConfig {
            rho,
            softening,
            max_fade,
        })
}

fn alpha() -> impl Strategy<Value = f64> {
    0.001..0.5f64
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn sage_husa_every_form(config in sh(), s in scenario()) {
        each_form!(check, (config, s));
    }

    #[test]
    fn sage_husa_whole_range_f64(config in sh_in(0.01..0.999f64), s in scenario()) {
        each_form_f64!(check, (config, s));
    }

    #[test]
    fn divergence_fading_every_form(config in fading(), s in scenario()) {
        each_form!(check, (config, s));
    }

    #[test]
    fn strong_tracking_every_form(config in st(), s in scenario()) {
        each_form!(check, (config, s));
    }

    #[test]
    fn outlier_compression_every_form(alpha in alpha(), s in scenario()) {
        each_form!(check, (CompressionConfig { alpha }, s));
    }

    #[test]
    fn improved_adaptive_every_form(sh in sh(), fading in fading(), alpha in alpha(), s in scenario()) {
        each_form!(check, (ImprovedConfig { sh, fading, alpha }, s));
    }

    #[test]
    fn sage_husa_fading_every_form(sh in sh(), fading in fading(), s in scenario()) {
        each_form!(check, (BaselineConfig { sh, fading }, s));
    }

    #[test]
    fn tuple_every_form(alpha in alpha(), st in st(), sh in sh(), s in scenario()) {
        each_form!(check, (TupleConfig { alpha, st, sh }, s));
    }
}

#[test]
fn paper_constructors_run_every_form() {
    #[derive(Debug, Clone, Copy)]
    struct Improved;
    impl Build for Improved {
        type A<T: Real> = ImprovedAdaptive<T, 2>;
        fn build<T: Real>(&self) -> Self::A<T> {
            ImprovedAdaptive::as_published().unwrap()
        }
        fn estimate<T: Real>(a: &Self::A<T>) -> Option<Matrix2<T>> {
            Some(*a.sage_husa.estimate())
        }
    }
    #[derive(Debug, Clone, Copy)]
    struct Baseline;
    impl Build for Baseline {
        type A<T: Real> = SageHusaFading<T, 2>;
        fn build<T: Real>(&self) -> Self::A<T> {
            SageHusaFading::as_published().unwrap()
        }
        fn estimate<T: Real>(a: &Self::A<T>) -> Option<Matrix2<T>> {
            Some(*a.sage_husa.estimate())
        }
    }
    let s = Scenario {
        seed: 3,
        scale: 4.0,
        outlier_rate: 0.05,
        outlier_size: 20.0,
        jump: 30.0,
    };
    each_form!(check, (Improved, s));
    each_form!(check, (Baseline, s));
}

/// A case the random search found: plain Sage–Husa (`b = 0.983`, no floor)
/// under a 5.7× mismatched `R`, rare 40σ outliers and a 20 m jump. The
/// estimate runs away (`R̂` above 10⁶ m², nearly singular) in both
/// precisions. `f64` keeps going. `f32` used to stop here with the typed
/// error naming the innovation covariance (which the property tests still
/// accept, see [`f32_limit`]); since the Joseph update takes the negated
/// gain and forms `B − K A` in one product, it keeps going too, and stays
/// within a tenth of a standard deviation of the `f64` filter.
#[test]
fn a_runaway_sage_husa_estimate_in_f32_tracks_f64() {
    let s = Scenario {
        seed: 4130530363513276249,
        scale: 5.69952456287941,
        outlier_rate: 0.004689272682563682,
        outlier_size: 40.71910597365423,
        jump: 20.381311591612675,
    };
    let config = ShConfig {
        b: 0.9833555822059118,
        floor: None,
    };
    let assumed = Matrix2::new(1.0, 0.2, 0.2, 0.5);
    let spec = cv::Spec::new(s.seed, 300, assumed * s.scale)
        .with_outliers(s.outlier_rate, s.outlier_size)
        .with_jump(150, Vector4::new(s.jump, -s.jump, 0.0, 0.0));
    let stream = cv::stream(&spec);
    let mut f64_filter = kestrel_core::Ekf::new(cv::x0::<f64>(), cv::p0::<f64>())
        .unwrap()
        .with_adapter(config.build::<f64>());
    support::run(
        &mut f64_filter,
        &stream,
        &cv::sensor(&assumed),
        |_, _, _| {},
    )
    .unwrap();
    assert!(f64_filter.adapter().estimate()[(0, 0)] > 1e6);
    let mut f32_filter = kestrel_core::Ekf::new(cv::x0::<f32>(), cv::p0::<f32>())
        .unwrap()
        .with_adapter(config.build::<f32>());
    support::run(
        &mut f32_filter,
        &stream,
        &cv::sensor(&assumed),
        |_, _, _| {},
    )
    .unwrap();
    assert!(f32_filter.adapter().estimate()[(0, 0)] > 1e6);
    assert!(support::symmetric_pd(&f32_filter.covariance()));
    let p = f64_filter.covariance();
    for i in 0..4 {
        let gap = (f64::from(f32_filter.state()[i]) - f64_filter.state()[i]).abs();
        assert!(
            gap < 0.1 * p[(i, i)].sqrt(),
            "state {i}: f32 {} against f64 {}, σ {}",
            f32_filter.state()[i],
            f64_filter.state()[i],
            p[(i, i)].sqrt()
        );
    }
}
