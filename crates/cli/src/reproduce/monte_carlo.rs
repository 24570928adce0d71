//! Running every filter of a scenario over many seeds, in parallel.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use kestrel::nav::experiment::{run_together, EpochRecord, RunError, RunOptions, RunSummary};
use kestrel::nav::scenario::Scenario;
use rayon::prelude::*;

use super::window::{Window, WindowError, WindowProbe};
use crate::CliError;

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
    /// Show a progress bar on stderr (only drawn when stderr is a terminal).
    pub progress: bool,
}

/// One run's result.
pub type RunOutcome = Result<(RunSummary, Vec<WindowError>), RunError>;

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
/// position error in `windows` (see [`WindowProbe`]).
///
/// The result is the same for any number of threads: every run is an
/// independent job (its filters share one simulation of the data, see
/// [`run_together`]) and its results are stored by index. A filter that
/// fails in a run is recorded as such and the others go on.
///
/// # Errors
/// [`CliError::Failed`] if the thread pool cannot be built or `runs` is 0.
pub fn run_monte_carlo(
    scenario: &Scenario,
    plan: &MonteCarloPlan,
    windows: &[Window],
) -> Result<Vec<FilterOutcome>, CliError> {
    if plan.runs == 0 {
        return Err(CliError::Failed("--runs must be at least 1".into()));
    }
    let pool = worker_pool(plan.threads)?;
    let filters = &scenario.filters;
    let bar = progress_bar(scenario, filters.len() * plan.runs, plan.progress);
    let options = RunOptions {
        duration: plan.duration,
        ..RunOptions::default()
    };
    // One job per run: its filters share one simulation of the data.
    let results: Vec<Vec<(RunOutcome, Vec<EpochRecord>)>> = pool.install(|| {
        (0..plan.runs)
            .into_par_iter()
            .map(|r| {
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
                bar.inc(filters.len() as u64);
                match outcomes {
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
                }
            })
            .collect()
    });
    bar.finish_and_clear();
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
pub(super) fn worker_pool(threads: usize) -> Result<rayon::ThreadPool, CliError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::Failed(format!("cannot start worker threads: {e}")))
}

fn progress_bar(scenario: &Scenario, jobs: usize, visible: bool) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(
        Some(jobs as u64),
        if visible {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    if let Ok(style) = ProgressStyle::with_template(
        "{prefix} [{bar:30}] {pos}/{len} runs  {elapsed_precise} elapsed, ~{eta} left",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(format!("scenario {}", scenario.name));
    bar
}
