//! Where each processed sample goes: the result files, the comparison with
//! the truth, the progress report.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::experiment::Adaptation;
use kestrel::nav::NavState;

use super::evaluation::{Evaluation, NavCovariance, Thinned};
use super::schedule::Schedule;
use crate::progress::Ticker;
use crate::Error;
use kestrel_io::gins::nav_line;

/// Header of the result CSV.
pub const RESULT_CSV_HEADER: &str =
    "week,time_s,lat_deg,lon_deg,height_m,vn_mps,ve_mps,vd_mps,roll_deg,pitch_deg,yaw_deg";

/// The outputs of a run.
pub(crate) struct Sink<'p> {
    pub label: &'static str,
    week: u32,
    interval: f64,
    schedule: Schedule,
    nav: BufWriter<File>,
    nav_path: PathBuf,
    csv: BufWriter<File>,
    line: String,
    csv_line: Vec<u8>,
    csv_path: PathBuf,
    pub evaluation: Option<Evaluation>,
    pub updates: usize,
    pub rejected: usize,
    pub samples: usize,
    pub end_time: f64,
    /// (time, latitude, longitude) of the samples, thinned for the track
    /// figure.
    pub track: Thinned<(f64, f64, f64)>,
    progress: Ticker<'p>,
}

/// Where the result goes and what it is compared with.
pub(crate) struct SinkSetup<'a, 'p> {
    pub label: &'static str,
    pub week: u32,
    pub interval: f64,
    pub nav_path: &'a Path,
    pub csv_path: &'a Path,
    pub evaluation: Option<Evaluation>,
    pub progress: Ticker<'p>,
}

/// Creates the output file `path` (inside the run's scratch folder: the
/// output transaction publishes it under its name when the run commits).
pub(crate) fn create_output(path: &Path) -> Result<File, Error> {
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(path)
        .map_err(|e| Error::io(path, e))
}

impl<'p> Sink<'p> {
    pub(crate) fn new(s: SinkSetup<'_, 'p>) -> Result<Self, Error> {
        let mut nav = BufWriter::with_capacity(1 << 16, create_output(s.nav_path)?);
        writeln!(
            nav,
            "# week sow lat_deg lon_deg h_m vN vE vD (m/s) roll pitch yaw (deg)"
        )
        .map_err(|e| Error::io(s.nav_path, e))?;
        let mut csv = BufWriter::with_capacity(1 << 16, create_output(s.csv_path)?);
        writeln!(csv, "{RESULT_CSV_HEADER}").map_err(|e| Error::io(s.csv_path, e))?;
        Ok(Self {
            label: s.label,
            week: s.week,
            interval: s.interval,
            schedule: Schedule::new(),
            nav,
            nav_path: s.nav_path.to_path_buf(),
            csv,
            line: String::with_capacity(256),
            csv_line: Vec::with_capacity(256),
            csv_path: s.csv_path.to_path_buf(),
            evaluation: s.evaluation,
            updates: 0,
            rejected: 0,
            samples: 0,
            end_time: 0.0,
            track: Thinned::default(),
            progress: s.progress,
        })
    }

    /// The solution after the sample at `nav.time`, with what the aiding
    /// update at that sample did, if there was one.
    pub(crate) fn sample(
        &mut self,
        nav: &NavState,
        update: Option<Adaptation>,
        covariance: Option<&NavCovariance>,
    ) -> Result<(), Error> {
        let t = nav.time;
        let finite = nav.pos.lat.is_finite()
            && nav.pos.lon.is_finite()
            && nav.pos.h.is_finite()
            && nav.vel.iter().all(|v| v.is_finite())
            && nav.att.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(Error::Failed(
                "the navigation solution is no longer finite".to_owned(),
            ));
        }
        self.samples += 1;
        self.end_time = t;
        self.track.push((t, nav.pos.lat, nav.pos.lon));
        if let Some(a) = update {
            self.updates += 1;
            self.rejected += usize::from(a.rejected);
        }
        if let Some(e) = self.evaluation.as_mut() {
            e.sample(nav, update, covariance)?;
        }
        if self.interval == 0.0 || self.schedule.due(t, 1.0 / self.interval) {
            self.write(nav)?;
        }
        self.progress.at(t)
    }

    /// One result line, formatted once: space-separated to the
    /// navigation file, the same text comma-separated to the CSV (numbers
    /// never contain spaces or commas).
    fn write(&mut self, nav: &NavState) -> Result<(), Error> {
        self.line.clear();
        nav_line(self.week, nav, &mut self.line);
        self.nav
            .write_all(self.line.as_bytes())
            .map_err(|e| Error::io(&self.nav_path, e))?;
        self.csv_line.clear();
        self.csv_line
            .extend(self.line.bytes().map(|b| if b == b' ' { b',' } else { b }));
        self.csv
            .write_all(&self.csv_line)
            .map_err(|e| Error::io(&self.csv_path, e))
    }

    /// Ends the progress report and flushes the files; when the run `succeeded`,
    /// puts them in place under their names (a rename, which replaces a
    /// symbolic link there rather than writing through it), otherwise
    /// deletes them.
    pub(crate) fn finish(&mut self, succeeded: bool) -> Result<(), Error> {
        self.progress.finish();
        let flushed = self
            .csv
            .flush()
            .map_err(|e| Error::io(&self.csv_path, e))
            .and_then(|()| self.nav.flush().map_err(|e| Error::io(&self.nav_path, e)));
        let evaluated = match self.evaluation.as_mut() {
            Some(e) => e.finish(succeeded && flushed.is_ok()),
            None => Ok(()),
        };
        let ok = succeeded && flushed.is_ok() && evaluated.is_ok();
        for path in [&self.nav_path, &self.csv_path] {
            keep_or_discard(path, ok)?;
        }
        flushed.and(evaluated)
    }
}

/// Removes the output file `path` unless `ok` (a failed run publishes
/// nothing; the scratch folder goes anyway, this frees its space early).
pub(crate) fn keep_or_discard(path: &Path, ok: bool) -> Result<(), Error> {
    if !ok {
        // Best effort: the run's own error is the one to report.
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}
