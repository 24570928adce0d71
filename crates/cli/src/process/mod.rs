//! `kestrel process`: recorded IMU / GNSS (/ odometer) data in the open
//! GINS text formats through the loosely coupled engine.
//!
//! The files are streamed sample by sample (memory does not grow with
//! their length). Each IMU line is one mechanisation step over the
//! interval since the previous line (the first one since the configured
//! initial time); a GNSS fix at `t` is used at the last IMU sample at or
//! before `t` (the engine extrapolates the solution to `t`); odometer
//! speeds come from the IMU file's 8th column at the configured rate. The
//! steps are those of the experiment runner, so simulated data written by
//! `kestrel simulate` gives the same errors as the in-memory run.

pub mod config;
mod dispatch;
pub(crate) mod filter_params;
mod outage;
mod pipeline;
mod progress;
mod schedule;
mod sink;
mod stats;
pub mod timing;
pub mod units;

use std::path::{Path, PathBuf};

use clap::Args;
use kestrel::nav::experiment::PositionAxes;
use kestrel::nav::scenario::FilterKind;

use crate::gins::{last_time, GnssReader, ImuReader};
use crate::plot::{error_figures, FilterTrace};
use crate::{CliError, InputError};

pub use config::Settings;
pub use outage::Outage;
pub use sink::RESULT_CSV_HEADER;
pub use stats::ErrorStats;

use dispatch::{dispatch, GnssLayout};
use pipeline::Job;
use sink::{Sink, SinkSetup, Truth};
use stats::Accumulator;

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
    /// Ignore GNSS fixes from START to END (seconds of week, inclusive);
    /// repeat for several windows.
    #[arg(long = "outage", value_name = "START:END")]
    pub outages: Vec<Outage>,
    /// Do not draw the error plots.
    #[arg(long)]
    pub no_plots: bool,
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct ProcessReport {
    /// The filter's label.
    pub filter: &'static str,
    /// IMU samples processed.
    pub samples: usize,
    /// Last IMU time processed, s of week.
    pub end_time: f64,
    /// GNSS fixes used.
    pub fixes_used: usize,
    /// GNSS fixes skipped in outage windows.
    pub fixes_in_outage: usize,
    /// Aiding updates (GNSS and odometer).
    pub updates: usize,
    /// Updates rejected by an adapter.
    pub rejected: usize,
    /// Errors against the truth, if a truth file was given.
    pub errors: Option<ErrorStats>,
    /// The IMU time line: nominal interval and the gaps bridged.
    pub timing: timing::TimingReport,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Runs `kestrel process` and prints its summary.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn run(args: &ProcessArgs) -> Result<(), CliError> {
    let report = process(args)?;
    print!("{}", summary(&report));
    Ok(())
}

/// Runs the processing of `args` and returns what it did (nothing printed).
///
/// # Errors
/// [`CliError`]: bad input (naming file, line, column or key), an output
/// that cannot be written, or a filter divergence (naming the time).
///
/// ```
/// use kestrel_cli::process::{process, ProcessArgs};
/// use kestrel_cli::simulate::{simulate, SimulateArgs};
/// let dir = std::env::temp_dir().join(format!("kestrel-doc-process-{}", std::process::id()));
/// simulate(&SimulateArgs { scenario: "002".into(), seed: Some(1), duration: Some(5.0),
///     imu_rate: None, out: dir.clone(), force: true }).unwrap();
/// let r = process(&ProcessArgs { imu: dir.join("imu.txt"), gnss: Some(dir.join("gnss.txt")),
///     odo: false, truth: Some(dir.join("truth.nav")), config: dir.join("process.toml"),
///     out: dir.join("result"), outages: vec!["2:3".parse().unwrap()], no_plots: true }).unwrap();
/// assert_eq!((r.samples, r.fixes_used, r.fixes_in_outage), (1000, 3, 2));
/// assert_eq!(r.errors.unwrap().epochs, 3);
/// assert!(kestrel_cli::process::summary(&r).starts_with("KF: 1000 IMU samples"));
/// ```
pub fn process(args: &ProcessArgs) -> Result<ProcessReport, CliError> {
    let settings = config::load(&args.config)?;
    if args.odo && settings.odometer.is_none() {
        return Err(
            InputError::file(&args.config, "--odo needs an [odometer] table")
                .with_key("odometer")
                .into(),
        );
    }
    let imu = ImuReader::open(&args.imu)?;
    let (gnss, layout) = match &args.gnss {
        None => (None, GnssLayout::None),
        Some(p) => {
            let mut g = GnssReader::open(p)?.peekable();
            let layout = match g.peek() {
                None => GnssLayout::None,
                Some(Err(_)) => {
                    return Err(g.next().and_then(Result::err).map_or_else(
                        || CliError::Failed("unreadable GNSS file".into()),
                        CliError::from,
                    ))
                }
                Some(Ok(f)) if f.vel.is_some() => GnssLayout::PositionVelocity,
                Some(Ok(_)) => GnssLayout::Position,
            };
            (Some(g), layout)
        }
    };
    let truth = args.truth.as_deref().map(Truth::open).transpose()?;
    std::fs::create_dir_all(&args.out).map_err(|e| CliError::io(&args.out, e))?;
    refuse_overwriting_inputs(args)?;
    remove_output_links(&args.out)?;
    let nav_path = args.out.join("result.nav");
    let csv_path = args.out.join("result.csv");
    let end = last_time(&args.imu).unwrap_or(settings.start.time);
    let label = settings.kind.label();
    let sink = Sink::new(SinkSetup {
        label,
        earth: settings.earth,
        week: settings.week,
        interval: settings.output_interval,
        nav_path: &nav_path,
        csv_path: &csv_path,
        truth,
        acc: Accumulator::new(settings.axes),
        progress: progress::Progress::new(settings.start.time, end),
    })?;
    let mut job = Job {
        imu,
        gnss,
        odometer_rate: if args.odo {
            settings.odometer.map(|o| o.rate)
        } else {
            None
        },
        outages: args.outages.clone(),
        start: settings.start.time,
        sink,
        fixes_used: 0,
        fixes_in_outage: 0,
        timing_rule: settings.timing,
        timing: timing::TimingReport::default(),
        pending: std::collections::VecDeque::new(),
    };
    let outcome = dispatch(&settings, layout, &mut job);
    job.sink.finish(outcome.is_ok())?;
    outcome?;
    let mut files = vec![nav_path, csv_path];
    let errors = if args.truth.is_some() {
        let stats = job.sink.acc.finish();
        files.extend(write_errors(
            args,
            &settings,
            label,
            &job.sink.records,
            &stats,
        )?);
        Some(stats)
    } else {
        None
    };
    Ok(ProcessReport {
        filter: label,
        samples: job.sink.samples,
        end_time: job.sink.end_time,
        fixes_used: job.fixes_used,
        fixes_in_outage: job.fixes_in_outage,
        updates: job.sink.updates,
        rejected: job.sink.rejected,
        errors,
        timing: job.timing.clone(),
        files,
    })
}

/// The names `process` writes in `--out`.
fn output_names() -> Vec<String> {
    let mut names: Vec<String> = [
        "result.nav",
        "result.csv",
        "errors.csv",
        "error_summary.csv",
    ]
    .map(String::from)
    .to_vec();
    for stem in crate::plot::FIGURES {
        names.push(format!("{stem}.png"));
        names.push(format!("{stem}.svg"));
    }
    names
}

/// Refuses a run whose outputs would replace one of its inputs (say
/// `--truth out/result.nav --out out`), comparing resolved paths, so a
/// symbolic link in `--out` pointing at an input is caught too.
fn refuse_overwriting_inputs(args: &ProcessArgs) -> Result<(), CliError> {
    let out = std::fs::canonicalize(&args.out).map_err(|e| CliError::io(&args.out, e))?;
    let inputs = [
        ("--imu", Some(&args.imu)),
        ("--gnss", args.gnss.as_ref()),
        ("--truth", args.truth.as_ref()),
        ("--config", Some(&args.config)),
    ];
    for (flag, input) in inputs {
        let Some(input) = input else { continue };
        let Ok(input_real) = std::fs::canonicalize(input) else {
            continue;
        };
        for name in output_names() {
            let output = out.join(&name);
            let resolved = std::fs::canonicalize(&output).unwrap_or(output.clone());
            if resolved == input_real || output == input_real {
                return Err(CliError::Failed(format!(
                    "refusing to write {}: it is the {flag} input {}; choose another --out",
                    args.out.join(&name).display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

/// Removes symbolic links standing under output names in `out`, so no
/// output is ever written through one (the link goes, its target is never
/// touched; inputs were checked before).
fn remove_output_links(out: &Path) -> Result<(), CliError> {
    for name in output_names() {
        let p = out.join(name);
        if std::fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink()) {
            std::fs::remove_file(&p).map_err(|e| CliError::io(&p, e))?;
        }
    }
    Ok(())
}

/// The error CSV, the summary CSV and the plots.
fn write_errors(
    args: &ProcessArgs,
    settings: &Settings,
    label: &'static str,
    records: &[kestrel::nav::experiment::EpochRecord],
    stats: &ErrorStats,
) -> Result<Vec<PathBuf>, CliError> {
    let dir = &args.out;
    let errors = dir.join("errors.csv");
    crate::output::write_epochs_csv(&errors, settings.axes, records)?;
    let summary = dir.join("error_summary.csv");
    write_summary_csv(&summary, stats)?;
    let mut files = vec![errors, summary];
    if !args.no_plots && !records.is_empty() {
        let title = String::from("kestrel process");
        let traces = [FilterTrace { label, records }];
        files.extend(error_figures(dir, &title, settings.axes, &traces)?);
    }
    Ok(files)
}

/// Names of the position axes.
fn axis_names(axes: PositionAxes) -> [&'static str; 3] {
    match axes {
        PositionAxes::NorthEastDown => ["north", "east", "down"],
        PositionAxes::EastNorthUp => ["east", "north", "up"],
    }
}

fn write_summary_csv(path: &Path, s: &ErrorStats) -> Result<(), CliError> {
    let p = axis_names(s.axes);
    let deg = |v: f64| v.to_degrees();
    let mut text = String::from("quantity,axis,unit,rms,max_abs\n");
    for (i, axis) in p.iter().enumerate() {
        text += &format!(
            "position,{axis},m,{},{}\n",
            s.rms_position[i], s.max_position[i]
        );
    }
    for (i, a) in ["north", "east", "down"].iter().enumerate() {
        text += &format!(
            "velocity,{a},m/s,{},{}\n",
            s.rms_velocity[i], s.max_velocity[i]
        );
    }
    for (i, a) in ["north", "east", "down"].iter().enumerate() {
        text += &format!(
            "attitude,{a},deg,{},{}\n",
            deg(s.rms_attitude[i]),
            deg(s.max_attitude[i])
        );
    }
    std::fs::write(path, text).map_err(|e| CliError::io(path, e))
}

/// The text `kestrel process` prints.
pub fn summary(r: &ProcessReport) -> String {
    let mut s = format!(
        "{}: {} IMU samples to {} s of week, {} GNSS fixes used ({} in outages), \
         {} updates ({} rejected)\n",
        r.filter, r.samples, r.end_time, r.fixes_used, r.fixes_in_outage, r.updates, r.rejected
    );
    s += &timing_summary(&r.timing);
    if let Some(e) = &r.errors {
        let p = axis_names(e.axes);
        s += &format!(
            "errors against the truth at {} aiding epochs (RMS / max |error|):\n",
            e.epochs
        );
        let row = |name: &str, axes: [&str; 3], unit: &str, rms: [f64; 3], max: [f64; 3]| {
            format!(
                "  {name:<9} {}: {:.4} / {:.4}  {}: {:.4} / {:.4}  {}: {:.4} / {:.4} {unit}\n",
                axes[0], rms[0], max[0], axes[1], rms[1], max[1], axes[2], rms[2], max[2]
            )
        };
        let v = |x: &kestrel::nav::nalgebra::Vector3<f64>| [x.x, x.y, x.z];
        let d = |x: &kestrel::nav::nalgebra::Vector3<f64>| v(&x.map(f64::to_degrees));
        let ned = ["north", "east", "down"];
        s += &row("position", p, "m", v(&e.rms_position), v(&e.max_position));
        s += &row(
            "velocity",
            ned,
            "m/s",
            v(&e.rms_velocity),
            v(&e.max_velocity),
        );
        s += &row(
            "attitude",
            ned,
            "deg",
            d(&e.rms_attitude),
            d(&e.max_attitude),
        );
    }
    for f in &r.files {
        s += &format!("wrote {}\n", f.display());
    }
    s
}

/// The lines on the IMU time line: the nominal interval, and the gaps
/// bridged as warnings (the first few by line, the longest, the count).
fn timing_summary(t: &timing::TimingReport) -> String {
    let mut s = format!("IMU nominal interval {} s", timing::seconds(t.nominal));
    if t.gaps == 0 {
        return s + ", no gaps\n";
    }
    s += &format!("; {} gaps bridged (total {:.3} s)\n", t.gaps, t.bridged);
    let kind = |g: &timing::Gap| {
        if g.long {
            "long gap coasted"
        } else {
            "dropout bridged"
        }
    };
    for g in &t.first_gaps {
        s += &format!(
            "warning: IMU {}: {:.4} s before line {}\n",
            kind(g),
            g.seconds,
            g.line
        );
    }
    if t.gaps > t.first_gaps.len() {
        s += &format!(
            "warning: … and {} more IMU gaps",
            t.gaps - t.first_gaps.len()
        );
        if let Some(g) = t.longest {
            s += &format!(" (the longest {:.4} s before line {})", g.seconds, g.line);
        }
        s += "\n";
    }
    s
}

/// The label `process` gives the filter of `kind`.
///
/// ```
/// use kestrel::nav::scenario::FilterKind;
/// assert_eq!(kestrel_cli::process::label(&FilterKind::Standard), "KF");
/// ```
pub fn label(kind: &FilterKind) -> &'static str {
    kind.label()
}
