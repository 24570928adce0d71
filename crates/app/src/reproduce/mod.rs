//! `reproduce` and `run`: Monte Carlo runs of a scenario's filters,
//! tables beside the papers' numbers, the consistency check and the
//! sensitivity study, as a [`Reproduction`] a front end prints, writes
//! ([`Reproduction::write`]) and draws.

mod consistency;
mod federated;
mod metric;
mod monte_carlo;
mod paper;
mod report;
mod sensitivity;
mod stats;
mod table;
mod verdict;
mod window;

use std::path::PathBuf;

use crate::experiment::PositionAxes;
use crate::scenario::{tuned, variants, FilterKind, MeasurementKind, Scenario, STUDY_SEEDS_FROM};

pub use consistency::{
    anees_band, nees_rows, nees_table, Anees, NeesRow, Reading, CONSISTENT_SHARE, SETTLING_SHARE,
};
pub use federated::{federated_section, largest_difference, precision_section};
pub use metric::Metric;
pub use monte_carlo::{run_monte_carlo, FilterOutcome, MonteCarloPlan, RunOutcome};
pub use paper::{paper, Paper, PaperRow, PaperTable, PAPERS};
pub use report::{scale_table, text_report, write_runs_csv, write_summary_csv, ReportInput};
pub use sensitivity::{
    run_study, study_disclosure, study_table, write_study_csv, StudyPlan, StudyRow, STUDY_METRICS,
};
pub use stats::{quantile, MeanStd, Quartiles};
pub use table::TextTable;
pub use verdict::{
    decide, from_headline, from_study, Basis, Comparison, Evidence, Outcome, Verdict,
};
pub use window::{Window, WindowError, WindowProbe};

use crate::output::write_epochs_csv;
use crate::progress::{Cancellable, Progress};
use crate::transaction::{Cancel, Transaction};
use crate::Error;

/// The most Monte Carlo runs a reproduction accepts.
pub const MAX_RUNS: usize = 10_000;

/// The most seeds per variant of the sensitivity study.
pub const MAX_STUDY_RUNS: usize = 1_000;

/// Seeds of the fault-free consistency runs (at most; fewer with fewer
/// runs): the Monte Carlo the ANEES averages over.
pub const CONSISTENCY_RUNS: usize = 20;

/// The most worker threads a reproduction accepts.
pub const MAX_THREADS: usize = 256;

/// How a scenario is reproduced.
#[derive(Clone, Debug)]
pub struct ReproduceOptions {
    /// Monte Carlo runs per filter (1 to [`MAX_RUNS`]); run `i` draws its
    /// sensor noise from `seed + i`.
    pub runs: usize,
    /// Seed of run 0 (`None`: the scenario's own seed).
    pub seed: Option<u64>,
    /// Worker threads (0: one per core, at most [`MAX_THREADS`]). The
    /// results do not depend on it.
    pub threads: usize,
    /// Simulate only the first seconds of each run (`None`: all of it).
    pub duration: Option<f64>,
    /// Seeds per variant of the sensitivity study (0 skips it; papers
    /// only).
    pub study_runs: usize,
    /// Stops the reproduction when set: no run starts after that and
    /// [`reproduce_scenario`] returns [`Error::Cancelled`].
    pub cancel: Cancel,
}

impl Default for ReproduceOptions {
    fn default() -> Self {
        Self {
            runs: 20,
            seed: None,
            threads: 0,
            duration: None,
            study_runs: 10,
            cancel: Cancel::default(),
        }
    }
}

/// A scenario's reproduction: every run's outcome, the checks and the
/// study, and the report text made from them.
#[derive(Clone, Debug)]
pub struct Reproduction {
    /// The scenario that was run.
    pub scenario: Scenario,
    /// The paper, for a built-in scenario reproduced as a paper.
    pub paper: Option<&'static Paper>,
    /// How it was run.
    pub plan: MonteCarloPlan,
    /// The outcome per filter, the scenario's first, then the tuned
    /// configuration's (labels ending in ` (tuned)`).
    pub outcomes: Vec<FilterOutcome>,
    /// The sensitivity study's rows (papers only; empty when skipped).
    pub study: Vec<StudyRow>,
    /// The text report.
    pub text: String,
}

/// Reproduces `scenario`: its Monte Carlo runs, and for a paper also the
/// tuned configuration, the consistency check and the sensitivity study
/// of `options.study_runs` seeds per variant; the report text is built
/// from them.
///
/// # Errors
/// [`Error::Failed`] for options out of range or worker threads that
/// cannot start; [`Error::Cancelled`] once `options.cancel` is set or
/// `progress` asks the runs to stop. A filter that diverges is reported in
/// the tables, not as an error.
pub fn reproduce_scenario(
    scenario: &Scenario,
    paper: Option<&'static Paper>,
    options: &ReproduceOptions,
    progress: &mut (dyn Progress + Send),
) -> Result<Reproduction, Error> {
    if let Some(d) = options.duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(Error::Failed(format!(
            "--duration must be a positive number of seconds, got {d}"
        )));
    }
    let plan = MonteCarloPlan {
        runs: options.runs,
        seed: options.seed.unwrap_or(scenario.seed),
        threads: options.threads,
        duration: options.duration,
    };
    let windows: Vec<Window> = paper
        .map(|p| p.windows.iter().map(|(_, w)| *w).collect())
        .unwrap_or_default();
    progress.stage(&format!("scenario {}", scenario.name));
    let progress = &mut Cancellable::new(progress, &options.cancel);
    let mut outcomes = run_monte_carlo(scenario, &plan, &windows, progress)?;
    // The configuration with competently tuned baselines, beside the
    // paper's.
    let tuned = paper.and_then(|_| tuned(&scenario.name));
    if let Some(t) = &tuned {
        let mut more = run_monte_carlo(t, &plan, &windows, progress)?;
        for o in &mut more {
            o.label = format!("{} (tuned)", o.label);
        }
        outcomes.extend(more);
    }
    let mut text = text_report(&ReportInput {
        scenario,
        plan: &plan,
        outcomes: &outcomes,
        paper,
    });
    if scenario.name == "001" && paper.is_some() {
        text.push_str(&federated_section(&outcomes));
        text.push_str(&precision_section(scenario, plan.seed, plan.duration));
    }
    let mut study = Vec::new();
    if let Some(p) = paper {
        let mut configs = vec![("", scenario)];
        if let Some(t) = &tuned {
            configs.push((" (tuned)", t));
        }
        let seeds = plan.seed
            ..plan
                .seed
                .saturating_add(plan.runs.min(CONSISTENCY_RUNS) as u64);
        progress.stage(&format!(
            "scenario {}: consistency check, then the sensitivity study ({} seeds per variant)…",
            scenario.name, options.study_runs
        ));
        let rows = nees_rows(
            &configs,
            seeds.clone(),
            plan.threads,
            plan.duration,
            &options.cancel,
        )?;
        text.push_str(&nees_table(&rows, seeds));
        let study_plan = StudyPlan {
            runs: options.study_runs,
            threads: plan.threads,
            duration: plan.duration,
        };
        study = run_study(&scenario.name, &study_plan, &options.cancel)?;
        text.push_str(&study_table(&study));
        for note in p.notes {
            text.push_str(&format!("note: {note}\n"));
        }
        // The disclosures are reviewed text: their numbers come from the
        // runs named in them, not from this run's tables.
        for note in p.disclosures {
            text.push_str(&format!("disclosure: {note}\n"));
        }
        if let Some(d) = study_disclosure(&study) {
            text.push_str(&format!("disclosure: {d}\n"));
        }
        text.push_str(&verdict_text(scenario, p, &plan, &outcomes, &study));
    }
    Ok(Reproduction {
        scenario: scenario.clone(),
        paper,
        plan,
        outcomes,
        study,
        text,
    })
}

/// The computed verdict of `paper` (from the study, or from the headline
/// runs when it was skipped) and the reviewed reading beside it.
fn verdict_text(
    scenario: &Scenario,
    paper: &Paper,
    plan: &MonteCarloPlan,
    outcomes: &[FilterOutcome],
    study: &[StudyRow],
) -> String {
    let computed = if study.is_empty() {
        // The paper's baseline is the headline variant's first filter.
        let baseline = variants(&scenario.name)
            .into_iter()
            .find(|v| v.headline)
            .map_or(scenario.filters[0], |v| v.scenario.filters[0]);
        let n = scenario.filters.len();
        let skip = scenario
            .filters
            .iter()
            .position(|k| *k == baseline)
            .unwrap_or(0);
        let seeds = plan.seed..plan.seed.saturating_add(plan.runs as u64);
        let why = if variants(&scenario.name).is_empty() {
            "this paper has no study variants"
        } else {
            "the study was skipped"
        };
        from_headline(&outcomes[skip..], n - skip, seeds, why)
    } else {
        from_study(study, STUDY_SEEDS_FROM)
    };
    match computed {
        Some(v) => format!(
            "{}reading (as reviewed on the full-length runs and study seeds 2000–2009, not recomputed): {}\n",
            v.text(),
            paper.verdict
        ),
        None => format!(
            "verdict (not computed: no comparison over seeds): {}\n",
            paper.verdict
        ),
    }
}

impl Reproduction {
    /// The report's inputs.
    pub fn report_input(&self) -> ReportInput<'_> {
        ReportInput {
            scenario: &self.scenario,
            plan: &self.plan,
            outcomes: &self.outcomes,
            paper: self.paper,
        }
    }

    /// The axes of the position errors (the paper's).
    pub fn axes(&self) -> PositionAxes {
        PositionAxes::for_scenario(&self.scenario.name)
    }

    /// Writes `summary.csv`, `runs.csv`, one `epochs_<filter>.csv` per
    /// filter (run 0), `sensitivity.csv` (with a study) and `report.txt`
    /// into the output transaction `tx` (published when it commits);
    /// returns their final paths in that order.
    ///
    /// # Errors
    /// [`Error::Io`] naming a file that cannot be written.
    pub fn write(&self, tx: &mut Transaction) -> Result<Vec<PathBuf>, Error> {
        let input = self.report_input();
        let mut names = Vec::new();
        write_summary_csv(&tx.path("summary.csv")?, &input)?;
        names.push("summary.csv".to_owned());
        write_runs_csv(&tx.path("runs.csv")?, &input)?;
        names.push("runs.csv".to_owned());
        for o in &self.outcomes {
            let name = format!("epochs_{}.csv", slug(&o.label));
            write_epochs_csv(&tx.path(&name)?, self.axes(), &o.records)?;
            names.push(name);
        }
        if !self.study.is_empty() {
            write_study_csv(&tx.path("sensitivity.csv")?, &self.study)?;
            names.push("sensitivity.csv".to_owned());
        }
        let report = tx.path("report.txt")?;
        std::fs::write(&report, &self.text).map_err(|e| Error::io(&report, e))?;
        names.push("report.txt".to_owned());
        Ok(names.iter().map(|n| tx.out().join(n)).collect())
    }

    /// The measurement size every filter updates with, for the NIS bound
    /// (`None` for federated filters, whose locals differ).
    pub fn nis_dof(&self) -> Option<usize> {
        nis_dof(&self.scenario)
    }

    /// The filters that failed in some runs: (label, failed runs, runs).
    pub fn failures(&self) -> Vec<(&str, usize, usize)> {
        self.outcomes
            .iter()
            .filter_map(|o| {
                let failed = o.failures().count();
                (failed > 0).then_some((o.label.as_str(), failed, o.runs.len()))
            })
            .collect()
    }
}

/// The measurement size every filter of `s` updates with, for the NIS
/// bound (`None` for federated filters, whose locals differ).
fn nis_dof(s: &Scenario) -> Option<usize> {
    let federated = s.filters.iter().any(|k| {
        matches!(
            k,
            FilterKind::FederatedUkf { .. } | FilterKind::FederatedSrUkf { .. }
        )
    });
    if federated {
        return None;
    }
    Some(match s.filter.measurement {
        MeasurementKind::GnssPositionVelocity => 6,
        MeasurementKind::AttitudeVelocityPosition => 9,
        MeasurementKind::OdometerVelocity => 3,
    })
}

/// A file-name-safe form of a label: lower case, runs of other characters
/// replaced by one `-`.
///
/// ```
/// assert_eq!(kestrel_app::reproduce::slug("Sage-Husa+fading"), "sage-husa-fading");
/// assert_eq!(kestrel_app::reproduce::slug("federated SR-UKF"), "federated-sr-ukf");
/// ```
pub fn slug(label: &str) -> String {
    let mut s = String::new();
    for c in label.chars() {
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('-') && !s.is_empty() {
            s.push('-');
        }
    }
    s.trim_end_matches('-').to_string()
}
