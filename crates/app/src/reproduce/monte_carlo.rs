//! Running every filter of a scenario over many seeds, in parallel.

use std::sync::Mutex;

use crate::experiment::{run_together, EpochRecord, RunError, RunOptions, RunSummary};
use crate::scenario::Scenario;
use rayon::prelude::*;

use super::window::{Window, WindowError, WindowProbe};
use crate::progress::Progress;
use crate::Error;

/// How a Monte Carlo is run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MonteCarloPlan {
    /// Number of runs per filter (each with its own sensor noise).
    pub runs: usize,
    /// Seed of run 0; run `i` uses `seed + i`, so the data of a run does not
    /// depend on how many runs or threads there are.
    pub seed: u64,
    /// Worker threads; 0 lets rayon choose (one per core).
    pub threads: usize,
    /// Simulated duration, seconds (`None`: the scenario's whole trajectory).
    pub duration: Option<f64>,
}

/// One run's result.
pub type RunOutcome = Result<(RunSummary, Vec<WindowError>), RunError>;

/// One run's outcome per filter, with run 0's epoch records.
type RunResults = Vec<(RunOutcome, Vec<EpochRecord>)>;

/// The outcome of one filter over all runs.
#[derive(Clone, Debug)]
pub struct FilterOutcome {
    /// The filter's label (with its configuration, e.g. `KF (tuned)`).
    pub label: String,
    /// One entry per run, in run order: its summary and the errors in the
    /// requested windows, or why it failed.
    pub runs: Vec<RunOutcome>,
    /// The aiding epochs of run 0 (empty if run 0 failed).
    pub records: Vec<EpochRecord>,
}

impl FilterOutcome {
    /// The summaries of the runs that completed.
    pub fn completed(&self) -> impl Iterator<Item = &RunSummary> {
        self.runs
            .iter()
            .filter_map(|r| r.as_ref().ok().map(|(s, _)| s))
    }

    /// Window `w`'s errors in the runs that completed.
    pub fn window(&self, w: usize) -> impl Iterator<Item = WindowError> + '_ {
        self.runs
            .iter()
            .filter_map(move |r| r.as_ref().ok().and_then(|(_, e)| e.get(w).copied()))
    }

    /// The runs that failed, as (run index, error).
    pub fn failures(&self) -> impl Iterator<Item = (usize, &RunError)> {
        self.runs
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().err().map(|e| (i, e)))
    }
}

/// Runs every filter of `scenario` `plan.runs` times, measuring the
/// position error in `windows` (see [`WindowProbe`]), telling `progress`
/// the filter runs done out of those planned.
///
/// The result is the same for any number of threads: every run is an
/// independent job (its filters share one simulation of the data, see
/// [`run_together`]) and its results are stored by index. A filter that
/// fails in a run is recorded as such and the others go on.
///
/// # Errors
/// [`Error::Failed`] if the thread pool cannot be built or `runs` is 0;
/// [`Error::Cancelled`] once `progress` asks the runs to stop (no run
/// starts after that).
pub fn run_monte_carlo(
    scenario: &Scenario,
    plan: &MonteCarloPlan,
    windows: &[Window],
    progress: &mut (dyn Progress + Send),
) -> Result<Vec<FilterOutcome>, Error> {
    if plan.runs == 0 {
        return Err(Error::Failed("--runs must be at least 1".into()));
    }
    let pool = worker_pool(plan.threads)?;
    let filters = &scenario.filters;
    progress.begin(0.0, (filters.len() * plan.runs) as f64);
    let done = Mutex::new((0usize, progress));
    let options = RunOptions {
        duration: plan.duration,
        ..RunOptions::default()
    };
    // One job per run: its filters share one simulation of the data.
    // `None` for a run not started because the reproduction was cancelled.
    let results: Vec<Option<RunResults>> = pool.install(|| {
        (0..plan.runs)
            .into_par_iter()
            .map(|r| {
                // A cancelled reproduction starts no more runs.
                if done.lock().map_or(true, |d| d.1.cancelled()) {
                    return None;
                }
                let seed = plan.seed.wrapping_add(r as u64);
                let mut probes: Vec<WindowProbe> =
                    filters.iter().map(|_| WindowProbe::new(windows)).collect();
                let mut records: Vec<Vec<EpochRecord>> =
                    filters.iter().map(|_| Vec::new()).collect();
                let outcomes = run_together(scenario, filters, seed, &options, |i, e| {
                    probes[i].add(e);
                    if r == 0 {
                        records[i].push(*e);
                    }
                });
                if let Ok(mut d) = done.lock() {
                    d.0 += filters.len();
                    let n = d.0 as f64;
                    d.1.reached(n);
                }
                Some(match outcomes {
                    Ok(outcomes) => outcomes
                        .into_iter()
                        .zip(probes)
                        .zip(records)
                        .map(|((outcome, probe), records)| match outcome {
                            Ok(summary) => (Ok((summary, probe.finish())), records),
                            Err(e) => (Err(e), Vec::new()),
                        })
                        .collect(),
                    Err(e) => filters
                        .iter()
                        .map(|_| (Err(e.clone()), Vec::new()))
                        .collect(),
                })
            })
            .collect()
    });
    if let Ok((_, progress)) = done.into_inner() {
        progress.finish();
    }
    let Some(results) = results.into_iter().collect::<Option<Vec<_>>>() else {
        return Err(Error::Cancelled);
    };
    let mut outcomes: Vec<FilterOutcome> = filters
        .iter()
        .map(|k| FilterOutcome {
            label: k.label().to_string(),
            runs: Vec::with_capacity(plan.runs),
            records: Vec::new(),
        })
        .collect();
    for (r, run) in results.into_iter().enumerate() {
        for (outcome, (summary, records)) in outcomes.iter_mut().zip(run) {
            outcome.runs.push(summary);
            if r == 0 {
                outcome.records = records;
            }
        }
    }
    Ok(outcomes)
}

/// A pool of `threads` workers (0: one per core).
pub(super) fn worker_pool(threads: usize) -> Result<rayon::ThreadPool, Error> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Failed(format!("cannot start worker threads: {e}")))
}
