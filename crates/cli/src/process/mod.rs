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
mod divergence;
mod drift;
mod evaluation;
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

use crate::gins::{last_time, ImuReader, OdometerReader};
use crate::plot::{figures_of, FilterTrace};
use crate::{CliError, InputError};

pub use config::Settings;
pub use drift::{gap_threshold, WindowDrift, WindowKind};
pub use outage::Outage;
pub use sink::RESULT_CSV_HEADER;
pub use stats::{ErrorStats, MotionStats, SumOfSquares};

use dispatch::{dispatch, GnssLayout};
use drift::DriftTable;
use evaluation::{Evaluation, EvaluationSetup, Truth};
use pipeline::{GnssInput, GnssSource, Job, OdometerFile};
use sink::{Sink, SinkSetup};

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
    /// GNSS fixes skipped for their quality flag (RTKLIB `Q`).
    pub fixes_refused_quality: usize,
    /// GNSS fixes at or before the initial time (read, checked, unused).
    pub fixes_before_start: usize,
    /// GNSS fixes after the last IMU sample (read, checked, unused).
    pub fixes_after_end: usize,
    /// Aiding updates (GNSS and odometer).
    pub updates: usize,
    /// Updates rejected by an adapter.
    pub rejected: usize,
    /// Errors against the truth at every truth epoch in the run, if a
    /// truth file was given.
    pub errors: Option<ErrorStats>,
    /// The same at the aiding epochs only (after the update); `None`
    /// without a truth or without an update at a truth epoch.
    pub aiding_errors: Option<ErrorStats>,
    /// Horizontal and vertical errors in each outage window and data gap
    /// (with a truth file).
    pub drift: Vec<WindowDrift>,
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
///     odo: false, odometer: None, truth: Some(dir.join("truth.nav")), config: dir.join("process.toml"),
///     out: dir.join("result"), outages: vec!["2:4".parse().unwrap()], no_plots: true }).unwrap();
/// // Fixes at 1 … 5 s; the half-open window drops those at 2 and 3 s.
/// assert_eq!((r.samples, r.fixes_used, r.fixes_in_outage), (1000, 3, 2));
/// // Compared at every truth epoch, and at the 3 aiding epochs.
/// assert_eq!((r.errors.unwrap().epochs, r.aiding_errors.unwrap().epochs), (1000, 3));
/// assert!(kestrel_cli::process::summary(&r).starts_with("KF: 1000 IMU samples"));
/// ```
pub fn process(args: &ProcessArgs) -> Result<ProcessReport, CliError> {
    let settings = config::load(&args.config)?;
    if args.odo && args.odometer.is_some() {
        return Err(CliError::Failed(
            "give the odometer speeds either in the IMU file (--odo) or in their own file \
             (--odometer), not both"
                .into(),
        ));
    }
    let odo_flag = if args.odo { "--odo" } else { "--odometer" };
    if (args.odo || args.odometer.is_some()) && settings.odometer.is_none() {
        return Err(InputError::file(
            &args.config,
            format!("{odo_flag} needs an [odometer] table"),
        )
        .with_key("odometer")
        .into());
    }
    if args.odo && !settings.imu_format.is_gins() && settings.imu_format.odometer.is_none() {
        return Err(InputError::file(
            &args.config,
            "--odo reads the odometer speed from the IMU file: give its column",
        )
        .with_key("imu_file.columns.odometer")
        .into());
    }
    let imu = ImuReader::open_with_format(
        &args.imu,
        &settings.imu_format,
        settings.week,
        settings.start.time,
    )?;
    let (gnss, layout) = match &args.gnss {
        None => (None, GnssLayout::None),
        Some(p) => {
            let mut g =
                GnssSource::open(GnssInput::open(p, &settings.gnss_format, settings.week)?)?;
            let layout = match g.peek()? {
                None => GnssLayout::None,
                Some(f) if f.vel.is_some() => GnssLayout::PositionVelocity,
                Some(_) => GnssLayout::Position,
            };
            (Some(g), layout)
        }
    };
    let truth = args
        .truth
        .as_deref()
        .map(|p| Truth::open(p, &settings.truth.format, settings.week))
        .transpose()?;
    std::fs::create_dir_all(&args.out).map_err(|e| CliError::io(&args.out, e))?;
    refuse_overwriting_inputs(args)?;
    remove_output_links(&args.out)?;
    let evaluation = match truth {
        None => None,
        Some(truth) => Some(Evaluation::new(EvaluationSetup {
            earth: settings.earth,
            axes: settings.axes,
            truth,
            antenna: settings.truth.at_antenna.then_some(settings.lever_arm),
            csv_path: args.out.join("errors.csv"),
            drift: DriftTable::new(
                &args.outages,
                args.gnss
                    .as_deref()
                    .and_then(|p| gnss_gap_threshold(p, &settings)),
                settings.start.time,
            ),
        })?),
    };
    let nav_path = args.out.join("result.nav");
    let csv_path = args.out.join("result.csv");
    // The progress bar's total: the last line's time (GINS layout only).
    let end = if settings.imu_format.is_gins() {
        last_time(&args.imu).unwrap_or(settings.start.time)
    } else {
        settings.start.time
    };
    let label = settings.kind.label();
    let sink = Sink::new(SinkSetup {
        label,
        week: settings.week,
        interval: settings.output_interval,
        nav_path: &nav_path,
        csv_path: &csv_path,
        evaluation,
        progress: progress::Progress::new(settings.start.time, end),
    })?;
    let mut job = Job {
        imu,
        gnss,
        odometer_rate: if args.odo || args.odometer.is_some() {
            settings.odometer.map(|o| o.rate)
        } else {
            None
        },
        odometer_file: match &args.odometer {
            Some(p) => Some(OdometerFile::new(OdometerReader::open(p)?)),
            None => None,
        },
        outages: args.outages.clone(),
        start: settings.start.time,
        sink,
        fixes_used: 0,
        fixes_in_outage: 0,
        fixes_before_start: 0,
        fixes_after_end: 0,
        error_model: settings.error_model,
        timing_rule: settings.timing,
        timing: timing::TimingReport::default(),
        pending: std::collections::VecDeque::new(),
    };
    let outcome = dispatch(&settings, layout, &mut job);
    // Nothing compared is an error, never a row of zeros.
    let end_time = job.sink.end_time;
    let outcome = outcome.and_then(|()| match &mut job.sink.evaluation {
        Some(e) if e.all.epochs() == 0 => Err(CliError::Failed(format!(
            "{}: {}",
            args.truth
                .as_deref()
                .unwrap_or(Path::new("truth"))
                .display(),
            e.why_nothing_compared(settings.start.time, end_time)
        ))),
        _ => Ok(()),
    });
    job.sink.finish(outcome.is_ok())?;
    outcome?;
    let mut files = vec![nav_path, csv_path];
    let (mut errors, mut aiding_errors, mut drift) = (None, None, Vec::new());
    if let Some(e) = job.sink.evaluation.take() {
        errors = e.all.finish();
        aiding_errors = e.aiding.finish();
        drift = e.drift.clone().finish(job.sink.end_time);
        files.push(args.out.join("errors.csv"));
        files.extend(write_errors(args, &settings, label, &e, &drift)?);
    }
    Ok(ProcessReport {
        filter: label,
        samples: job.sink.samples,
        end_time: job.sink.end_time,
        fixes_used: job.fixes_used,
        fixes_in_outage: job.fixes_in_outage,
        fixes_refused_quality: job.gnss.as_ref().map_or(0, GnssSource::refused),
        fixes_before_start: job.fixes_before_start,
        fixes_after_end: job.fixes_after_end,
        updates: job.sink.updates,
        rejected: job.sink.rejected,
        errors,
        aiding_errors,
        drift,
        timing: job.timing.clone(),
        files,
    })
}

/// 1.5 × the median interval of the first 21 intervals of the GNSS file:
/// longer intervals between fixes are data gaps. `None` if the file has
/// fewer than two fixes (an unreadable line is the main reader's to report).
fn gnss_gap_threshold(path: &Path, settings: &Settings) -> Option<f64> {
    let times: Vec<f64> = GnssInput::open(path, &settings.gnss_format, settings.week)
        .ok()?
        .take(22)
        .map_while(Result::ok)
        .map(|f| f.time)
        .collect();
    gap_threshold(&times)
}

/// The names `process` writes in `--out`.
fn output_names() -> Vec<String> {
    let mut names: Vec<String> = [
        "result.nav",
        "result.csv",
        "errors.csv",
        "error_summary.csv",
        "drift.csv",
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
        ("--odometer", args.odometer.as_ref()),
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

/// The summary CSV, the drift table and the plots (the error CSV was
/// streamed during the run).
fn write_errors(
    args: &ProcessArgs,
    settings: &Settings,
    label: &'static str,
    e: &Evaluation,
    drift: &[WindowDrift],
) -> Result<Vec<PathBuf>, CliError> {
    let dir = &args.out;
    let summary = dir.join("error_summary.csv");
    write_summary_csv(
        &summary,
        &[("all", e.all.finish()), ("aiding", e.aiding.finish())],
    )?;
    let drift_path = dir.join("drift.csv");
    write_drift_csv(&drift_path, drift)?;
    let mut files = vec![summary, drift_path];
    if !args.no_plots {
        let title = String::from("kestrel process");
        let errors = [FilterTrace {
            label,
            records: &e.errors.records,
        }];
        let aiding = [FilterTrace {
            label,
            records: &e.updates.records,
        }];
        let options = crate::plot::FigureOptions::default();
        files.extend(figures_of(
            dir,
            &title,
            settings.axes,
            &errors,
            &aiding,
            &options,
        )?);
    }
    Ok(files)
}

/// `drift.csv`: one row per window; the statistics are empty for a window
/// without compared epochs.
fn write_drift_csv(path: &Path, drift: &[WindowDrift]) -> Result<(), CliError> {
    let mut text = String::from(
        "kind,start_s,end_s,duration_s,epochs,rms_horizontal_m,max_horizontal_m,\
         rms_vertical_m,max_vertical_m\n",
    );
    for w in drift {
        let pair =
            |p: Option<(f64, f64)>| p.map_or_else(|| ",".to_owned(), |(r, m)| format!("{r},{m}"));
        text += &format!(
            "{},{},{},{},{},{},{}\n",
            w.kind.name(),
            w.start,
            w.end,
            w.end - w.start,
            w.epochs,
            pair(w.horizontal),
            pair(w.vertical)
        );
    }
    write_atomically(path, &text)
}

/// Writes `text` to `path` through a partial file renamed into place.
fn write_atomically(path: &Path, text: &str) -> Result<(), CliError> {
    let mut f = sink::create_partial(path)?;
    std::io::Write::write_all(&mut f, text.as_bytes()).map_err(|e| CliError::io(path, e))?;
    sink::settle(path, true)
}

/// Names of the position axes.
fn axis_names(axes: PositionAxes) -> [&'static str; 3] {
    match axes {
        PositionAxes::NorthEastDown => ["north", "east", "down"],
        PositionAxes::EastNorthUp => ["east", "north", "up"],
    }
}

/// `error_summary.csv`: RMS and max |error| per quantity and axis, over
/// every compared epoch (`all`) and over the aiding epochs (`aiding`);
/// a set without epochs has no rows.
fn write_summary_csv(path: &Path, sets: &[(&str, Option<ErrorStats>)]) -> Result<(), CliError> {
    let mut text = String::from("epochs,count,quantity,axis,unit,rms,max_abs\n");
    for (name, stats) in sets {
        let Some(s) = stats else { continue };
        let head = format!("{name},{}", s.epochs);
        let p = axis_names(s.axes);
        let deg = |v: f64| v.to_degrees();
        for (i, axis) in p.iter().enumerate() {
            text += &format!(
                "{head},position,{axis},m,{},{}\n",
                s.rms_position[i], s.max_position[i]
            );
        }
        let Some(m) = &s.motion else { continue };
        for (i, a) in ["north", "east", "down"].iter().enumerate() {
            text += &format!(
                "{head},velocity,{a},m/s,{},{}\n",
                m.rms_velocity[i], m.max_velocity[i]
            );
        }
        for (i, a) in ["north", "east", "down"].iter().enumerate() {
            text += &format!(
                "{head},attitude,{a},deg,{},{}\n",
                deg(m.rms_attitude[i]),
                deg(m.max_attitude[i])
            );
        }
    }
    write_atomically(path, &text)
}

/// The text `kestrel process` prints.
pub fn summary(r: &ProcessReport) -> String {
    let mut s = format!(
        "{}: {} IMU samples to {} s of week, {} GNSS fixes used ({} in outages), \
         {} updates ({} rejected)\n",
        r.filter, r.samples, r.end_time, r.fixes_used, r.fixes_in_outage, r.updates, r.rejected
    );
    s += &timing_summary(&r.timing);
    if r.fixes_refused_quality > 0 {
        s += &format!(
            "{} GNSS fixes skipped for their quality flag (gnss_file.quality)\n",
            r.fixes_refused_quality
        );
    }
    if r.fixes_before_start > 0 {
        s += &format!(
            "warning: {} GNSS fixes at or before the initial time were not used\n",
            r.fixes_before_start
        );
    }
    if r.fixes_after_end > 0 {
        s += &format!(
            "warning: {} GNSS fixes after the last IMU sample were read and checked but not used\n",
            r.fixes_after_end
        );
    }
    if let Some(e) = &r.errors {
        s += &error_block(
            &format!(
                "errors against the truth at {} epochs (every truth epoch of the run; \
                 RMS / max |error|):\n",
                e.epochs
            ),
            e,
        );
    }
    if let Some(e) = &r.aiding_errors {
        s += &error_block(
            &format!("… at the {} aiding epochs, after the update:\n", e.epochs),
            e,
        );
    }
    if !r.drift.is_empty() {
        s += "drift without GNSS (horizontal / vertical error, RMS and max):\n";
        for w in &r.drift {
            s += &format!(
                "  {:<6} {} to {} s ({} s): ",
                w.kind.name(),
                w.start,
                w.end,
                w.end - w.start
            );
            s += &match (w.horizontal, w.vertical) {
                (Some((rh, mh)), Some((rv, mv))) => format!(
                    "{} epochs, horizontal {rh:.4} / {mh:.4} m, vertical {rv:.4} / {mv:.4} m\n",
                    w.epochs
                ),
                _ => "no truth epoch in the window\n".to_owned(),
            };
        }
    }
    for f in &r.files {
        s += &format!("wrote {}\n", f.display());
    }
    s
}

/// The RMS / max rows of `e` under `title`.
fn error_block(title: &str, e: &ErrorStats) -> String {
    let p = axis_names(e.axes);
    let row = |name: &str, axes: [&str; 3], unit: &str, rms: [f64; 3], max: [f64; 3]| {
        format!(
            "  {name:<9} {}: {:.4} / {:.4}  {}: {:.4} / {:.4}  {}: {:.4} / {:.4} {unit}\n",
            axes[0], rms[0], max[0], axes[1], rms[1], max[1], axes[2], rms[2], max[2]
        )
    };
    let v = |x: &kestrel::nav::nalgebra::Vector3<f64>| [x.x, x.y, x.z];
    let d = |x: &kestrel::nav::nalgebra::Vector3<f64>| v(&x.map(f64::to_degrees));
    let ned = ["north", "east", "down"];
    let mut s = title.to_owned();
    s += &row("position", p, "m", v(&e.rms_position), v(&e.max_position));
    match &e.motion {
        Some(m) => {
            s += &row(
                "velocity",
                ned,
                "m/s",
                v(&m.rms_velocity),
                v(&m.max_velocity),
            );
            s += &row(
                "attitude",
                ned,
                "deg",
                d(&m.rms_attitude),
                d(&m.max_attitude),
            );
        }
        None => s += "  (a position-only reference: no velocity or attitude errors)\n",
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
