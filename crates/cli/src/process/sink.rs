//! Where each processed sample goes: the result files, the comparison with
//! the truth, the progress bar.

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use kestrel::nav::experiment::{Adaptation, EpochRecord};
use kestrel::nav::{Ellipsoid, NavError, NavState};

use super::progress::Progress;
use super::schedule::Schedule;
use super::stats::Accumulator;
use crate::gins::{nav_line, NavReader, NavRecord, WEEK_SECONDS};
use crate::{CliError, InputError};

/// Header of the result CSV.
pub const RESULT_CSV_HEADER: &str =
    "week,time_s,lat_deg,lon_deg,height_m,vn_mps,ve_mps,vd_mps,roll_deg,pitch_deg,yaw_deg";

/// Truth times within this many seconds of a sample are the same instant.
const SAME_TIME: f64 = 1e-6;

/// The truth file, read forward as the run goes.
pub(crate) struct Truth {
    reader: NavReader<BufReader<File>>,
    current: Option<NavRecord>,
    /// The week of the file's first line: later weeks continue its
    /// seconds of week (as the IMU and GNSS times do across a rollover).
    first_week: Option<u32>,
}

impl Truth {
    pub(crate) fn open(path: &Path) -> Result<Self, InputError> {
        Ok(Self {
            reader: NavReader::open(path)?,
            current: None,
            first_week: None,
        })
    }

    /// The truth at `t` s of week, if the file has a line at that time.
    fn at(&mut self, t: f64) -> Result<Option<NavState>, InputError> {
        loop {
            match self.current {
                Some(r) if r.state.time >= t - SAME_TIME => {
                    return Ok((r.state.time <= t + SAME_TIME).then_some(r.state))
                }
                _ => match self.reader.next() {
                    Some(r) => {
                        let mut r = r?;
                        let first = *self.first_week.get_or_insert(r.week);
                        r.state.time += f64::from(r.week.saturating_sub(first)) * WEEK_SECONDS;
                        self.current = Some(r);
                    }
                    None => return Ok(None),
                },
            }
        }
    }
}

/// The outputs of a run.
pub(crate) struct Sink {
    pub label: &'static str,
    earth: Ellipsoid,
    week: u32,
    interval: f64,
    schedule: Schedule,
    nav: BufWriter<File>,
    nav_path: PathBuf,
    csv: BufWriter<File>,
    line: String,
    csv_line: Vec<u8>,
    csv_path: PathBuf,
    truth: Option<Truth>,
    pub records: Vec<EpochRecord>,
    pub acc: Accumulator,
    pub updates: usize,
    pub rejected: usize,
    pub samples: usize,
    pub end_time: f64,
    progress: Progress,
}

/// Where the result goes and what it is compared with.
pub(crate) struct SinkSetup<'a> {
    pub label: &'static str,
    pub earth: Ellipsoid,
    pub week: u32,
    pub interval: f64,
    pub nav_path: &'a Path,
    pub csv_path: &'a Path,
    pub truth: Option<Truth>,
    pub acc: Accumulator,
    pub progress: Progress,
}

/// The file a result is written to until the run succeeds: `.NAME.partial`
/// beside it, so a failed or interrupted run never leaves a file under the
/// result's name that looks complete.
pub(crate) fn partial_path(path: &Path) -> PathBuf {
    let name = path.file_name().map_or_else(
        || std::ffi::OsString::from("result"),
        std::ffi::OsStr::to_os_string,
    );
    let mut partial = std::ffi::OsString::from(".");
    partial.push(name);
    partial.push(".partial");
    path.with_file_name(partial)
}

/// Creates the partial file of `path` afresh: a stale one (or a symbolic
/// link in its place) is removed, never followed.
fn create_partial(path: &Path) -> Result<File, CliError> {
    let partial = partial_path(path);
    match std::fs::remove_file(&partial) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(CliError::io(&partial, e)),
    }
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&partial)
        .map_err(|e| CliError::io(&partial, e))
}

impl Sink {
    pub(crate) fn new(s: SinkSetup<'_>) -> Result<Self, CliError> {
        let mut nav = BufWriter::with_capacity(1 << 16, create_partial(s.nav_path)?);
        writeln!(
            nav,
            "# week sow lat_deg lon_deg h_m vN vE vD (m/s) roll pitch yaw (deg)"
        )
        .map_err(|e| CliError::io(s.nav_path, e))?;
        let mut csv = BufWriter::with_capacity(1 << 16, create_partial(s.csv_path)?);
        writeln!(csv, "{RESULT_CSV_HEADER}").map_err(|e| CliError::io(s.csv_path, e))?;
        Ok(Self {
            label: s.label,
            earth: s.earth,
            week: s.week,
            interval: s.interval,
            schedule: Schedule::new(),
            nav,
            nav_path: s.nav_path.to_path_buf(),
            csv,
            line: String::with_capacity(256),
            csv_line: Vec::with_capacity(256),
            csv_path: s.csv_path.to_path_buf(),
            truth: s.truth,
            records: Vec::new(),
            acc: s.acc,
            updates: 0,
            rejected: 0,
            samples: 0,
            end_time: 0.0,
            progress: s.progress,
        })
    }

    /// The solution after the sample at `nav.time`, with what the aiding
    /// update at that sample did, if there was one.
    pub(crate) fn sample(
        &mut self,
        nav: &NavState,
        update: Option<Adaptation>,
    ) -> Result<(), CliError> {
        let t = nav.time;
        let finite = nav.pos.lat.is_finite()
            && nav.pos.lon.is_finite()
            && nav.pos.h.is_finite()
            && nav.vel.iter().all(|v| v.is_finite())
            && nav.att.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(CliError::Failed(format!(
                "{} diverged at {t} s of week: non-finite navigation solution",
                self.label
            )));
        }
        self.samples += 1;
        self.end_time = t;
        if let Some(a) = update {
            self.updates += 1;
            self.rejected += usize::from(a.rejected);
            self.compare(nav, a)?;
        }
        if self.interval == 0.0 || self.schedule.due(t, 1.0 / self.interval) {
            self.write(nav)?;
        }
        self.progress.at(t);
        Ok(())
    }

    fn compare(&mut self, nav: &NavState, adaptation: Adaptation) -> Result<(), CliError> {
        let Some(truth) = self.truth.as_mut() else {
            return Ok(());
        };
        let Some(truth) = truth.at(nav.time)? else {
            return Ok(());
        };
        let e = NavError::between(&self.earth, nav, &truth);
        if !e.to_vector().iter().all(|v| v.is_finite()) {
            return Err(CliError::Failed(format!(
                "{} diverged at {} s of week: non-finite error against the truth",
                self.label, nav.time
            )));
        }
        let r = EpochRecord {
            time: nav.time,
            position: e.dr,
            velocity: e.dv,
            attitude: e.phi,
            adaptation,
        };
        self.acc.add(&r);
        self.records.push(r);
        Ok(())
    }

    /// One result line, formatted once: space-separated to the
    /// navigation file, the same text comma-separated to the CSV (numbers
    /// never contain spaces or commas).
    fn write(&mut self, nav: &NavState) -> Result<(), CliError> {
        self.line.clear();
        nav_line(self.week, nav, &mut self.line);
        self.nav
            .write_all(self.line.as_bytes())
            .map_err(|e| CliError::io(&self.nav_path, e))?;
        self.csv_line.clear();
        self.csv_line
            .extend(self.line.bytes().map(|b| if b == b' ' { b',' } else { b }));
        self.csv
            .write_all(&self.csv_line)
            .map_err(|e| CliError::io(&self.csv_path, e))
    }

    /// Removes the bar and flushes the files; when the run `succeeded`,
    /// puts them in place under their names (a rename, which replaces a
    /// symbolic link there rather than writing through it), otherwise
    /// deletes them.
    pub(crate) fn finish(&mut self, succeeded: bool) -> Result<(), CliError> {
        self.progress.finish();
        let flushed = self
            .csv
            .flush()
            .map_err(|e| CliError::io(&self.csv_path, e))
            .and_then(|()| {
                self.nav
                    .flush()
                    .map_err(|e| CliError::io(&self.nav_path, e))
            });
        for path in [&self.nav_path, &self.csv_path] {
            let partial = partial_path(path);
            if succeeded && flushed.is_ok() {
                std::fs::rename(&partial, path).map_err(|e| CliError::io(path, e))?;
            } else {
                // Best effort: the run's own error is the one to report.
                let _ = std::fs::remove_file(&partial);
            }
        }
        flushed
    }
}
