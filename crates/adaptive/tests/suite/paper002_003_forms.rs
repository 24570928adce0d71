//! Every adapter of papers 002 / 003 — Huber inflation, the χ² gate, the
//! fuzzy odometer gain, the windowed noise estimate, and the paper-003
//! composition (fuzzy gain, then windowed noise) — runs with the EKF, UKF
//! and SR-UKF in `f64` and `f32` under random parameters drawn from their
//! documented ranges and random streams (correlated `R`, outliers), and
//! after every update the state covariance and the `R` the gain used are
//! exactly symmetric and positive definite.

use crate::support;

use kestrel_adaptive::{
    ChiSquareGate, FuzzyGain, HuberInflation, InflationShape, OdometerInputs, WindowedNoise,
};
use kestrel_core::adapter::NoiseAdapter;
use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector, Vector2};
use kestrel_core::{Filter, Real};
use proptest::prelude::*;
use rand::RngExt;
use support::{cv, symmetric_pd, to, CvForm};

/// Something to do to the adapter before each update.
trait Prepare<A> {
    fn prepare(&mut self, adapter: &mut A);
}

/// Nothing to prepare.
struct Nothing;
impl<A> Prepare<A> for Nothing {
    fn prepare(&mut self, _: &mut A) {}
}

/// Draws fuzzy-gain inputs: dm₁ ∈ [0.3, 2], ΔH ∈ [−60, 60] deg/s,
/// v_OD ∈ [−20, 20]².
struct Inputs(rand_chacha::ChaCha8Rng);
impl Inputs {
    fn draw<T: Real>(&mut self) -> OdometerInputs<T, 2> {
        let dm1 = self.0.random_range(0.3..2.0);
        let heading = self.0.random_range(-60.0..60.0);
        let v = Vector2::new(
            self.0.random_range(-20.0..20.0),
            self.0.random_range(-20.0..20.0),
        );
        OdometerInputs::new(to(dm1), to(heading), v.map(to))
    }
}
impl<T: Real, const S: usize, const O: usize, const R: usize> Prepare<FuzzyGain<T, 2, S, O, R>>
    for Inputs
{
    fn prepare(&mut self, adapter: &mut FuzzyGain<T, 2, S, O, R>) {
        adapter.set_inputs(self.draw());
    }
}
impl<T: Real, B> Prepare<(FuzzyGain<T, 2>, B)> for Inputs {
    fn prepare(&mut self, adapter: &mut (FuzzyGain<T, 2>, B)) {
        adapter.0.set_inputs(self.draw());
    }
}

/// One random case: the stream and the adapter parameters.
#[derive(Debug, Clone, Copy)]
struct Case {
    seed: u64,
    r: Matrix2<f64>,
    outlier_rate: f64,
    outlier_size: f64,
    significance: f64,
    diagonal: bool,
    gate: f64,
    smoothing: f64,
    floor: f64,
    odometer_seed: u64,
}

fn case() -> impl Strategy<Value = Case> {
    (
        any::<u64>(),
        (0.05..5.0_f64, 0.05..5.0_f64, -0.9..0.9_f64),
        (0.0..0.2_f64, 0.0..50.0_f64),
        (0.01..=0.15_f64, any::<bool>(), 0.001..0.5_f64),
        (
            0.01..=1.0_f64,
            prop_oneof![Just(1e-6), Just(1e-3), Just(1.0)],
        ),
    )
        .prop_map(
            |(seed, (a, b, rho), (rate, size), (sig, diagonal, gate), (smoothing, floor))| {
                let off = rho * (a * b).sqrt();
                Case {
                    seed,
                    r: Matrix2::new(a, off, off, b),
                    outlier_rate: rate,
                    outlier_size: size,
                    significance: sig,
                    diagonal,
                    gate,
                    smoothing,
                    floor,
                    odometer_seed: seed ^ 0x5eed,
                }
            },
        )
}

const STEPS: usize = 60;

/// Runs `adapter` in form `F` over the case's stream, preparing it before
/// each update, and checks `P` and the used `R` after every update.
fn check<T: Real, F: CvForm<T>, A: NoiseAdapter<T, 2> + Clone>(
    name: &str,
    make: fn(SVector<T, 4>, SMatrix<T, 4, 4>) -> Filter<T, 4, F>,
    case: &Case,
    adapter: &A,
    prepare: &mut dyn Prepare<A>,
) {
    let spec =
        cv::Spec::new(case.seed, STEPS, case.r).with_outliers(case.outlier_rate, case.outlier_size);
    let stream = cv::stream(&spec);
    let sensor = cv::sensor::<T>(&case.r);
    let process = cv::process::<T>(stream.q);
    let mut f = make(cv::x0(), cv::p0()).with_adapter(adapter.clone());
    for (k, z) in stream.z.iter().enumerate() {
        f.predict(&process, T::one()).unwrap();
        prepare.prepare(f.adapter_mut());
        let detail = f
            .update_detailed(&sensor, &z.map(to::<T>))
            .unwrap_or_else(|e| panic!("{name} at {k}: {e}"));
        assert!(symmetric_pd(&f.covariance()), "{name}: P at {k}");
        assert!(symmetric_pd(&detail.noise), "{name}: R at {k}");
        assert!(
            detail.report.innovation_used.iter().all(|v| v.is_finite()),
            "{name} at {k}"
        );
    }
}

/// Runs `check` for every form in `f64` and `f32`, the adapter built by
/// `$adapter` (a generic expression in `T`) and prepared by `$prepare`.
macro_rules! all_forms {
    ($case:expr, |$t:ident| $adapter:expr, $prepare:expr) => {{
        fn run_one<$t: Real, F: CvForm<$t>>(
            name: &str,
            make: fn(SVector<$t, 4>, SMatrix<$t, 4, 4>) -> Filter<$t, 4, F>,
            case: &Case,
        ) {
            let adapter = $adapter(case);
            let mut prepare = $prepare(case);
            check(name, make, case, &adapter, &mut prepare);
        }
        each_form!(run_one, &$case);
    }};
}

fn inputs(case: &Case) -> Inputs {
    Inputs(support::rng(case.odometer_seed))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn huber_keeps_p_and_r_spd(case in case()) {
        all_forms!(case, |T| |c: &Case| {
            let shape = if c.diagonal { InflationShape::Diagonal } else { InflationShape::Congruence };
            HuberInflation::<T, 2>::new(kestrel_core::real::lit(c.significance)).unwrap().with_shape(shape)
        }, |_: &Case| Nothing);
    }

    #[test]
    fn gate_keeps_p_and_r_spd(case in case()) {
        all_forms!(case, |T| |c: &Case| ChiSquareGate::<T, 2>::new(kestrel_core::real::lit(c.gate)).unwrap(),
            |_: &Case| Nothing);
    }

    #[test]
    fn fuzzy_gain_keeps_p_and_r_spd(case in case()) {
        all_forms!(case, |T| |c: &Case| {
            let engine = *FuzzyGain::<T, 2>::odometer().unwrap().engine();
            FuzzyGain::<T, 2>::new(engine, kestrel_adaptive::ODOMETER_UNUSABLE, kestrel_core::real::lit(c.smoothing))
                .unwrap()
        }, inputs);
    }

    #[test]
    fn windowed_noise_keeps_p_and_r_spd(case in case()) {
        all_forms!(case, |T| |c: &Case| WindowedNoise::<T, 2, 1>::new(to(c.floor)).unwrap(),
            |_: &Case| Nothing);
        all_forms!(case, |T| |c: &Case| WindowedNoise::<T, 2, 8>::new(to(c.floor)).unwrap(),
            |_: &Case| Nothing);
    }

    #[test]
    fn paper003_composition_keeps_p_and_r_spd(case in case()) {
        all_forms!(case, |T| |c: &Case| (
            FuzzyGain::<T, 2>::new(
                kestrel_adaptive::odometer_engine().unwrap(),
                kestrel_adaptive::ODOMETER_UNUSABLE,
                to(c.smoothing),
            ).unwrap(),
            WindowedNoise::<T, 2, 8>::new(to(c.floor)).unwrap(),
        ), inputs);
    }
}
