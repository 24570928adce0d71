//! Recorded IMU / GNSS (/ odometer) data through the loosely coupled
//! engine: what `kestrel process` runs.
//!
//! The files are streamed sample by sample (memory does not grow with
//! their length). Each IMU line is one mechanisation step over the
//! interval since the previous line (the first one since the configured
//! initial time); a GNSS fix at `t` is used at the last IMU sample at or
//! before `t` (the engine extrapolates the solution to `t`); odometer
//! speeds come from the IMU file or their own file at the configured
//! rate. The
//! steps are those of the experiment runner, so simulated data written by
//! `kestrel simulate` gives the same errors as the in-memory run.

mod alignment;

mod consistency;
mod constraints;
mod dispatch;
mod divergence;
mod drift;
mod evaluation;
mod outage;
mod pipeline;

mod schedule;
mod sink;
mod smooth;
mod state_files;
mod stats;
pub mod timing;
mod traces;

use std::path::{Path, PathBuf};

use crate::experiment::{EpochRecord, PositionAxes};
use crate::scenario::FilterKind;

use crate::{Error, InputError};
use kestrel_io::gins::{last_time, ImuReader, OdometerReader};

pub use crate::config::process::Settings;
pub use crate::progress::{Progress, Silent};
pub use alignment::AlignmentReport;
pub use consistency::{chi_square_band, Consistency};
pub use constraints::ConstraintCounts;
pub use drift::{gap_threshold, WindowDrift, WindowKind};
pub use outage::Outage;
pub use sink::RESULT_CSV_HEADER;
pub use smooth::SmoothedReport;
pub use stats::{ErrorStats, MotionStats, SumOfSquares};
pub use traces::{StateRow, StateTraces, Track};

use dispatch::{dispatch, GnssLayout};
use drift::DriftTable;
use evaluation::{Evaluation, EvaluationSetup, Truth};
use pipeline::{GnssInput, GnssSource, Job, OdometerFile};
use sink::{Sink, SinkSetup};

/// Where the odometer speeds come from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum OdometerInput {
    /// No odometer.
    #[default]
    None,
    /// The IMU file's odometer column (the 8th in the GINS layout; the one
    /// `[imu_file.columns] odometer` names otherwise), `--odo` on the
    /// command line.
    ImuColumn,
    /// Their own file (`sow speed`, m/s), `--odometer FILE`.
    File(PathBuf),
}

/// The files of a run: what [`process`] reads and where it writes.
///
/// Messages name each input by the `kestrel process` flag that gives it
/// (`--imu`, `--gnss`, …), so they read the same from the library and the
/// command line.
#[derive(Clone, Debug, PartialEq)]
pub struct Inputs {
    /// IMU file (`--imu`): the GINS layout (GPS seconds of week, angle
    /// increments x y z in rad, velocity increments x y z in m/s, body
    /// forward-right-down, optional odometer speed) or the layout the
    /// configuration's `[imu_file]` table describes.
    pub imu: PathBuf,
    /// GNSS file (`--gnss`): the GINS text layout or, with
    /// `[gnss_file] format = "rtklib"`, an RTKLIB `.pos`.
    pub gnss: Option<PathBuf>,
    /// Odometer speeds.
    pub odometer: OdometerInput,
    /// Reference trajectory (`--truth`) in the format `[truth_file]`
    /// names: errors at every truth epoch, RMS, drift table.
    pub truth: Option<PathBuf>,
    /// The processing configuration (`--config`, TOML).
    pub config: PathBuf,
    /// Output directory (`--out`), created if missing.
    pub out: PathBuf,
    /// GNSS fixes at `start ≤ t < end` are ignored (`--outage`).
    pub outages: Vec<Outage>,
    /// File names the caller writes into `out` after the run (plots, say):
    /// checked against the inputs and freed of symbolic links like the
    /// run's own outputs. Plain names only: one with a folder, `.` or `..`
    /// is an error.
    pub also_written: Vec<String>,
    /// Also run the RTS smoother over the forward pass (`--smooth`):
    /// writes `smoothed.nav`, `smoothed.csv`, `smoothed_imu_errors.*`,
    /// `smoothed_std.*` and, with a truth, `errors_smoothed.csv`.
    pub smooth: bool,
}

impl Inputs {
    /// A run on the IMU file `imu` with the configuration `config`,
    /// writing to `out`; everything else absent.
    pub fn new(
        imu: impl Into<PathBuf>,
        config: impl Into<PathBuf>,
        out: impl Into<PathBuf>,
    ) -> Self {
        Self {
            imu: imu.into(),
            gnss: None,
            odometer: OdometerInput::None,
            truth: None,
            config: config.into(),
            out: out.into(),
            outages: Vec::new(),
            also_written: Vec::new(),
            smooth: false,
        }
    }
}

/// The errors of a run at full rate, thinned evenly to at most 20 000 of
/// each kind, for plotting.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorTraces {
    /// At every compared truth epoch.
    pub every: Vec<EpochRecord>,
    /// At the aiding epochs, after the update.
    pub aiding: Vec<EpochRecord>,
    /// The σ of the navigation errors at the epochs of `every` (attitude
    /// rad, velocity m/s, position m; north, east, down), for ±3σ
    /// envelopes.
    pub every_sigma: Vec<[f64; 9]>,
    /// The smoothed solution's errors at every compared truth epoch (empty
    /// without `smooth`).
    pub smoothed: Vec<EpochRecord>,
    /// The σ at the epochs of `smoothed`.
    pub smoothed_sigma: Vec<[f64; 9]>,
    /// The forward filter's position NEES `(time, NEES)` at the compared
    /// epochs, thinned like the errors.
    pub nees: Vec<(f64, f64)>,
    /// The same for the smoothed solution (empty without `smooth`).
    pub smoothed_nees: Vec<(f64, f64)>,
}

/// What [`process`] returns: the report, the track and the filter's
/// estimates over time and, with a truth, the error traces.
#[derive(Clone, Debug, PartialEq)]
pub struct Processed {
    /// Counts, statistics and files.
    pub report: ProcessReport,
    /// The errors over time (with a truth file).
    pub traces: Option<ErrorTraces>,
    /// The horizontal track, the fixes and the outages.
    pub track: Track,
    /// The IMU error estimates and σ over time.
    pub states: StateTraces,
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
    /// Standstill and non-holonomic pseudo-measurements (`[zupt]`, `[nhc]`).
    pub constraints: ConstraintCounts,
    /// The automatic alignment (`[alignment]`), if configured.
    pub alignment: Option<AlignmentReport>,
    /// Errors against the truth at every truth epoch in the run, if a
    /// truth file was given.
    pub errors: Option<ErrorStats>,
    /// The same at the aiding epochs only (after the update); `None`
    /// without a truth or without an update at a truth epoch.
    pub aiding_errors: Option<ErrorStats>,
    /// The position NEES of the forward filter at the compared epochs
    /// (with a truth).
    pub consistency: Option<Consistency>,
    /// Horizontal and vertical errors in each outage window and data gap
    /// (with a truth file).
    pub drift: Vec<WindowDrift>,
    /// The IMU time line: nominal interval and the gaps bridged.
    pub timing: timing::TimingReport,
    /// The axes of the position errors.
    pub axes: PositionAxes,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// The smoothed solution (with `smooth`).
    pub smoothed: Option<SmoothedReport>,
}

/// Processes the files of `inputs`, writes the results into `inputs.out`
/// and returns what it did; `progress` hears how far the run has come.
/// Nothing is printed ([`summary`] gives the text the command prints).
///
/// # Errors
/// [`Error`]: bad input (naming file, line, column or key), an output
/// that cannot be written or would replace an input, or a filter
/// divergence (naming the time, the last input line and the quantity).
/// A failed run leaves no result file behind.
///
/// ```
/// use kestrel_app::process::{process, Inputs, Silent};
/// let data = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data");
/// let out = std::env::temp_dir().join(format!("kestrel-doc-process-{}", std::process::id()));
/// let mut inputs = Inputs::new(format!("{data}/imu.txt"), format!("{data}/process.toml"), &out);
/// inputs.gnss = Some(format!("{data}/gnss.txt").into());
/// inputs.truth = Some(format!("{data}/truth.nav").into());
/// inputs.outages = vec!["2:4".parse()?];
/// let run = process(&inputs, &mut Silent)?;
/// let r = &run.report;
/// // 5 s at 50 Hz; fixes at 1 … 5 s, the half-open window drops 2 and 3 s.
/// assert_eq!((r.samples, r.fixes_used, r.fixes_in_outage), (250, 3, 2));
/// // Compared at every truth epoch, and at the 3 aiding epochs.
/// let (every, aiding) = (r.errors.as_ref().unwrap(), r.aiding_errors.as_ref().unwrap());
/// assert_eq!((every.epochs, aiding.epochs), (250, 3));
/// assert!(kestrel_app::process::summary(r).starts_with("KF: 250 IMU samples"));
/// # std::fs::remove_dir_all(&out)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn process(inputs: &Inputs, progress: &mut dyn Progress) -> Result<Processed, Error> {
    let mut settings = crate::config::process::load(&inputs.config)?;
    let alignment = match settings.alignment {
        Some(a) => Some(alignment::align(
            &inputs.imu,
            inputs.gnss.as_deref(),
            &a,
            &mut settings,
        )?),
        None => None,
    };
    let odo_flag = match inputs.odometer {
        OdometerInput::None => None,
        OdometerInput::ImuColumn => Some("--odo"),
        OdometerInput::File(_) => Some("--odometer"),
    };
    if let (Some(flag), None) = (odo_flag, &settings.odometer) {
        return Err(
            InputError::file(&inputs.config, format!("{flag} needs an [odometer] table"))
                .with_key("odometer")
                .into(),
        );
    }
    if inputs.odometer == OdometerInput::ImuColumn
        && !settings.imu_format.is_gins()
        && settings.imu_format.odometer.is_none()
    {
        return Err(InputError::file(
            &inputs.config,
            "--odo reads the odometer speed from the IMU file: give its column",
        )
        .with_key("imu_file.columns.odometer")
        .into());
    }
    let imu = ImuReader::open_with_format(
        &inputs.imu,
        &settings.imu_format,
        settings.week,
        settings.start.time,
    )?;
    let (gnss, layout) = match &inputs.gnss {
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
    let truth = inputs
        .truth
        .as_deref()
        .map(|p| Truth::open(p, &settings.truth.format, settings.week))
        .transpose()?;
    // A caller's name is a file in `out`, never a path out of it.
    if let Some(bad) = inputs.also_written.iter().find(|n| {
        let mut parts = Path::new(n.as_str()).components();
        !matches!(
            (parts.next(), parts.next()),
            (Some(std::path::Component::Normal(_)), None)
        )
    }) {
        return Err(Error::Failed(format!(
            "also_written: `{bad}` is not a plain file name (no folders, `.` or `..`)"
        )));
    }
    std::fs::create_dir_all(&inputs.out).map_err(|e| Error::io(&inputs.out, e))?;
    let names = output_names(&inputs.also_written);
    refuse_overwriting_inputs(inputs, &names)?;
    remove_output_links(&inputs.out, &names)?;
    let evaluation = match truth {
        None => None,
        Some(truth) => Some(compare_with(inputs, &settings, truth, "errors.csv")?),
    };
    let smoother = if inputs.smooth {
        let evaluation = match inputs.truth.as_deref() {
            None => None,
            Some(p) => {
                let truth = Truth::open(p, &settings.truth.format, settings.week)?;
                Some(compare_with(
                    inputs,
                    &settings,
                    truth,
                    "errors_smoothed.csv",
                )?)
            }
        };
        Some(smooth::ForwardRecord::new(
            &inputs.out,
            smooth::SmoothSetup {
                label: settings.kind.label(),
                week: settings.week,
                interval: settings.output_interval,
                earth: settings.earth,
                nav_path: inputs.out.join("smoothed.nav"),
                csv_path: inputs.out.join("smoothed.csv"),
                out: inputs.out.clone(),
                evaluation,
            },
        )?)
    } else {
        None
    };
    let nav_path = inputs.out.join("result.nav");
    let csv_path = inputs.out.join("result.csv");
    // The span reported as progress: to the last line's time (GINS layout
    // only; otherwise unknown).
    let end = if settings.imu_format.is_gins() {
        last_time(&inputs.imu).unwrap_or(settings.start.time)
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
        progress: crate::progress::Ticker::new(progress, settings.start.time, end),
    })?;
    let mut job = Job {
        imu,
        gnss,
        odometer_rate: match odo_flag {
            Some(_) => settings.odometer.map(|o| o.rate),
            None => None,
        },
        odometer_file: match &inputs.odometer {
            OdometerInput::File(p) => Some(OdometerFile::new(OdometerReader::open(p)?)),
            _ => None,
        },
        outages: inputs.outages.clone(),
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
        smoother,
        smoothed: None,
        smoothed_traces: smooth::SmoothedTraces::default(),
        fix_track: evaluation::Thinned::default(),
        constraints: constraints::Constraints::new(settings.nhc, settings.zupt),
        out: inputs.out.clone(),
        output_interval: settings.output_interval,
        states: None,
    };
    let outcome = dispatch(&settings, layout, &mut job);
    // Nothing compared is an error, never a row of zeros.
    let end_time = job.sink.end_time;
    let outcome = outcome.and_then(|()| match &mut job.sink.evaluation {
        Some(e) if e.all.epochs() == 0 => Err(Error::Failed(format!(
            "{}: {}",
            inputs
                .truth
                .as_deref()
                .unwrap_or(Path::new("truth"))
                .display(),
            e.why_nothing_compared(settings.start.time, end_time)
        ))),
        _ => Ok(()),
    });
    let mut state_traces = StateTraces::default();
    let states = job.states.take().map(|mut s| {
        state_traces.estimates = s.estimate_names.clone();
        state_traces.sigmas = s.sigma_names.clone();
        state_traces.forward = std::mem::take(&mut s.rows.records);
        s.finish(outcome.is_ok())
    });
    job.sink.finish(outcome.is_ok())?;
    outcome?;
    let mut files = vec![nav_path, csv_path];
    if let Some(s) = states {
        files.extend(s?);
    }
    let (mut errors, mut aiding_errors, mut drift) = (None, None, Vec::new());
    let mut consistency = None;
    let mut traces = None;
    if let Some(e) = job.sink.evaluation.take() {
        errors = e.all.finish();
        aiding_errors = e.aiding.finish();
        consistency = Some(e.consistency);
        drift = e.drift.clone().finish(job.sink.end_time);
        files.push(inputs.out.join("errors.csv"));
        files.extend(write_errors(&inputs.out, &e, &drift)?);
        traces = Some(ErrorTraces {
            every: e.errors.records,
            every_sigma: e.sigmas.records,
            aiding: e.updates.records,
            smoothed: std::mem::take(&mut job.smoothed_traces.errors),
            smoothed_sigma: std::mem::take(&mut job.smoothed_traces.sigmas),
            nees: e.nees.records,
            smoothed_nees: std::mem::take(&mut job.smoothed_traces.nees),
        });
    }
    let report = ProcessReport {
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
        constraints: job.constraints.counts,
        alignment,
        errors,
        aiding_errors,
        consistency,
        drift,
        timing: job.timing.clone(),
        axes: settings.axes,
        files,
        smoothed: job.smoothed.take(),
    };
    state_traces.smoothed = std::mem::take(&mut job.smoothed_traces.states);
    // The track in metres from the initial position.
    let local = |points: &[(f64, f64, f64)]| -> Vec<(f64, f64, f64)> {
        points
            .iter()
            .map(|&(t, lat, lon)| {
                let here = kestrel::nav::Geodetic::new(lat, lon, settings.start.pos.h);
                let d = settings.earth.ned_offset(&settings.start.pos, &here);
                (t, d.x, d.y)
            })
            .collect()
    };
    let track = Track {
        forward: local(&job.sink.track.records),
        smoothed: local(&job.smoothed_traces.track),
        fixes: local(&job.fix_track.records),
        outages: inputs.outages.iter().map(|o| (o.start, o.end)).collect(),
    };
    Ok(Processed {
        report,
        traces,
        track,
        states: state_traces,
    })
}

/// The comparison of a solution with `truth`, writing `csv` in `--out`.
fn compare_with(
    inputs: &Inputs,
    settings: &Settings,
    truth: Truth,
    csv: &str,
) -> Result<Evaluation, Error> {
    Evaluation::new(EvaluationSetup {
        earth: settings.earth,
        axes: settings.axes,
        truth,
        antenna: settings.truth.at_antenna.then_some(settings.lever_arm),
        csv_path: inputs.out.join(csv),
        drift: DriftTable::new(
            &inputs.outages,
            inputs
                .gnss
                .as_deref()
                .and_then(|p| gnss_gap_threshold(p, settings)),
            settings.start.time,
        ),
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

/// The names written in `--out`: the run's own and the caller's `extra`.
fn output_names(extra: &[String]) -> Vec<String> {
    let states = ["result", "smoothed"]
        .into_iter()
        .flat_map(state_files::StateFiles::names);
    [
        "result.nav",
        "result.csv",
        "errors.csv",
        "error_summary.csv",
        "drift.csv",
        "smoothed.nav",
        "smoothed.csv",
        "errors_smoothed.csv",
        ".smoother-epochs.partial",
        ".smoother-samples.partial",
        ".smoother-corrections.partial",
    ]
    .map(String::from)
    .into_iter()
    .chain(states)
    .chain(extra.iter().cloned())
    .collect()
}

/// Refuses a run whose outputs would replace one of its inputs (say
/// `--truth out/result.nav --out out`), comparing resolved paths, so a
/// symbolic link in `--out` pointing at an input is caught too.
fn refuse_overwriting_inputs(inputs: &Inputs, names: &[String]) -> Result<(), Error> {
    let out = std::fs::canonicalize(&inputs.out).map_err(|e| Error::io(&inputs.out, e))?;
    let odometer = match &inputs.odometer {
        OdometerInput::File(p) => Some(p),
        _ => None,
    };
    let given = [
        ("--imu", Some(&inputs.imu)),
        ("--gnss", inputs.gnss.as_ref()),
        ("--truth", inputs.truth.as_ref()),
        ("--odometer", odometer),
        ("--config", Some(&inputs.config)),
    ];
    for (flag, input) in given {
        let Some(input) = input else { continue };
        let Ok(input_real) = std::fs::canonicalize(input) else {
            continue;
        };
        for name in names {
            let output = out.join(name);
            let resolved = std::fs::canonicalize(&output).unwrap_or(output.clone());
            if resolved == input_real || output == input_real {
                return Err(Error::Failed(format!(
                    "refusing to write {}: it is the {flag} input {}; choose another --out",
                    inputs.out.join(name).display(),
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
fn remove_output_links(out: &Path, names: &[String]) -> Result<(), Error> {
    for name in names {
        let p = out.join(name);
        if std::fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink()) {
            std::fs::remove_file(&p).map_err(|e| Error::io(&p, e))?;
        }
    }
    Ok(())
}

/// The summary CSV and the drift table (the error CSV was streamed
/// during the run).
fn write_errors(dir: &Path, e: &Evaluation, drift: &[WindowDrift]) -> Result<Vec<PathBuf>, Error> {
    let summary = dir.join("error_summary.csv");
    write_summary_csv(
        &summary,
        &[("all", e.all.finish()), ("aiding", e.aiding.finish())],
    )?;
    let drift_path = dir.join("drift.csv");
    write_drift_csv(&drift_path, drift)?;
    Ok(vec![summary, drift_path])
}

/// `drift.csv`: one row per window; the statistics are empty for a window
/// without compared epochs.
fn write_drift_csv(path: &Path, drift: &[WindowDrift]) -> Result<(), Error> {
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
fn write_atomically(path: &Path, text: &str) -> Result<(), Error> {
    let mut f = sink::create_partial(path)?;
    std::io::Write::write_all(&mut f, text.as_bytes()).map_err(|e| Error::io(path, e))?;
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
fn write_summary_csv(path: &Path, sets: &[(&str, Option<ErrorStats>)]) -> Result<(), Error> {
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
    if let Some(a) = &r.alignment {
        let [roll, pitch, yaw] = a.attitude;
        s += &format!(
            "alignment: levelled over {} to {} s ({} IMU samples, specific-force spread {:.3} \
             m/s²): roll {roll:.3}°, pitch {pitch:.3}°, yaw {yaw:.2}° ",
            a.window.0, a.window.1, a.samples, a.accel_spread
        );
        s += &match (a.yaw, a.course_fix) {
            (_, Some((t, v))) => format!("from the GNSS course at {t} s ({v:.1} m/s)"),
            _ => "by gyrocompassing".to_owned(),
        };
        if let Some([x, y, z]) = a.gyro_bias {
            s += &format!("; initial gyro bias {x:.1}, {y:.1}, {z:.1} °/h");
        }
        s += &format!("; the run starts at {} s\n", a.start);
    }
    let c = &r.constraints;
    if c.zero_velocity + c.non_holonomic + c.standstill_samples > 0 {
        s += &format!(
            "constraints: {} zero-velocity and {} zero-angular-rate updates ({} IMU samples \
             detected standing still), {} non-holonomic updates\n",
            c.zero_velocity, c.zero_angular_rate, c.standstill_samples, c.non_holonomic
        );
    }
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
    if let Some(c) = &r.consistency {
        s += &nees_line(c);
    }
    s += &drift_block(&r.drift);
    if let Some(sm) = &r.smoothed {
        s += &format!(
            "smoothed (Rauch-Tung-Striebel over {} covariance epochs):\n",
            sm.epochs
        );
        if let Some(e) = &sm.errors {
            s += &error_block(
                &format!(
                    "  errors against the truth at {} epochs (RMS / max |error|):\n",
                    e.epochs
                ),
                e,
            );
        }
        if let Some(c) = &sm.consistency {
            s += &nees_line(c);
        }
        s += &drift_block(&sm.drift);
    }
    let smoothed_files = r.smoothed.iter().flat_map(|sm| &sm.files);
    for f in r.files.iter().chain(smoothed_files) {
        s += &format!("wrote {}\n", f.display());
    }
    s
}

/// The NEES line: mean and share inside the band, or why there is none.
fn nees_line(c: &Consistency) -> String {
    let (low, high) = chi_square_band(3);
    match (c.mean(), c.inside_share()) {
        (Some(mean), Some(share)) => format!(
            "position NEES (3 degrees of freedom, consistent: mean 3): mean {mean:.2}, \
             {:.1} % of {} epochs inside the 95 % χ² band [{low:.3}, {high:.3}], {:.1} % above\n",
            100.0 * share,
            c.epochs,
            100.0 * c.above as f64 / c.epochs as f64
        ),
        _ => "position NEES: no epoch with a usable covariance\n".to_owned(),
    }
}

/// The drift table's lines (nothing for no window).
fn drift_block(drift: &[WindowDrift]) -> String {
    let mut s = String::new();
    if drift.is_empty() {
        return s;
    }
    s += "drift without GNSS (horizontal / vertical error, RMS and max):\n";
    for w in drift {
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
/// use kestrel_app::scenario::FilterKind;
/// assert_eq!(kestrel_app::process::label(&FilterKind::Standard), "KF");
/// ```
pub fn label(kind: &FilterKind) -> &'static str {
    kind.label()
}
