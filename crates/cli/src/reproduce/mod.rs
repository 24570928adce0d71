//! `kestrel reproduce`, `kestrel run` and `kestrel scenarios`: Monte Carlo
//! runs of a scenario's filters, tables beside the papers' numbers, CSV and
//! plots.

mod consistency;
mod federated;
mod metric;
mod monte_carlo;
mod paper;
mod report;
mod sensitivity;
mod stats;
mod table;
mod window;

use std::path::{Path, PathBuf};

use clap::Args;
use kestrel::nav::experiment::PositionAxes;
use kestrel::nav::scenario::{builtin, by_name, tuned, FilterKind, MeasurementKind, Scenario};

pub use consistency::{nees_rows, nees_table, NeesRow};
pub use federated::{federated_section, largest_difference, precision_section};
pub use metric::Metric;
pub use monte_carlo::{run_monte_carlo, FilterOutcome, MonteCarloPlan, RunOutcome};
pub use paper::{paper, Paper, PaperRow, PaperTable, PAPERS};
pub use report::{text_report, write_runs_csv, write_summary_csv, ReportInput};
pub use sensitivity::{
    run_study, study_table, write_study_csv, StudyPlan, StudyRow, STUDY_METRICS,
};
pub use stats::{quantile, MeanStd, Quartiles};
pub use table::TextTable;
pub use window::{Window, WindowError, WindowProbe};

use crate::plot::{error_figures_with, sensitivity_figure, FigureOptions, FilterTrace};
use crate::CliError;
use kestrel_io::output::write_epochs_csv;

/// The most Monte Carlo runs `--runs` accepts.
pub const MAX_RUNS: usize = 10_000;

/// The most seeds per variant `--study-runs` accepts.
pub const MAX_STUDY_RUNS: usize = 1_000;

/// Seeds of the fault-free consistency runs (at most; fewer with `--runs`).
pub const CONSISTENCY_RUNS: usize = 5;

/// The most worker threads `--threads` accepts.
pub const MAX_THREADS: usize = 256;

/// Options shared by `reproduce` and `run`.
#[derive(Debug, Clone, Args)]
pub struct MonteCarloArgs {
    /// Monte Carlo runs per filter (1 to 10 000); run i draws its sensor
    /// noise from seed + i.
    #[arg(long, default_value_t = 20, value_name = "N",
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_RUNS as u64))]
    pub runs: usize,
    /// Seed of run 0 [default: the scenario's own seed].
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Output directory; each scenario writes into DIR/<scenario name>/.
    #[arg(long, default_value = "kestrel-out", value_name = "DIR")]
    pub out: PathBuf,
    /// Worker threads (0 for one per core, at most 256). The results do
    /// not depend on it.
    #[arg(long, default_value_t = 0, value_name = "K",
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(0..=MAX_THREADS as u64))]
    pub threads: usize,
    /// Simulate only the first SECONDS of each scenario [default: all of it].
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Skip the PNG/SVG figures (tables and CSV only).
    #[arg(long)]
    pub no_plots: bool,
}

/// Arguments of `kestrel reproduce`.
#[derive(Debug, Clone, Args)]
pub struct ReproduceArgs {
    /// Which paper's experiment: 000, 001, 002, 003, 004, or all.
    #[arg(value_parser = ["000", "001", "002", "003", "004", "all"])]
    pub which: String,
    #[command(flatten)]
    pub monte_carlo: MonteCarloArgs,
    /// Seeds per variant of the sensitivity study (0 to skip it, at most
    /// 1000); run i of a variant uses seed 2000 + i, disjoint from the
    /// seeds the scenarios were tuned on and from the tests'.
    #[arg(long, default_value_t = 10, value_name = "N",
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(0..=MAX_STUDY_RUNS as u64))]
    pub study_runs: usize,
}

/// Arguments of `kestrel run`.
#[derive(Debug, Clone, Args)]
pub struct RunArgs {
    /// The scenario file (TOML; see the examples in scenarios/).
    pub scenario: PathBuf,
    #[command(flatten)]
    pub monte_carlo: MonteCarloArgs,
}

/// Runs `kestrel reproduce`.
///
/// # Errors
/// [`CliError`] with a one-line cause: bad options, or an output file that
/// cannot be written. A filter that diverges is reported in the tables, not
/// as an error.
pub fn reproduce(args: &ReproduceArgs) -> Result<(), CliError> {
    let scenarios: Vec<Scenario> = if args.which == "all" {
        builtin().into()
    } else {
        let s = by_name(&args.which)
            .ok_or_else(|| CliError::Failed(format!("no built-in scenario `{}`", args.which)))?;
        vec![s]
    };
    let mut study = Vec::new();
    for s in &scenarios {
        study.extend(execute(
            s,
            paper(&s.name),
            &args.monte_carlo,
            args.study_runs,
        )?);
    }
    if !study.is_empty() {
        let mc = &args.monte_carlo;
        std::fs::create_dir_all(&mc.out).map_err(|e| CliError::io(&mc.out, e))?;
        let csv = mc.out.join("sensitivity.csv");
        write_study_csv(&csv, &study)?;
        let mut files = vec![csv];
        if !mc.no_plots {
            files.extend(sensitivity_figure(&mc.out, "sensitivity", &study, 0)?);
        }
        let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
        println!("sensitivity study: wrote {}\n", names.join(", "));
    }
    Ok(())
}

/// Runs `kestrel run`.
///
/// # Errors
/// As [`reproduce`], and [`CliError::Input`] for a bad scenario file.
pub fn run_file(args: &RunArgs) -> Result<(), CliError> {
    let scenario = crate::scenario_file::load(&args.scenario)?;
    execute(&scenario, None, &args.monte_carlo, 0).map(|_| ())
}

/// Runs `kestrel scenarios`: prints each built-in scenario with a one-line
/// description.
///
/// # Errors
/// Never.
pub fn list_scenarios() -> Result<(), CliError> {
    for s in builtin() {
        println!("{}  {}", s.name, s.description);
    }
    Ok(())
}

/// Runs one scenario, prints its report and writes its files; for a paper
/// also its tuned configuration, the consistency check and the
/// sensitivity study of `study_runs` seeds per variant, whose rows it
/// returns.
fn execute(
    scenario: &Scenario,
    paper: Option<&Paper>,
    args: &MonteCarloArgs,
    study_runs: usize,
) -> Result<Vec<StudyRow>, CliError> {
    if let Some(d) = args.duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(CliError::Failed(format!(
            "--duration must be a positive number of seconds, got {d}"
        )));
    }
    let plan = MonteCarloPlan {
        runs: args.runs,
        seed: args.seed.unwrap_or(scenario.seed),
        threads: args.threads,
        duration: args.duration,
        progress: true,
    };
    let windows: Vec<Window> = paper
        .map(|p| p.windows.iter().map(|(_, w)| *w).collect())
        .unwrap_or_default();
    let mut outcomes = run_monte_carlo(scenario, &plan, &windows)?;
    // The configuration with competently tuned baselines, beside the
    // paper's.
    let tuned = paper.and_then(|_| tuned(&scenario.name));
    if let Some(t) = &tuned {
        let mut more = run_monte_carlo(t, &plan, &windows)?;
        for o in &mut more {
            o.label = format!("{} (tuned)", o.label);
        }
        outcomes.extend(more);
    }
    let input = ReportInput {
        scenario,
        plan: &plan,
        outcomes: &outcomes,
        paper,
    };
    let mut text = text_report(&input);
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
        if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            eprintln!(
                "scenario {}: consistency check, then the sensitivity study ({study_runs} seeds per variant)…",
                scenario.name
            );
        }
        let rows = nees_rows(&configs, seeds.clone(), args.threads, args.duration)?;
        text.push_str(&nees_table(&rows, seeds));
        let study_plan = StudyPlan {
            runs: study_runs,
            threads: args.threads,
            duration: args.duration,
        };
        study = run_study(&scenario.name, &study_plan)?;
        text.push_str(&study_table(&study));
        for note in p.notes {
            text.push_str(&format!("note: {note}\n"));
        }
        for note in p.disclosures {
            text.push_str(&format!("disclosure: {note}\n"));
        }
        text.push_str(&format!(
            "verdict (of the full-length runs and study): {}\n",
            p.verdict
        ));
    }
    let dir = args.out.join(slug(&scenario.name));
    std::fs::create_dir_all(&dir).map_err(|e| CliError::io(&dir, e))?;
    let mut written = write_outputs(&dir, &input, !args.no_plots)?;
    if !study.is_empty() {
        write_study_csv(&dir.join("sensitivity.csv"), &study)?;
        written += 1;
    }
    let report = dir.join("report.txt");
    std::fs::write(&report, &text).map_err(|e| CliError::io(&report, e))?;
    println!("{text}");
    println!(
        "wrote {} files to {} (report.txt, summary.csv, runs.csv, epochs_*.csv{}{})\n",
        written + 1,
        dir.display(),
        if study.is_empty() {
            ""
        } else {
            ", sensitivity.csv"
        },
        if args.no_plots { "" } else { ", *.png, *.svg" }
    );
    for o in &outcomes {
        let failed = o.failures().count();
        if failed > 0 {
            eprintln!(
                "kestrel: warning: {} failed in {failed} of {} runs of scenario {} (see the report)",
                o.label,
                o.runs.len(),
                scenario.name
            );
        }
    }
    Ok(study)
}

/// Writes summary.csv, runs.csv, one epochs CSV per filter (run 0) and the figures;
/// returns the number of files written.
fn write_outputs(dir: &Path, input: &ReportInput<'_>, plots: bool) -> Result<usize, CliError> {
    let axes = PositionAxes::for_scenario(&input.scenario.name);
    write_summary_csv(&dir.join("summary.csv"), input)?;
    write_runs_csv(&dir.join("runs.csv"), input)?;
    let mut files = 2;
    for o in input.outcomes {
        write_epochs_csv(
            &dir.join(format!("epochs_{}.csv", slug(&o.label))),
            axes,
            &o.records,
        )?;
        files += 1;
    }
    if plots {
        let traces: Vec<FilterTrace<'_>> = input
            .outcomes
            .iter()
            .map(|o| FilterTrace {
                label: &o.label,
                records: &o.records,
            })
            .collect();
        let title = format!(
            "scenario {}: {}",
            input.scenario.name, input.scenario.description
        );
        let options = FigureOptions {
            nis_dof: nis_dof(input.scenario),
            ..FigureOptions::default()
        };
        files += error_figures_with(dir, &title, axes, &traces, &options)?.len();
    }
    Ok(files)
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
/// assert_eq!(kestrel_cli::reproduce::slug("Sage-Husa+fading"), "sage-husa-fading");
/// assert_eq!(kestrel_cli::reproduce::slug("federated SR-UKF"), "federated-sr-ukf");
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
