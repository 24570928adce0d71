//! Paired timing of the dense `kf_step` against its two baselines (the
//! `adskalman` crate and the hand-written nalgebra filter) on the model of
//! the `step` benchmark, for a machine whose speed changes while it runs.
//!
//! The three filters take turns within one process, with a throughput
//! probe, as `common::rounds` describes: a slow period of the machine
//! falls on all three alike, and a round whose probe was slow counts as
//! contended. (In such periods the KF step at 2 states lost a quarter of
//! its speed where adskalman's lost 5 %: code that keeps many instructions
//! in flight loses more than code that waits on one dependent chain.)
//!
//! For each size it prints every filter's median time a step over the
//! rounds, with the 10th and 90th percentiles, the median over rounds of
//! the KF's time divided by the faster baseline's in the same round, and
//! the share of rounds in which the KF was at or below both; then the same
//! ratio over the uncontended and over the contended rounds apart.
//!
//! At 2 states a fourth filter takes its turn: the step written out by hand
//! with every check of the library's step (`common::checked_by_hand`), and
//! a line after the table sets its time against adskalman's: what a checked
//! step costs at least, against what the library's generic one costs.
//!
//! ```sh
//! cargo bench --bench paired                  # every size, 300 rounds each
//! cargo bench --bench paired -- 2 6 --rounds 1000
//! ```
//!
//! Every filter is checked against the hand-written `f64` filter before it
//! is timed.

mod common;

use std::hint::black_box;

use common::adskalman_kf;
use common::checked_by_hand::CheckedByHand;
use common::hand::HandKf;
use common::model::Model;
use common::reference::{check, CHECK_STEPS};
use common::rounds::{
    chunk_steps, parse_rounds, probe_levels, quantile, spread, time_chunk, Probe, CONTENDED,
};
use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Const, DimMin};
use kestrel::Ekf;

/// The sizes of the `step` benchmark.
const SIZES: [usize; 9] = [2, 4, 6, 9, 12, 15, 18, 24, 32];

/// Rounds per size unless `--rounds` says otherwise.
const DEFAULT_ROUNDS: usize = 300;

/// The timed workloads: the three filters, in the order of the printed
/// columns, the throughput probe, and (at 2 states only) the step written
/// out by hand with the library's checks.
const WORKLOADS: usize = 5;

/// The index of the probe's times.
const PROBE: usize = 3;

/// The index of the checked step by hand's times (empty above 2 states).
const BY_HAND: usize = 4;

/// What one size's rounds measured.
struct Row {
    n: usize,
    /// Nanoseconds a step, per round: KF, adskalman, nalgebra,
    /// nanoseconds a probe call, and (at 2 states) the checked step by hand.
    times: [Vec<f64>; WORKLOADS],
}

/// Checks the three filters at size `N`, then times `rounds` rounds.
fn paired<const N: usize, const M: usize>(rounds: usize) -> Row
where
    Const<M>: DimMin<Const<M>, Output = Const<M>>,
{
    let m = Model::<f64, N, M>::of_step_benchmarks();
    let process = LinearProcess::new(m.phi, m.q);
    let measurement = LinearMeasurement::new(m.h, m.r);
    let mut kf = Ekf::new(m.x0, m.p0).expect("initial covariance");
    let mut hand = HandKf::new(m.x0, m.p0);
    let (ads_process, ads_measurement) = adskalman_kf::models(&m, &m.r);
    let ads = ::adskalman::KalmanFilterNoControl::<f64, Const<N>, Const<M>>::new(
        &ads_process,
        &ads_measurement,
    );
    let mut est = ::adskalman::StateAndCovariance::<f64, Const<N>>::new(m.x0, m.p0);
    for _ in 0..CHECK_STEPS {
        kf.predict(&process, 1.0).expect("predict");
        kf.update(&measurement, &m.z).expect("update");
        est = ads.step(&est, &m.z).expect("adskalman step");
        assert!(hand.step(&m, &m.r, &m.z), "nalgebra step");
    }
    check("kf", &m, &m.r, kf.state(), &kf.covariance());
    check("adskalman", &m, &m.r, est.state(), est.covariance());
    check("nalgebra", &m, &m.r, &hand.x, &hand.p);
    // The same model at 2 states (used only when `N = 2`).
    let m2 = Model::<f64, 2, 2>::of_step_benchmarks();
    let mut by_hand = CheckedByHand::new(m2.x0, &m2.p0).expect("initial covariance");
    if N == 2 {
        for _ in 0..CHECK_STEPS {
            by_hand.predict(&m2.phi, &m2.q, 1.0).expect("predict");
            by_hand.update(&m2.h, &m2.r, &m2.z).expect("update");
        }
        check("checked by hand", &m2, &m2.r, &by_hand.x, &by_hand.p());
    }

    let mut kf_step = || {
        kf.predict(&process, 1.0).expect("predict");
        black_box(kf.update(&measurement, black_box(&m.z)).expect("update"));
    };
    let mut ads_step = || est = ads.step(&est, black_box(&m.z)).expect("adskalman step");
    let mut hand_step = || assert!(hand.step(&m, &m.r, black_box(&m.z)));
    let mut by_hand_step = || {
        by_hand.predict(&m2.phi, &m2.q, 1.0).expect("predict");
        black_box(
            by_hand
                .update(&m2.h, &m2.r, black_box(&m2.z))
                .expect("update"),
        );
    };
    let mut probe = Probe::new();
    let mut probe_call = || probe.call();
    let chunk = chunk_steps(&mut kf_step);
    let probe_chunk = chunk_steps(&mut probe_call);
    let workloads = if N == 2 { WORKLOADS } else { BY_HAND };
    let mut times: [Vec<f64>; WORKLOADS] = Default::default();
    for round in 0..rounds {
        for k in 0..workloads {
            // Each closure is timed by its own instance of `time_chunk`, its
            // step inlined into the loop as in a criterion benchmark.
            let workload = (round + k) % workloads;
            let t = match workload {
                0 => time_chunk(&mut kf_step, chunk),
                1 => time_chunk(&mut ads_step, chunk),
                2 => time_chunk(&mut hand_step, chunk),
                PROBE => time_chunk(&mut probe_call, probe_chunk),
                _ => time_chunk(&mut by_hand_step, chunk),
            };
            times[workload].push(t);
        }
    }
    Row { n: N, times }
}

/// Runs `paired` at size `n`, `None` for a size the `step` benchmark does
/// not have.
fn row(n: usize, rounds: usize) -> Option<Row> {
    Some(match n {
        2 => paired::<2, 2>(rounds),
        4 => paired::<4, 4>(rounds),
        6 => paired::<6, 6>(rounds),
        9 => paired::<9, 6>(rounds),
        12 => paired::<12, 6>(rounds),
        15 => paired::<15, 6>(rounds),
        18 => paired::<18, 6>(rounds),
        24 => paired::<24, 6>(rounds),
        32 => paired::<32, 6>(rounds),
        _ => return None,
    })
}

/// `median (rounds at or below 1 of rounds)` of the `ratios` of the rounds
/// `keep` selects (KF ÷ faster baseline: the rounds with the KF at or below
/// both).
fn ratio_of(ratios: &[f64], keep: impl Fn(usize) -> bool) -> String {
    let kept: Vec<f64> = (0..ratios.len())
        .filter(|&i| keep(i))
        .map(|i| ratios[i])
        .collect();
    let at_or_below = kept.iter().filter(|&&r| r <= 1.0).count();
    match quantile(&kept, 0.5) {
        Some(r) => format!("{r:.2} ({at_or_below} of {})", kept.len()),
        None => "no rounds".to_string(),
    }
}

/// Prints `row`, its rounds split by the probe's `fastest` round of the run.
fn print(row: &Row, fastest: f64) {
    let [kf, ads, hand, probe, _] = &row.times;
    let ratios: Vec<f64> = (0..kf.len()).map(|i| kf[i] / ads[i].min(hand[i])).collect();
    let contended = |i: usize| probe[i] > CONTENDED * fastest;
    let levels = probe_levels(probe, fastest);
    println!(
        "| {} | {} | {} | {} | {} | {} | {} | {levels} |",
        row.n,
        spread(kf, 0),
        spread(ads, 0),
        spread(hand, 0),
        ratio_of(&ratios, |_| true),
        ratio_of(&ratios, |i| !contended(i)),
        ratio_of(&ratios, contended),
    );
}

/// The sizes and the number of rounds from the command line.
fn parse(args: &[String]) -> Result<(Vec<usize>, usize), String> {
    let (rounds, rest) = parse_rounds(args)?;
    let mut sizes = Vec::new();
    for size in &rest {
        match size.parse() {
            Ok(n) if SIZES.contains(&n) => sizes.push(n),
            _ => {
                let sizes: Vec<String> = SIZES.iter().map(|n| n.to_string()).collect();
                return Err(format!(
                    "'{size}' is not a size of the step benchmark (one of {})",
                    sizes.join(", ")
                ));
            }
        }
    }
    if sizes.is_empty() {
        sizes = SIZES.to_vec();
    }
    Ok((sizes, rounds.unwrap_or(DEFAULT_ROUNDS)))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (sizes, rounds) = match parse(&args) {
        Ok(parsed) => parsed,
        Err(message) => {
            eprintln!("paired: {message}");
            eprintln!("usage: paired [SIZE ...] [--rounds R]");
            std::process::exit(2);
        }
    };
    println!("ns a step, median over rounds (10th–90th percentile); {rounds} rounds a size");
    println!(
        "KF ÷ faster baseline: median over rounds (rounds with the KF at or below both, of rounds)"
    );
    println!(
        "contended: the probe took more than {CONTENDED} × its fastest round of the run; probe: its 10th–90th percentile ÷ its fastest"
    );
    println!();
    println!("| n | kf | adskalman | nalgebra | KF ÷ faster | uncontended | contended | probe |");
    println!("|---|---|---|---|---|---|---|---|");
    // Printed once every size has run: the split takes the probe's fastest
    // round over all of them. (`parse` admits only sizes `row` has.)
    let rows: Vec<Row> = sizes.iter().filter_map(|&n| row(n, rounds)).collect();
    let fastest = rows
        .iter()
        .flat_map(|r| r.times[PROBE].iter().copied())
        .fold(f64::INFINITY, f64::min);
    for r in &rows {
        print(r, fastest);
    }
    for r in rows.iter().filter(|r| !r.times[BY_HAND].is_empty()) {
        print_by_hand(r, fastest);
    }
}

/// The checked step by hand's time at 2 states, its ratio to adskalman's in
/// the same round over all, the uncontended and the contended rounds (with
/// the rounds in which it was at or below adskalman), and the KF's ratio
/// to it, split alike.
fn print_by_hand(row: &Row, fastest: f64) {
    let [kf, ads, _, probe, by_hand] = &row.times;
    let contended = |i: usize| probe[i] > CONTENDED * fastest;
    let to_ads: Vec<f64> = (0..by_hand.len()).map(|i| by_hand[i] / ads[i]).collect();
    let kf_to_it: Vec<f64> = (0..by_hand.len()).map(|i| kf[i] / by_hand[i]).collect();
    println!();
    println!(
        "{} states, the step by hand with the library's checks: {} ns; ÷ adskalman {}, uncontended {}, contended {}; KF ÷ it {}, uncontended {}, contended {}",
        row.n,
        spread(by_hand, 0),
        ratio_of(&to_ads, |_| true),
        ratio_of(&to_ads, |i| !contended(i)),
        ratio_of(&to_ads, contended),
        ratio_of(&kf_to_it, |_| true),
        ratio_of(&kf_to_it, |i| !contended(i)),
        ratio_of(&kf_to_it, contended),
    );
}
