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
mod results;
mod schedule;
mod setup;
mod sink;
mod smooth;
mod state_files;
mod stats;
pub mod timing;
mod traces;

use std::path::PathBuf;

use crate::experiment::{EpochRecord, HealthEvent, HealthEventKind, HealthSummary, PositionAxes};
use crate::scenario::FilterKind;
use crate::transaction::{Begin, Cancel, InputRecord, Provenance, Transaction};
use crate::Error;

pub use crate::config::process::Settings;
use crate::progress::Cancellable;
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

use dispatch::dispatch;

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
    /// Also run the RTS smoother over the forward pass (`--smooth`):
    /// writes `smoothed.nav`, `smoothed.csv`, `smoothed_imu_errors.*`,
    /// `smoothed_std.*` and, with a truth, `errors_smoothed.csv`.
    pub smooth: bool,
    /// Stop the run with an error at the health monitor's first alarm
    /// (`--stop-on-divergence`; see [`Health`](crate::experiment::Health)).
    /// Without it an alarm is a warning in the summary.
    pub stop_on_divergence: bool,
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
            smooth: false,
            stop_on_divergence: false,
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
    /// What the run read and how it was configured, for the manifest.
    pub provenance: Provenance,
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
    /// What the health monitor found over the forward pass.
    pub health: HealthSummary,
    /// Its events in time order (at most the first 100).
    pub health_events: Vec<HealthEvent>,
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
    let mut tx = begin(inputs, false, &["process".to_owned()])?;
    let processed = run(inputs, &mut tx, progress, &Cancel::default())?;
    tx.commit(processed.provenance.clone())?;
    Ok(processed)
}

/// The output transaction of a run of `inputs` into `inputs.out`,
/// recording `command`: the inputs are named by their flags, so none of
/// them can be replaced; `force` lets the run replace files in the folder
/// that no earlier run wrote.
///
/// # Errors
/// As [`Transaction::begin`].
pub fn begin(inputs: &Inputs, force: bool, command: &[String]) -> Result<Transaction, Error> {
    let mut begin = Begin {
        command: command.to_vec(),
        force,
        ..Begin::default()
    }
    .input("--imu", &inputs.imu)
    .input("--config", &inputs.config);
    if let Some(p) = &inputs.gnss {
        begin = begin.input("--gnss", p);
    }
    if let Some(p) = &inputs.truth {
        begin = begin.input("--truth", p);
    }
    if let OdometerInput::File(p) = &inputs.odometer {
        begin = begin.input("--odometer", p);
    }
    Transaction::begin(&inputs.out, begin)
}

/// Processes `inputs` into the transaction `tx` (the caller commits it,
/// after adding files of its own such as figures): every input read once
/// as a stream, `cancel` checked at every progress report.
///
/// # Errors
/// As [`process`], and [`Error::Cancelled`] once `cancel` is set.
pub fn run(
    inputs: &Inputs,
    tx: &mut Transaction,
    progress: &mut dyn Progress,
    cancel: &Cancel,
) -> Result<Processed, Error> {
    let (mut settings, config) = crate::config::process::load_recorded(&inputs.config)?;
    setup::check_odometer(inputs, &settings)?;
    let mut readers = setup::Readers::open(inputs, &settings)?;
    // The alignment sets the initial state (and may move the start) that
    // everything after it reads, from the same streams.
    let alignment = match settings.alignment {
        Some(a) => Some(alignment::align(
            &mut readers,
            &inputs.outages,
            &a,
            &mut settings,
        )?),
        None => None,
    };
    let layout = readers.layout;
    let tallies = std::mem::take(&mut readers.tallies);
    let dir = tx.scratch_dir().to_path_buf();
    let mut progress = Cancellable::new(progress, cancel);
    let mut job = setup::job(inputs, &settings, readers, &dir, &mut progress)?;
    let outcome = dispatch(&settings, layout, &mut job);
    let mut processed = results::finish(inputs, &settings, job, outcome, alignment)?;
    cancel.check()?;
    let mut records: Vec<InputRecord> = tallies
        .iter()
        .map(|(flag, path, t)| InputRecord {
            flag: flag.clone(),
            path: path.display().to_string(),
            bytes: t.bytes(),
            sha256: t.sha256(),
        })
        .collect();
    records.push(InputRecord {
        flag: "--config".into(),
        path: inputs.config.display().to_string(),
        bytes: config.tally.bytes(),
        sha256: config.tally.sha256(),
    });
    // The files in the order the run wrote them, under their final names.
    let adopt = |files: &mut Vec<PathBuf>, tx: &mut Transaction| -> Result<(), Error> {
        for f in std::mem::take(files) {
            let name = f.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            files.push(tx.adopt(name)?);
        }
        Ok(())
    };
    adopt(&mut processed.report.files, tx)?;
    if let Some(smoothed) = processed.report.smoothed.as_mut() {
        adopt(&mut smoothed.files, tx)?;
    }
    processed.provenance = Provenance {
        inputs: records,
        configuration: Some(config.resolved),
        seeds: Vec::new(),
        limits: Vec::new(),
    };
    Ok(processed)
}

/// Names of the position axes.
fn axis_names(axes: PositionAxes) -> [&'static str; 3] {
    match axes {
        PositionAxes::NorthEastDown => ["north", "east", "down"],
        PositionAxes::EastNorthUp => ["east", "north", "up"],
    }
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
    s += &health_block(r);
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

/// The health monitor's lines: one per event (the first few), a warning
/// when the run ends diverged, or that there was no alarm.
fn health_block(r: &ProcessReport) -> String {
    const SHOWN: usize = 5;
    let h = &r.health;
    let mut s = String::new();
    if h.alarms == 0 {
        return format!(
            "health: no alarm (innovations{} tested in windows of 20 updates)\n",
            if h.nees_checked {
                " and position NEES"
            } else {
                ""
            }
        );
    }
    for e in r.health_events.iter().take(SHOWN) {
        let tag = if e.kind == HealthEventKind::Recovered {
            "health"
        } else {
            "warning"
        };
        s += &format!("{tag}: {} {e}\n", r.filter);
    }
    if r.health_events.len() > SHOWN {
        s += &format!(
            "health: … {} more events ({} alarms in all)\n",
            r.health_events.len() - SHOWN,
            h.alarms
        );
    }
    if h.diverged() {
        s += &format!(
            "warning: {} diverged: the {} alarm is still raised at the end of the run\n",
            r.filter,
            if h.nees_checked {
                "position NEES"
            } else {
                "innovation"
            }
        );
    }
    s
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
