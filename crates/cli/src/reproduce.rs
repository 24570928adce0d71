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
use kestrel_app::transaction::{Begin, InputRecord, Provenance, Transaction};

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
    /// The library's options with `study_runs` seeds per study variant,
    /// stopped by `ctx`'s signals.
    fn options(&self, study_runs: usize, ctx: &crate::Context) -> ReproduceOptions {
        ReproduceOptions {
            runs: self.runs,
            seed: self.seed,
            threads: self.threads,
            duration: self.duration,
            study_runs,
            cancel: ctx.cancel.clone(),
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
/// Each scenario's folder (`DIR/<scenario>/`) is one output transaction,
/// published when its scenario is done; the study across scenarios
/// (`DIR/sensitivity.*`) is another, on `DIR` itself, held from the start
/// so a second reproduction into `DIR` is refused at once.
///
/// # Errors
/// [`CliError`] with a one-line cause: bad options, an output file that
/// cannot be written, or a filter that failed in every run (after its
/// scenario's files are written). A filter that diverges in some runs is
/// reported in the tables, not as an error.
pub fn reproduce(args: &ReproduceArgs, ctx: &crate::Context) -> Result<(), CliError> {
    let scenarios: Vec<Scenario> = if args.which == "all" {
        builtin().into()
    } else {
        let s = by_name(&args.which)
            .ok_or_else(|| CliError::Failed(format!("no built-in scenario `{}`", args.which)))?;
        vec![s]
    };
    let mut top = Transaction::begin(&args.monte_carlo.out, Begin::command(&ctx.command))?;
    let mut study = Vec::new();
    let mut failed = Vec::new();
    for s in &scenarios {
        let options = args.monte_carlo.options(args.study_runs, ctx);
        let done = execute(s, paper(&s.name), &args.monte_carlo, &options, ctx, None)?;
        study.extend(done.study);
        failed.extend(done.failed);
    }
    if !study.is_empty() {
        write_study(&args.monte_carlo, &mut top, &study)?;
        top.commit(Provenance::default())?;
    }
    every_run_failed(&failed)
}

/// The sensitivity study of every scenario reproduced: its CSV and figure
/// in the output folder.
fn write_study(
    mc: &MonteCarloArgs,
    tx: &mut Transaction,
    study: &[StudyRow],
) -> Result<(), CliError> {
    write_study_csv(&tx.path("sensitivity.csv")?, study)?;
    let mut files = vec![mc.out.join("sensitivity.csv")];
    if !mc.no_plots {
        for f in sensitivity_figure(tx.scratch_dir(), "sensitivity", study, 0)? {
            files.push(tx.adopt(&file_name(&f))?);
        }
    }
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    crate::outln!("sensitivity study: wrote {}\n", names.join(", "))?;
    Ok(())
}

/// Runs `kestrel run`.
///
/// # Errors
/// As [`reproduce`], and [`CliError::Input`] for a bad scenario file.
pub fn run_file(args: &RunArgs, ctx: &crate::Context) -> Result<(), CliError> {
    let (scenario, tally) = kestrel_app::config::scenario::load_recorded(&args.scenario)?;
    let options = args.monte_carlo.options(0, ctx);
    let input = InputRecord {
        flag: "scenario file".into(),
        path: args.scenario.display().to_string(),
        bytes: tally.bytes(),
        sha256: tally.sha256(),
    };
    let done = execute(
        &scenario,
        None,
        &args.monte_carlo,
        &options,
        ctx,
        Some((&args.scenario, input)),
    )?;
    every_run_failed(&done.failed)
}

/// An error naming the filters that failed in every run (`scenario`,
/// `filter`), if any.
fn every_run_failed(failed: &[(String, String)]) -> Result<(), CliError> {
    if failed.is_empty() {
        return Ok(());
    }
    let names: Vec<String> = failed
        .iter()
        .map(|(scenario, filter)| format!("{filter} (scenario {scenario})"))
        .collect();
    Err(CliError::Failed(format!(
        "every run of {} failed; the reports say why",
        names.join(", ")
    )))
}

/// Runs `kestrel scenarios`: prints each built-in scenario with a one-line
/// description.
///
/// # Errors
/// Never.
pub fn list_scenarios() -> Result<(), CliError> {
    for s in builtin() {
        crate::outln!("{}  {}", s.name, s.description)?;
    }
    Ok(())
}

/// What [`execute`] leaves for the caller.
struct Executed {
    /// The sensitivity study's rows.
    study: Vec<StudyRow>,
    /// The filters that failed in every run: (scenario, filter).
    failed: Vec<(String, String)>,
}

/// Reproduces one scenario, writes its files and figures through one
/// output transaction on its folder and prints its report; returns its
/// sensitivity study's rows and the filters that failed in every run.
fn execute(
    scenario: &Scenario,
    paper: Option<&'static Paper>,
    args: &MonteCarloArgs,
    options: &ReproduceOptions,
    ctx: &crate::Context,
    input: Option<(&Path, InputRecord)>,
) -> Result<Executed, CliError> {
    let dir = args.out.join(slug(&scenario.name));
    let mut begin = Begin::command(&ctx.command);
    let mut provenance = provenance(scenario, options);
    if let Some((path, record)) = input {
        begin = begin.input("scenario file", path);
        provenance.inputs.push(record);
    }
    let mut tx = Transaction::begin(&dir, begin)?;
    let r = reproduce_scenario(scenario, paper, options, &mut Bar::runs())?;
    let mut written = r.write(&mut tx)?.len();
    if !args.no_plots {
        for f in figures(tx.scratch_dir(), &r)? {
            tx.adopt(&file_name(&f))?;
            written += 1;
        }
    }
    ctx.cancel.check()?;
    tx.commit(provenance)?;
    crate::outln!("{}", r.text)?;
    crate::outln!(
        "wrote {written} files to {} (report.txt, summary.csv, runs.csv, epochs_*.csv{}{})\n",
        dir.display(),
        if r.study.is_empty() {
            ""
        } else {
            ", sensitivity.csv"
        },
        if args.no_plots { "" } else { ", *.png, *.svg" }
    )?;
    let mut failed = Vec::new();
    for (label, n, runs) in r.failures() {
        crate::errln!(
            "kestrel: warning: {label} failed in {n} of {runs} runs of scenario {} (see the report)",
            scenario.name
        )?;
        if n == runs {
            failed.push((scenario.name.clone(), label.to_owned()));
        }
    }
    Ok(Executed {
        study: r.study,
        failed,
    })
}

/// What a reproduction's manifest records beyond the command line: the
/// seeds and the options that shape the numbers.
fn provenance(scenario: &Scenario, options: &ReproduceOptions) -> Provenance {
    let seed = options.seed.unwrap_or(scenario.seed);
    Provenance {
        seeds: (0..options.runs as u64)
            .map(|i| seed.wrapping_add(i))
            .collect(),
        configuration: Some(serde_json::json!({
            "scenario": scenario.name,
            "runs": options.runs,
            "seed": seed,
            "duration_s": options.duration,
            "study_runs": options.study_runs,
        })),
        ..Provenance::default()
    }
}

/// The file name of a path the figure code returned.
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
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
