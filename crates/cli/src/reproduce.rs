//! `kestrel reproduce`, `kestrel run` and `kestrel scenarios`: the
//! arguments, the report on stdout, the files and the figures around
//! [`kestrel_app::reproduce`].

use std::path::{Path, PathBuf};

use clap::Args;
use kestrel_app::reproduce::{
    paper, reproduce_scenario, slug, write_study_csv, Paper, ReproduceOptions, Reproduction,
    StudyRow, MAX_RUNS, MAX_STUDY_RUNS, MAX_THREADS,
};
use kestrel_app::scenario::{builtin, by_name, Scenario};

use crate::plot::{error_figures_with, sensitivity_figure, FigureOptions, FilterTrace};
use crate::progress::Bar;
use crate::CliError;

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

impl MonteCarloArgs {
    /// The library's options with `study_runs` seeds per study variant.
    fn options(&self, study_runs: usize) -> ReproduceOptions {
        ReproduceOptions {
            runs: self.runs,
            seed: self.seed,
            threads: self.threads,
            duration: self.duration,
            study_runs,
        }
    }
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
        let options = args.monte_carlo.options(args.study_runs);
        study.extend(execute(s, paper(&s.name), &args.monte_carlo, &options)?);
    }
    if !study.is_empty() {
        write_study(&args.monte_carlo, &study)?;
    }
    Ok(())
}

/// The sensitivity study of every scenario reproduced: its CSV and figure
/// in the output folder.
fn write_study(mc: &MonteCarloArgs, study: &[StudyRow]) -> Result<(), CliError> {
    std::fs::create_dir_all(&mc.out).map_err(|e| CliError::io(&mc.out, e))?;
    let csv = mc.out.join("sensitivity.csv");
    write_study_csv(&csv, study)?;
    let mut files = vec![csv];
    if !mc.no_plots {
        files.extend(sensitivity_figure(&mc.out, "sensitivity", study, 0)?);
    }
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    println!("sensitivity study: wrote {}\n", names.join(", "));
    Ok(())
}

/// Runs `kestrel run`.
///
/// # Errors
/// As [`reproduce`], and [`CliError::Input`] for a bad scenario file.
pub fn run_file(args: &RunArgs) -> Result<(), CliError> {
    let scenario = kestrel_app::config::scenario::load(&args.scenario)?;
    let options = args.monte_carlo.options(0);
    execute(&scenario, None, &args.monte_carlo, &options).map(|_| ())
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

/// Reproduces one scenario, writes its files and figures and prints its
/// report; returns its sensitivity study's rows.
fn execute(
    scenario: &Scenario,
    paper: Option<&'static Paper>,
    args: &MonteCarloArgs,
    options: &ReproduceOptions,
) -> Result<Vec<StudyRow>, CliError> {
    let r = reproduce_scenario(scenario, paper, options, &mut Bar::runs())?;
    let dir = args.out.join(slug(&scenario.name));
    let mut written = r.write(&dir)?.len();
    if !args.no_plots {
        written += figures(&dir, &r)?.len();
    }
    println!("{}", r.text);
    println!(
        "wrote {written} files to {} (report.txt, summary.csv, runs.csv, epochs_*.csv{}{})\n",
        dir.display(),
        if r.study.is_empty() {
            ""
        } else {
            ", sensitivity.csv"
        },
        if args.no_plots { "" } else { ", *.png, *.svg" }
    );
    for (label, failed, runs) in r.failures() {
        eprintln!(
            "kestrel: warning: {label} failed in {failed} of {runs} runs of scenario {} (see the report)",
            scenario.name
        );
    }
    Ok(r.study)
}

/// The error figures of a reproduction in `dir`.
fn figures(dir: &Path, r: &Reproduction) -> Result<Vec<PathBuf>, CliError> {
    let traces: Vec<FilterTrace<'_>> = r
        .outcomes
        .iter()
        .map(|o| FilterTrace {
            label: &o.label,
            records: &o.records,
        })
        .collect();
    let title = format!("scenario {}: {}", r.scenario.name, r.scenario.description);
    let options = FigureOptions {
        nis_dof: r.nis_dof(),
        ..FigureOptions::default()
    };
    error_figures_with(dir, &title, r.axes(), &traces, &options)
}
