//! `kestrel process`: the arguments, the progress bar and the plots around
//! the pipeline of [`kestrel_app::process`].

use std::path::PathBuf;

use clap::Args;
use kestrel_app::process::{Inputs, OdometerInput, Outage, ProcessReport};

use crate::plot::{
    adaptation_figure, process_figures, FigureOptions, FilterTrace, ProcessPlots, SolutionErrors,
};
use crate::{CliError, Context};

pub use kestrel_app::process::summary;

/// Arguments of `kestrel process`.
#[derive(Clone, Debug, Args)]
pub struct ProcessArgs {
    /// IMU file: GNSS seconds of week, angle increments x y z (rad),
    /// velocity increments x y z (m/s), body forward-right-down, and an
    /// optional 8th column of odometer speed (m/s).
    #[arg(long, value_name = "FILE")]
    pub imu: PathBuf,
    /// GNSS file: seconds of week, latitude, longitude (deg), height (m),
    /// position σ north east down (m), optionally velocity north east down
    /// (m/s) and its σ (m/s).
    #[arg(long, value_name = "FILE")]
    pub gnss: Option<PathBuf>,
    /// Use the IMU file's 8th column as odometer speed (m/s), at the rate
    /// of the configuration's [odometer] table.
    #[arg(long)]
    pub odo: bool,
    /// Odometer file (`sow speed`, m/s): speeds at the rate of the
    /// configuration's [odometer] table (instead of --odo).
    #[arg(long, value_name = "FILE", conflicts_with = "odo")]
    pub odometer: Option<PathBuf>,
    /// Reference trajectory (week, seconds of week, lat, lon (deg), h (m),
    /// velocity NED (m/s), roll pitch yaw (deg)): errors, RMS and plots.
    #[arg(long, value_name = "FILE")]
    pub truth: Option<PathBuf>,
    /// Configuration (TOML): initial state and its σ, IMU noise, lever
    /// arm, filter, GNSS noise, odometer, output.
    #[arg(long, value_name = "FILE")]
    pub config: PathBuf,
    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR", default_value = "kestrel-process")]
    pub out: PathBuf,
    /// Ignore GNSS fixes at START ≤ t < END (seconds of week, half-open:
    /// as if those lines were deleted); repeat for several windows.
    #[arg(long = "outage", value_name = "START:END")]
    pub outages: Vec<Outage>,
    /// Do not draw the error plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Replace files in --out that no earlier kestrel run into it wrote
    /// (without it they are refused; an earlier run's files are always
    /// replaced, exactly the set its manifest lists).
    #[arg(long)]
    pub force: bool,
    /// Also smooth the run (Rauch-Tung-Striebel over the closed-loop error
    /// state): smoothed.nav, smoothed.csv, smoothed_std.csv and, with
    /// --truth, errors_smoothed.csv; the plots show both solutions.
    #[arg(long)]
    pub smooth: bool,
    /// Stop with an error (non-zero status) at the health monitor's first
    /// alarm: the NIS of a measurement kind (or, with --truth, the
    /// position NEES) beyond its χ² bound for 3 windows of 20 updates in a
    /// row. Without it an alarm is a warning in the summary.
    #[arg(long)]
    pub stop_on_divergence: bool,
}

/// Runs `kestrel process` and prints its summary.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn run(args: &ProcessArgs, ctx: &Context) -> Result<(), CliError> {
    let report = process(args, ctx)?;
    crate::out::print(&summary(&report))?;
    Ok(())
}

/// Runs the processing of `args` with a progress bar on a terminal, draws
/// the error plots (with a truth, unless `no_plots`) and returns what it
/// did (nothing printed).
///
/// # Errors
/// [`CliError`]: bad input (naming file, line, column or key), an output
/// that cannot be written, or a filter divergence (naming the time).
pub fn process(args: &ProcessArgs, ctx: &Context) -> Result<ProcessReport, CliError> {
    if args.odo && args.odometer.is_some() {
        return Err(CliError::Failed(
            "give the odometer speeds either in the IMU file (--odo) or in their own file \
             (--odometer), not both"
                .into(),
        ));
    }
    let inputs = Inputs {
        imu: args.imu.clone(),
        gnss: args.gnss.clone(),
        odometer: match (&args.odometer, args.odo) {
            (Some(p), _) => OdometerInput::File(p.clone()),
            (None, true) => OdometerInput::ImuColumn,
            (None, false) => OdometerInput::None,
        },
        truth: args.truth.clone(),
        config: args.config.clone(),
        out: args.out.clone(),
        outages: args.outages.clone(),
        smooth: args.smooth,
        stop_on_divergence: args.stop_on_divergence,
    };
    let mut tx = kestrel_app::process::begin(&inputs, args.force, &ctx.command)?;
    let mut bar = crate::progress::Bar::time();
    let run = kestrel_app::process::run(&inputs, &mut tx, &mut bar, &ctx.cancel)?;
    let mut report = run.report.clone();
    if !args.no_plots {
        for figure in figures(&run.traces, &report, &run, tx.scratch_dir())? {
            let name = figure
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            report.files.push(tx.adopt(name)?);
        }
    }
    ctx.cancel.check()?;
    tx.commit(run.provenance)?;
    Ok(report)
}

/// The figures of a run, drawn into `dir`; their paths there.
fn figures(
    traces: &Option<kestrel_app::process::ErrorTraces>,
    report: &ProcessReport,
    run: &kestrel_app::process::Processed,
    dir: &std::path::Path,
) -> Result<Vec<std::path::PathBuf>, CliError> {
    let mut solutions = Vec::new();
    if let Some(t) = traces {
        solutions.push(SolutionErrors {
            label: report.filter,
            errors: &t.every,
            sigma: &t.every_sigma,
            nees: &t.nees,
        });
        if report.smoothed.is_some() {
            solutions.push(SolutionErrors {
                label: "smoothed",
                errors: &t.smoothed,
                sigma: &t.smoothed_sigma,
                nees: &t.smoothed_nees,
            });
        }
    }
    let plots = ProcessPlots {
        title: "kestrel process",
        axes: report.axes,
        solutions: &solutions,
        track: &run.track,
        states: &run.states,
    };
    let mut files = process_figures(dir, &plots)?;
    if let Some(t) = traces {
        let aiding = [FilterTrace {
            label: report.filter,
            records: &t.aiding,
        }];
        files.extend(adaptation_figure(
            dir,
            "kestrel process",
            &aiding,
            &FigureOptions::default(),
        )?);
    }
    Ok(files)
}
