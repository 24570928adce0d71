//! After the pass: the result files put in place (or removed, when the
//! run failed), the statistics of the comparison with the truth, the
//! report and what is kept in memory for figures.

use std::path::{Path, PathBuf};

use super::evaluation::Evaluation;
use super::pipeline::{GnssSource, Job};
use super::{
    axis_names, AlignmentReport, Consistency, ErrorStats, ErrorTraces, Inputs, ProcessReport,
    Processed, Settings, StateTraces, Track, WindowDrift,
};
use crate::Error;

/// What the pass produced, as [`process`](super::process) returns it:
/// `outcome` is the pass's own result (a failure removes the result files
/// and is returned).
pub(super) fn finish(
    inputs: &Inputs,
    settings: &Settings,
    mut job: Job<'_>,
    outcome: Result<(), Error>,
    alignment: Option<AlignmentReport>,
) -> Result<Processed, Error> {
    // Nothing compared is an error, never a row of zeros.
    let outcome = outcome.and_then(|()| check_compared(&mut job, inputs, settings));
    let dir = job.out.clone();
    let (mut files, mut states) = close(&mut job, &dir, outcome)?;
    let (statistics, traces) = compared(&mut job, &dir, &mut files)?;
    let report = report(&mut job, settings, alignment, statistics, files);
    states.smoothed = std::mem::take(&mut job.smoothed_traces.states);
    let track = track(&job, inputs, settings);
    Ok(Processed {
        report,
        traces,
        track,
        states,
        provenance: Default::default(),
    })
}

/// An error if a truth was given but no epoch of the run was compared
/// with it, saying why.
fn check_compared(job: &mut Job<'_>, inputs: &Inputs, settings: &Settings) -> Result<(), Error> {
    let end_time = job.sink.end_time;
    match &mut job.sink.evaluation {
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
    }
}

/// Closes the forward pass's files: put in place when `outcome` is a
/// success, removed otherwise (and the error returned). Returns the files
/// written and the estimates and σ kept for figures.
fn close(
    job: &mut Job<'_>,
    out: &Path,
    outcome: Result<(), Error>,
) -> Result<(Vec<PathBuf>, StateTraces), Error> {
    let mut traces = StateTraces::default();
    let states = job.states.take().map(|mut s| {
        traces.estimates = s.estimate_names.clone();
        traces.sigmas = s.sigma_names.clone();
        traces.forward = std::mem::take(&mut s.rows.records);
        s.finish(outcome.is_ok())
    });
    job.sink.finish(outcome.is_ok())?;
    outcome?;
    let mut files = vec![out.join("result.nav"), out.join("result.csv")];
    if let Some(s) = states {
        files.extend(s?);
    }
    Ok((files, traces))
}

/// The forward solution's statistics against the truth (the report's
/// part; all empty without a truth).
#[derive(Default)]
struct Statistics {
    errors: Option<ErrorStats>,
    aiding_errors: Option<ErrorStats>,
    consistency: Option<Consistency>,
    drift: Vec<WindowDrift>,
}

/// The comparison with the truth, if any: its statistics, the summary and
/// drift tables written into `out` (named in `files` after the error CSV),
/// and the error traces of both solutions for figures.
fn compared(
    job: &mut Job<'_>,
    out: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<(Statistics, Option<ErrorTraces>), Error> {
    let Some(e) = job.sink.evaluation.take() else {
        return Ok((Statistics::default(), None));
    };
    let statistics = Statistics {
        errors: e.all.finish(),
        aiding_errors: e.aiding.finish(),
        consistency: Some(e.consistency),
        drift: e.drift.clone().finish(job.sink.end_time),
    };
    files.push(out.join("errors.csv"));
    files.extend(write_errors(out, &e, &statistics.drift)?);
    let smoothed = &mut job.smoothed_traces;
    let traces = ErrorTraces {
        every: e.errors.records,
        every_sigma: e.sigmas.records,
        aiding: e.updates.records,
        smoothed: std::mem::take(&mut smoothed.errors),
        smoothed_sigma: std::mem::take(&mut smoothed.sigmas),
        nees: e.nees.records,
        smoothed_nees: std::mem::take(&mut smoothed.nees),
    };
    Ok((statistics, Some(traces)))
}

/// The report of the run: the pass's counts, the alignment, the
/// statistics and the files.
fn report(
    job: &mut Job<'_>,
    settings: &Settings,
    alignment: Option<AlignmentReport>,
    statistics: Statistics,
    files: Vec<PathBuf>,
) -> ProcessReport {
    ProcessReport {
        filter: settings.kind.label(),
        samples: job.sink.samples,
        end_time: job.sink.end_time,
        fixes_used: job.fixes.used,
        fixes_in_outage: job.fixes.in_outage,
        fixes_refused_quality: job.gnss.as_ref().map_or(0, GnssSource::refused),
        fixes_before_start: job.fixes.before_start,
        fixes_after_end: job.fixes.after_end,
        updates: job.sink.updates,
        rejected: job.sink.rejected,
        constraints: job.constraints.counts,
        alignment,
        errors: statistics.errors,
        aiding_errors: statistics.aiding_errors,
        consistency: statistics.consistency,
        drift: statistics.drift,
        timing: job.timing.clone(),
        axes: settings.axes,
        files,
        smoothed: job.smoothed.take(),
        health: job.health.summary(),
        health_events: std::mem::take(&mut job.health_events),
    }
}

/// The tracks of the solutions and the fixes in metres from the initial
/// position, with the outage windows.
fn track(job: &Job<'_>, inputs: &Inputs, settings: &Settings) -> Track {
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
    Track {
        forward: local(&job.sink.track.records),
        smoothed: local(&job.smoothed_traces.track),
        fixes: local(&job.fix_track.records),
        outages: inputs.outages.iter().map(|o| (o.start, o.end)).collect(),
    }
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
    write_file(path, &text)
}

/// Writes `text` to the output file `path` (in the run's scratch folder).
fn write_file(path: &Path, text: &str) -> Result<(), Error> {
    let mut f = super::sink::create_output(path)?;
    std::io::Write::write_all(&mut f, text.as_bytes()).map_err(|e| Error::io(path, e))
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
    write_file(path, &text)
}
