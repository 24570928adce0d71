//! Timing several workloads in turns within one process, for a machine
//! whose speed changes while it runs (the `paired` and `paired_ratios`
//! benchmarks).
//!
//! On a shared virtual machine a process runs slower for tens to hundreds
//! of milliseconds at a time. A criterion run times one benchmark after
//! another, so the two cells of a ratio can fall one in a slow period and
//! the other not. Here each round times one chunk of about a millisecond
//! of each workload, in an order that rotates from round to round, and a
//! ratio is taken within the round, so both of its terms see the same
//! periods.
//!
//! The slow periods are the machine's: a physical core shared with another
//! program's thread runs fewer instructions per cycle for each, and code
//! that keeps many instructions in flight loses more than code that waits
//! on one dependent chain. Each round therefore also times a [`Probe`]:
//! independent integer and float operations with no memory traffic, which
//! slowed by 1.4–1.5 × in such periods (`docs/notes/benchmark-rounds.md`).
//! A round whose probe took more than [`CONTENDED`] × the probe's fastest
//! round of the run counts as contended. When no round of a run was
//! uncontended the fastest is a contended one and the split says nothing:
//! the probe's spread over its fastest round then stays near 1.

use std::hint::black_box;
use std::time::Instant;

/// The time a chunk of a workload is sized to.
pub const CHUNK_NANOS: f64 = 1.0e6;

/// A round whose probe took more than this many times the probe's fastest
/// round is contended. The probe's two levels are 1.4–1.5 × apart, and
/// within a level its rounds scatter by about a tenth.
pub const CONTENDED: f64 = 1.2;

/// The most rounds accepted (one to two hours a run).
pub const MAX_ROUNDS: usize = 1_000_000;

/// Sixteen passes over twelve independent integer chains and sixteen
/// independent float sums: as many instructions in flight as the core
/// takes, none waiting on memory or on a long chain, so its time follows
/// the core's throughput, not its latency.
pub struct Probe {
    ints: [u64; 12],
    floats: [f64; 16],
}

impl Probe {
    pub fn new() -> Self {
        Self {
            ints: core::array::from_fn(|i| i as u64),
            floats: [1.0; 16],
        }
    }

    /// Out of line: one copy of the code for every caller, so its times
    /// compare across sizes (inlined into each size's timing loop, its
    /// registers were allocated differently: 2.5–3.9 × at 32 states).
    #[inline(never)]
    pub fn call(&mut self) {
        for _ in 0..16 {
            for (i, a) in self.ints.iter_mut().enumerate() {
                *a = a.wrapping_add(i as u64) ^ 0x55;
            }
            for a in &mut self.floats {
                *a += 1.0;
            }
            // Opaque between passes, so the compiler neither folds the
            // passes together nor keeps more than one pass's work.
            self.ints = black_box(self.ints);
            self.floats = black_box(self.floats);
        }
    }
}

/// The `q`-quantile of `v` (nearest rank), or `None` when `v` is empty.
pub fn quantile(v: &[f64], q: f64) -> Option<f64> {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let last = s.len().checked_sub(1)?;
    s.get((q * last as f64).round() as usize).copied()
}

/// `median (p10–p90)` of `v` with `digits` decimals.
pub fn spread(v: &[f64], digits: usize) -> String {
    match (quantile(v, 0.5), quantile(v, 0.1), quantile(v, 0.9)) {
        (Some(m), Some(lo), Some(hi)) => format!("{m:.digits$} ({lo:.digits$}–{hi:.digits$})"),
        _ => "no rounds".to_string(),
    }
}

/// The probe's 10th–90th percentile over its `fastest` round.
pub fn probe_levels(probe: &[f64], fastest: f64) -> String {
    match (quantile(probe, 0.1), quantile(probe, 0.9)) {
        (Some(lo), Some(hi)) => format!("{:.2}–{:.2}", lo / fastest, hi / fastest),
        _ => "no rounds".to_string(),
    }
}

/// A Markdown table of one row: each workload's median over rounds with its
/// 10th and 90th percentiles, in whole nanoseconds.
pub fn print_medians(names: &[&str], times: &[Vec<f64>]) {
    println!("| {} |", names.join(" | "));
    println!("|{}", "---|".repeat(names.len()));
    let cells: Vec<String> = times.iter().map(|t| spread(t, 0)).collect();
    println!("| {} |", cells.join(" | "));
}

/// Nanoseconds a step of `steps` calls of `step`. Generic, so each workload
/// is timed by its own instance with its step inlined into the loop, as in
/// a criterion benchmark.
pub fn time_chunk(step: &mut impl FnMut(), steps: usize) -> f64 {
    let start = Instant::now();
    for _ in 0..steps {
        step();
    }
    start.elapsed().as_nanos() as f64 / steps as f64
}

/// Steps of `step` that take about [`CHUNK_NANOS`] (doubling from one).
pub fn chunk_steps(step: &mut impl FnMut()) -> usize {
    steps_for_chunk(&mut |steps| time_chunk(step, steps))
}

/// Steps that take about [`CHUNK_NANOS`] by `timed` (nanoseconds a step of
/// a chunk of the given length), doubling from one.
fn steps_for_chunk(timed: &mut dyn FnMut(usize) -> f64) -> usize {
    let mut steps = 1;
    while timed(steps) * (steps as f64) < CHUNK_NANOS && steps < 1 << 24 {
        steps *= 2;
    }
    steps
}

/// A workload for [`take_turns`]: times a chunk of the given number of
/// steps and returns nanoseconds a step, as `|n| time_chunk(&mut step, n)`
/// does. One dynamic call a chunk; the steps inside are the closure's own.
pub type Timed<'a> = &'a mut dyn FnMut(usize) -> f64;

/// `rounds` rounds of the workloads in turns: each round times one chunk
/// of about [`CHUNK_NANOS`] of every workload, starting one workload later
/// than the round before, so that no workload always follows the same
/// one. Per workload, in the order given, its nanoseconds a step in each
/// round.
pub fn take_turns<const W: usize>(rounds: usize, mut workloads: [Timed<'_>; W]) -> [Vec<f64>; W] {
    let chunks: [usize; W] = core::array::from_fn(|w| steps_for_chunk(&mut *workloads[w]));
    let mut times: [Vec<f64>; W] = core::array::from_fn(|_| Vec::with_capacity(rounds));
    for round in 0..rounds {
        for k in 0..W {
            let w = (round + k) % W;
            times[w].push((workloads[w])(chunks[w]));
        }
    }
    times
}

/// The rounds `--rounds` asks for, `default` without it; for any other
/// argument, or a bad value, a message naming it and `usage` on standard
/// error, and exit code 2. `name` is the benchmark's.
pub fn rounds_or_exit(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = format!("usage: {name} [--rounds R]");
    match parse_rounds(&args) {
        Ok((rounds, rest)) if rest.is_empty() => rounds.unwrap_or(default),
        Ok((_, rest)) => {
            eprintln!("{name}: unexpected argument '{}'", rest[0]);
            eprintln!("{usage}");
            std::process::exit(2);
        }
        Err(message) => {
            eprintln!("{name}: {message}");
            eprintln!("{usage}");
            std::process::exit(2);
        }
    }
}

/// The value of `--rounds` (`None`: the flag is absent; `cargo bench` adds
/// `--bench`, which is skipped) and the other arguments in order.
pub fn parse_rounds(args: &[String]) -> Result<(Option<usize>, Vec<String>), String> {
    let mut rounds = None;
    let mut rest = Vec::new();
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--bench" => {}
            "--rounds" => {
                let value = it.next().ok_or("--rounds needs a number")?;
                rounds = Some(
                    value
                        .parse()
                        .ok()
                        .filter(|r| (1..=MAX_ROUNDS).contains(r))
                        .ok_or(format!(
                            "--rounds {value}: the number of rounds must be 1 to {MAX_ROUNDS}"
                        ))?,
                );
            }
            other => rest.push(other.to_string()),
        }
    }
    Ok((rounds, rest))
}
