//! The consistency check of a reproduction's filters: position NEES on the
//! fault-free form of the scenario, where a well-modelled filter's NEES is
//! χ²(3).

use std::fmt::Write as _;

use crate::experiment::{run_together, RunOptions};
use crate::scenario::{fault_free, Scenario};
use rayon::prelude::*;

use super::monte_carlo::worker_pool;
use super::table::TextTable;
use crate::process::chi_square_band;
use crate::transaction::Cancel;
use crate::Error;

/// The share of a run skipped before NEES is counted (the initial
/// convergence).
pub const SETTLING_SHARE: f64 = 0.1;

/// Mean NEES above this: the filter is over-confident (its covariance
/// does not cover its errors); below [`CONSERVATIVE_BELOW`]: conservative.
pub const OVERCONFIDENT_ABOVE: f64 = 6.0;

/// See [`OVERCONFIDENT_ABOVE`].
pub const CONSERVATIVE_BELOW: f64 = 1.0;

/// One filter's NEES over the fault-free runs.
#[derive(Clone, Debug, PartialEq)]
pub struct NeesRow {
    /// The filter's label (with its configuration).
    pub label: String,
    /// Mean position NEES over the counted epochs of every completed run.
    pub mean: Option<f64>,
    /// Share of those epochs inside the two-sided 95 % χ²(3) band.
    pub inside: Option<f64>,
    /// Epochs counted.
    pub epochs: usize,
    /// Runs that failed.
    pub failed: usize,
}

/// Runs every filter of each `(label suffix, scenario)` configuration on
/// the scenario's [`fault_free`] form for `seeds` and measures the
/// position NEES after the first [`SETTLING_SHARE`] of the run.
///
/// # Errors
/// [`Error::Failed`] if the worker threads cannot start;
/// [`Error::Cancelled`] once `cancel` is set (no run starts after that).
pub fn nees_rows(
    configs: &[(&str, &Scenario)],
    seeds: core::ops::Range<u64>,
    threads: usize,
    duration: Option<f64>,
    cancel: &Cancel,
) -> Result<Vec<NeesRow>, Error> {
    let (lo, hi) = band();
    let pool = worker_pool(threads)?;
    let clean: Vec<Scenario> = configs.iter().map(|(_, s)| fault_free(s)).collect();
    let seeds: Vec<u64> = seeds.collect();
    let options = RunOptions {
        duration,
        ..RunOptions::default()
    }
    .without_records();
    // One job per (configuration, seed): its filters share one simulation.
    let work: Vec<(usize, u64)> = (0..clean.len())
        .flat_map(|c| seeds.iter().map(move |&seed| (c, seed)))
        .collect();
    let runs: Vec<Vec<Option<NeesSums>>> = pool.install(|| {
        work.par_iter()
            .map(|&(c, seed)| {
                let s = &clean[c];
                if cancel.is_cancelled() {
                    return vec![None; s.filters.len()];
                }
                let start = duration
                    .or_else(|| s.trajectory().ok().map(|t| t.duration()))
                    .unwrap_or(0.0)
                    * SETTLING_SHARE;
                let mut sums = vec![NeesSums::default(); s.filters.len()];
                let done = run_together(s, &s.filters, seed, &options, |i, r| {
                    if let (true, Some(v)) = (r.time >= start, r.position_nees) {
                        sums[i].add(v, (lo..=hi).contains(&v));
                    }
                });
                match done {
                    Ok(done) => done
                        .iter()
                        .zip(sums)
                        .map(|(d, x)| d.is_ok().then_some(x))
                        .collect(),
                    Err(_) => vec![None; s.filters.len()],
                }
            })
            .collect()
    });
    cancel.check()?;
    let mut rows = Vec::new();
    for (c, ((suffix, _), s)) in configs.iter().zip(&clean).enumerate() {
        let of_config = &runs[c * seeds.len()..(c + 1) * seeds.len()];
        for (i, k) in s.filters.iter().enumerate() {
            // Summed over the seeds in order, as a run at a time would.
            let (mut total, mut failed) = (NeesSums::default(), 0);
            for run in of_config {
                match run[i] {
                    Some(x) => total.merge(&x),
                    None => failed += 1,
                }
            }
            let share = |x: f64| (total.epochs > 0).then(|| x / total.epochs as f64);
            rows.push(NeesRow {
                label: format!("{}{suffix}", k.label()),
                mean: share(total.sum),
                inside: share(total.inside as f64),
                epochs: total.epochs,
                failed,
            });
        }
    }
    Ok(rows)
}

/// The NEES of one filter's counted epochs: their sum, how many fell in
/// the band, how many there were.
#[derive(Clone, Copy, Debug, Default)]
struct NeesSums {
    sum: f64,
    inside: usize,
    epochs: usize,
}

impl NeesSums {
    fn add(&mut self, nees: f64, in_band: bool) {
        self.sum += nees;
        self.inside += usize::from(in_band);
        self.epochs += 1;
    }

    fn merge(&mut self, run: &NeesSums) {
        self.sum += run.sum;
        self.inside += run.inside;
        self.epochs += run.epochs;
    }
}

/// The two-sided 95 % band of χ²(3).
fn band() -> (f64, f64) {
    chi_square_band(3)
}

/// The NEES rows as a text table with a plain reading per filter.
pub fn nees_table(rows: &[NeesRow], seeds: core::ops::Range<u64>) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let (lo, hi) = band();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "consistency on the fault-free scenario (no outliers, noise changes or odometer faults), seeds {}–{}, after the first {:.0} % of each run:",
        seeds.start,
        seeds.end.saturating_sub(1),
        SETTLING_SHARE * 100.0
    );
    let mut t = TextTable::new(
        [
            "filter",
            "position NEES mean (3 expected)",
            &format!("in [{lo:.2}, {hi:.2}]"),
            "epochs",
            "failed runs",
            "reading",
        ]
        .map(String::from)
        .to_vec(),
    );
    for r in rows {
        let reading = match r.mean {
            None => "no NEES (no single covariance)",
            Some(m) if m > OVERCONFIDENT_ABOVE => "over-confident",
            Some(m) if m < CONSERVATIVE_BELOW => "conservative",
            Some(_) => "consistent",
        };
        t.row(vec![
            r.label.clone(),
            r.mean.map_or("—".into(), |m| format!("{m:.2}")),
            r.inside
                .map_or("—".into(), |s| format!("{:.0} %", 100.0 * s)),
            r.epochs.to_string(),
            r.failed.to_string(),
            reading.to_string(),
        ]);
    }
    let _ = writeln!(out, "{t}");
    let _ = writeln!(
        out,
        "   reading: mean NEES above {OVERCONFIDENT_ABOVE} over-confident, below {CONSERVATIVE_BELOW} conservative, else consistent\n"
    );
    out
}
