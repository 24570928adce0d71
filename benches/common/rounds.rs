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
//! slowed by 1.4–1.5 × in such periods (benchmark notes, fourteenth round).
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
    let mut steps = 1;
    while time_chunk(step, steps) * (steps as f64) < CHUNK_NANOS && steps < 1 << 24 {
        steps *= 2;
    }
    steps
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
