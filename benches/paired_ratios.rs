//! Paired timing of the ratios the speed goals set at 15 states: the UKF
//! and SR-UKF steps against the KF step, each `f32` step against its `f64`
//! one, and the EKF with paper 000's `ImprovedAdaptive` against the plain
//! EKF.
//!
//! In a criterion run the two cells of a ratio are timed minutes apart,
//! and on a shared machine one can fall in a slow period and the other not
//! (run by run, UKF ÷ KF has moved between 2.09 and 3.55 over five runs of
//! `step`; `docs/notes/benchmark-rounds.md`). Here the eight steps and a throughput
//! probe take turns within one process, as `common::rounds` describes, and
//! each ratio is taken within a round.
//!
//! The steps are those of the `step` benchmark (`kf_step/15`,
//! `ukf_step/15`, `srukf_step/15` and their `_f32` cells: the dense model,
//! `M = 6`, a constant `z`) and of the `adapters` benchmark
//! (`adapter_step/15/plain` and `adapter_step/15/improved_adaptive`: the
//! same model fed a simulated cycle of 1024 measurements, so the adapter
//! estimates, compresses and fades at its natural rates). Every filter is
//! checked before it is timed: the six on a constant `z` against the
//! hand-written `f64` filter, the two on the cycle by running it once
//! (every update accepted, the batch path taken, the adapter acting).
//!
//! ```sh
//! cargo bench --bench paired_ratios                 # 1000 rounds
//! cargo bench --bench paired_ratios -- --rounds 3000
//! ```
//!
//! It prints each step's median time over the rounds with the 10th and
//! 90th percentiles, then for each ratio its median over rounds with the
//! 10th and 90th percentiles, the rounds in which it met its goal, and the
//! same over the uncontended and the contended rounds apart.

// Not every shared piece is used here (the baselines are not timed).
#[allow(dead_code)]
mod common;

use std::hint::black_box;

use common::model::Model;
use common::reference::{check, CHECK_STEPS};
use common::rounds::{
    print_medians, probe_levels, rounds_or_exit, spread, take_turns, time_chunk, Probe, CONTENDED,
};
use common::simulate::{cycled, measurements, CYCLE};
use kestrel::adaptive::ImprovedAdaptive;
use kestrel::form::{PredictForm, UpdateForm};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::{Ekf, Filter, Real, SrUkf, Ukf};

const N: usize = 15;
const M: usize = 6;

/// Rounds unless `--rounds` says otherwise (about ten seconds).
const DEFAULT_ROUNDS: usize = 1000;

/// The timed workloads, in the order of the printed columns; the probe is
/// the last.
const WORKLOADS: [&str; 9] = [
    "kf",
    "ukf",
    "srukf",
    "kf_f32",
    "ukf_f32",
    "srukf_f32",
    "plain",
    "improved",
    "probe",
];

/// The probe's index in [`WORKLOADS`].
const PROBE: usize = 8;

/// A ratio of two workloads' times in one round, and the most it may be.
struct Goal {
    name: &'static str,
    numerator: usize,
    denominator: usize,
    most: f64,
}

/// The goals of the speed work at 15 states.
const GOALS: [Goal; 6] = [
    Goal {
        name: "UKF ÷ KF",
        numerator: 1,
        denominator: 0,
        most: 2.5,
    },
    Goal {
        name: "SR-UKF ÷ KF",
        numerator: 2,
        denominator: 0,
        most: 3.0,
    },
    Goal {
        name: "KF `f32` ÷ `f64`",
        numerator: 3,
        denominator: 0,
        most: 0.7,
    },
    Goal {
        name: "UKF `f32` ÷ `f64`",
        numerator: 4,
        denominator: 1,
        most: 0.7,
    },
    Goal {
        name: "SR-UKF `f32` ÷ `f64`",
        numerator: 5,
        denominator: 2,
        most: 0.7,
    },
    Goal {
        name: "`ImprovedAdaptive` ÷ plain",
        numerator: 7,
        denominator: 6,
        most: 1.2,
    },
];

/// `f` after [`CHECK_STEPS`] checked steps on the constant `z` of `m`
/// (panics unless it matches the hand-written `f64` filter).
fn checked<T, F>(name: &str, mut f: Filter<T, N, F>, m: &Model<T, N, M>) -> Filter<T, N, F>
where
    T: Real,
    F: PredictForm<T, N, LinearProcess<T, N>> + UpdateForm<T, N, LinearMeasurement<T, N, M>, M>,
{
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, m.r);
    for _ in 0..CHECK_STEPS {
        f.predict(&process, T::one()).expect("predict");
        let report = f.update(&measurement, &m.z).expect("update");
        assert!(!report.sequential, "{name}: batch update");
    }
    let reference = Model::<f64, N, M>::of_step_benchmarks();
    check(name, &reference, &reference.r, f.state(), &f.covariance());
    f
}

/// Nanoseconds a step (a probe call for the probe), per workload and round.
fn measure(rounds: usize) -> [Vec<f64>; WORKLOADS.len()] {
    let m64 = Model::<f64, N, M>::of_step_benchmarks();
    let m32: Model<f32, N, M> = m64.to();
    let mut kf = checked("kf", Ekf::new(m64.x0, m64.p0).unwrap(), &m64);
    let mut ukf = checked("ukf", Ukf::new(m64.x0, m64.p0).unwrap(), &m64);
    let mut srukf = checked("srukf", SrUkf::new(m64.x0, m64.p0).unwrap(), &m64);
    let mut kf32 = checked("kf_f32", Ekf::new(m32.x0, m32.p0).unwrap(), &m32);
    let mut ukf32 = checked("ukf_f32", Ukf::new(m32.x0, m32.p0).unwrap(), &m32);
    let mut srukf32 = checked("srukf_f32", SrUkf::new(m32.x0, m32.p0).unwrap(), &m32);
    let zs = measurements(&m64);
    let ekf = || Ekf::new(m64.x0, m64.p0).unwrap();
    let mut plain = cycled("plain", ekf(), &m64, &zs, |_| true);
    let adapter = ImprovedAdaptive::as_published().unwrap();
    let mut improved = cycled("improved", ekf().with_adapter(adapter), &m64, &zs, |r| {
        r.adapters.sage_husa.estimated && r.adapters.tests.0.compressed
    });

    let p64 = LinearProcess::new(m64.phi, m64.q);
    let s64 = LinearMeasurement::new(m64.h, m64.r);
    let p32 = LinearProcess::new(m32.phi, m32.q);
    let s32 = LinearMeasurement::new(m32.h, m32.r);
    // One closure per workload, each a step as the criterion cells time it.
    macro_rules! step {
        ($f:ident, $p:expr, $s:expr, $z:expr) => {
            || {
                $f.predict(&$p, 1.0).expect("predict");
                black_box($f.update(&$s, black_box($z)).expect("update"));
            }
        };
    }
    let mut kf_step = step!(kf, p64, s64, &m64.z);
    let mut ukf_step = step!(ukf, p64, s64, &m64.z);
    let mut srukf_step = step!(srukf, p64, s64, &m64.z);
    let mut kf32_step = step!(kf32, p32, s32, &m32.z);
    let mut ukf32_step = step!(ukf32, p32, s32, &m32.z);
    let mut srukf32_step = step!(srukf32, p32, s32, &m32.z);
    let (mut k_plain, mut k_improved) = (0, 0);
    let mut plain_step = || {
        plain.predict(&p64, 1.0).expect("predict");
        black_box(plain.update(&s64, black_box(&zs[k_plain])).expect("update"));
        k_plain = (k_plain + 1) % CYCLE;
    };
    let mut improved_step = || {
        improved.predict(&p64, 1.0).expect("predict");
        black_box(
            improved
                .update(&s64, black_box(&zs[k_improved]))
                .expect("update"),
        );
        k_improved = (k_improved + 1) % CYCLE;
    };
    let mut probe = Probe::new();
    let mut probe_call = || probe.call();

    take_turns(
        rounds,
        [
            &mut |n| time_chunk(&mut kf_step, n),
            &mut |n| time_chunk(&mut ukf_step, n),
            &mut |n| time_chunk(&mut srukf_step, n),
            &mut |n| time_chunk(&mut kf32_step, n),
            &mut |n| time_chunk(&mut ukf32_step, n),
            &mut |n| time_chunk(&mut srukf32_step, n),
            &mut |n| time_chunk(&mut plain_step, n),
            &mut |n| time_chunk(&mut improved_step, n),
            &mut |n| time_chunk(&mut probe_call, n),
        ],
    )
}

/// `median (p10–p90), met of rounds` of the ratios `keep` selects, against
/// the goal's `most`.
fn summary(ratios: &[f64], most: f64, keep: impl Fn(usize) -> bool) -> String {
    let kept: Vec<f64> = (0..ratios.len())
        .filter(|&i| keep(i))
        .map(|i| ratios[i])
        .collect();
    if kept.is_empty() {
        return "no rounds".to_string();
    }
    let met = kept.iter().filter(|&&r| r <= most).count();
    format!("{}, {met} of {}", spread(&kept, 2), kept.len())
}

fn main() {
    let rounds = rounds_or_exit("paired_ratios", DEFAULT_ROUNDS);
    let times = measure(rounds);
    let probe = &times[PROBE];
    let fastest = probe.iter().copied().fold(f64::INFINITY, f64::min);
    let contended = |i: usize| probe[i] > CONTENDED * fastest;

    println!("{N} states, M = {M}: ns a step (the probe: a call), median over rounds (10th–90th percentile); {rounds} rounds");
    println!();
    print_medians(&WORKLOADS, &times);
    println!();
    println!("Each ratio within a round: median over rounds (10th–90th percentile), rounds meeting the goal of rounds");
    println!(
        "contended: the probe took more than {CONTENDED} × its fastest round; probe: its 10th–90th percentile ÷ its fastest, {}",
        probe_levels(probe, fastest)
    );
    println!();
    println!("| ratio | goal | all rounds | uncontended | contended |");
    println!("|---|---|---|---|---|");
    for goal in &GOALS {
        let (num, den) = (&times[goal.numerator], &times[goal.denominator]);
        let ratios: Vec<f64> = num.iter().zip(den).map(|(a, b)| a / b).collect();
        println!(
            "| {} | ≤ {} | {} | {} | {} |",
            goal.name,
            goal.most,
            summary(&ratios, goal.most, |_| true),
            summary(&ratios, goal.most, |i| !contended(i)),
            summary(&ratios, goal.most, contended),
        );
    }
}
