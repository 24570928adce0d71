//! The processing loop: IMU samples in file order, the aiding due at each,
//! the outputs — one monomorphised loop per filter type.

use std::collections::VecDeque;
use std::fs::File;
use std::io::BufReader;

use crate::experiment::Adaptation;
use kestrel::adapter::PriorAdapter;
use kestrel::form::{Form, PredictForm, UpdateForm};
use kestrel::nav::engine::{ErrorSystem, LooselyCoupled};
use kestrel::nav::measurement::{
    ErrorMeasurement, GnssFix, OdometerReading, ZeroAngularRate, ZeroVelocity,
};
use kestrel::FilterError;

use super::divergence::{describe, Step};
use super::outage::Outage;
use super::schedule::Schedule;
use super::sink::Sink;
use super::timing::{ImuTiming, TimingReport, TimingRule, NOMINAL_SAMPLES};
use crate::config::process::GnssFormat;
use crate::{Error, InputError};
use kestrel_io::gins::{
    GnssReader, ImuReader, ImuRecord, OdometerReader, RtklibReader, SpeedRecord,
};

/// The inputs of a run and its outputs.
pub(crate) struct Job<'p> {
    pub imu: ImuReader<BufReader<File>>,
    pub gnss: Option<GnssSource>,
    /// Odometer update rate (Hz) when odometer speeds are used.
    pub odometer_rate: Option<f64>,
    /// The odometer's own file (else the IMU file's odometer column).
    pub odometer_file: Option<OdometerFile>,
    pub outages: Vec<Outage>,
    pub start: f64,
    pub sink: Sink<'p>,
    /// GNSS fixes used, skipped in outages, before the initial time and
    /// after the last IMU sample (read and checked, not used).
    pub fixes_used: usize,
    pub fixes_in_outage: usize,
    pub fixes_before_start: usize,
    pub fixes_after_end: usize,
    /// The error-state model (to name state components in errors).
    pub error_model: crate::scenario::ErrorModelKind,
    /// The treatment of IMU gaps, and what was seen.
    pub timing_rule: TimingRule,
    pub timing: TimingReport,
    /// IMU records read ahead (to estimate the nominal interval).
    pub pending: VecDeque<ImuRecord>,
    /// The record for `--smooth`.
    pub smoother: Option<super::smooth::ForwardRecord>,
    /// What the smoother did.
    pub smoothed: Option<super::smooth::SmoothedReport>,
    /// The output folder and interval (for the state files).
    pub out: std::path::PathBuf,
    pub output_interval: f64,
    /// The forward run's IMU error estimates and σ (created with the
    /// engine's layout).
    pub states: Option<super::state_files::StateFiles>,
    /// The fixes used: (time, latitude, longitude), thinned.
    pub fix_track: super::evaluation::Thinned<(f64, f64, f64)>,
    /// Standstill and non-holonomic pseudo-measurements.
    pub constraints: super::constraints::Constraints,
    /// The smoothed solution's errors, thinned (with a truth).
    pub smoothed_traces: super::smooth::SmoothedTraces,
}

/// A reading of the odometer file is used for this long after its time, s:
/// longer, the odometer is taken to be silent (no update).
pub const ODOMETER_MAX_AGE: f64 = 1.0;

/// The odometer's own file, read forward: the speed at a time is the
/// latest reading at or before it.
pub(crate) struct OdometerFile {
    reader: OdometerReader<BufReader<File>>,
    ahead: Option<SpeedRecord>,
    latest: Option<SpeedRecord>,
    /// Readings that became the latest (reached by the run).
    reached: usize,
}

impl OdometerFile {
    pub(crate) fn new(reader: OdometerReader<BufReader<File>>) -> Self {
        Self {
            reader,
            ahead: None,
            latest: None,
            reached: 0,
        }
    }

    /// The speed at `t` and its line: the latest reading at or before `t`,
    /// if at most [`ODOMETER_MAX_AGE`] old.
    fn speed_at(&mut self, t: f64) -> Result<Option<(f64, usize)>, InputError> {
        loop {
            if self.ahead.is_none() {
                self.ahead = self.reader.next().transpose()?;
            }
            match self.ahead {
                Some(r) if r.time <= t => {
                    self.latest = self.ahead.take();
                    self.reached += 1;
                }
                _ => break,
            }
        }
        Ok(self
            .latest
            .filter(|r| t - r.time <= ODOMETER_MAX_AGE)
            .map(|r| (r.speed, r.line)))
    }

    fn path(&self) -> &std::path::Path {
        self.reader.path()
    }
}

/// The GNSS file in the format the configuration names.
pub(crate) enum GnssInput {
    /// The GINS text format.
    Gins(GnssReader<BufReader<File>>),
    /// RTKLIB `.pos`.
    Rtklib(RtklibReader<BufReader<File>>),
}

impl GnssInput {
    /// Opens the GNSS file at `path` in `format`; times in seconds of GPS
    /// week `week0`.
    pub(crate) fn open(
        path: &std::path::Path,
        format: &GnssFormat,
        week0: u32,
    ) -> Result<Self, InputError> {
        Ok(match format {
            GnssFormat::Gins => Self::Gins(GnssReader::open(path)?),
            GnssFormat::Rtklib { quality } => {
                Self::Rtklib(RtklibReader::open(path, week0, quality)?)
            }
        })
    }

    fn last_line(&self) -> Option<usize> {
        match self {
            Self::Gins(r) => r.last_line(),
            Self::Rtklib(r) => r.last_line(),
        }
    }

    fn path(&self) -> &std::path::Path {
        match self {
            Self::Gins(r) => r.path(),
            Self::Rtklib(r) => r.path(),
        }
    }

    /// Fixes skipped for their quality flag.
    pub(crate) fn refused(&self) -> usize {
        match self {
            Self::Gins(_) => 0,
            Self::Rtklib(r) => r.refused(),
        }
    }
}

impl Iterator for GnssInput {
    type Item = Result<GnssFix, InputError>;

    fn next(&mut self) -> Option<Self::Item> {
        match self {
            Self::Gins(r) => r.next(),
            Self::Rtklib(r) => r.next(),
        }
    }
}

/// The GNSS file read one fix ahead, each fix with its line.
pub(crate) struct GnssSource {
    reader: GnssInput,
    ahead: Option<(GnssFix, usize)>,
}

impl GnssSource {
    /// The GNSS file at its first fix (an error in the lines before it is
    /// returned here).
    pub(crate) fn open(reader: GnssInput) -> Result<Self, InputError> {
        let mut s = Self {
            reader,
            ahead: None,
        };
        s.fill()?;
        Ok(s)
    }

    fn fill(&mut self) -> Result<(), InputError> {
        if self.ahead.is_none()
            && let Some(fix) = self.reader.next().transpose()?
        {
            self.ahead = Some((fix, self.reader.last_line().unwrap_or(0)));
        }
        Ok(())
    }

    /// The next fix, not consumed.
    pub(crate) fn peek(&mut self) -> Result<Option<&GnssFix>, InputError> {
        self.fill()?;
        Ok(self.ahead.as_ref().map(|(f, _)| f))
    }

    /// The next fix and its line.
    fn take(&mut self) -> Result<Option<(GnssFix, usize)>, InputError> {
        self.fill()?;
        Ok(self.ahead.take())
    }

    /// The file's name.
    pub(crate) fn path(&self) -> &std::path::Path {
        self.reader.path()
    }

    /// Fixes skipped for their quality flag.
    pub(crate) fn refused(&self) -> usize {
        self.reader.refused()
    }
}

impl Job<'_> {
    /// The first IMU record after the start time.
    fn first_imu(&mut self) -> Result<ImuRecord, Error> {
        for r in self.imu.by_ref() {
            let r = r?;
            if r.time > self.start {
                return Ok(r);
            }
        }
        Err(Error::Failed(format!(
            "no IMU sample after the initial time {} s of week",
            self.start
        )))
    }

    /// The next IMU record: read ahead first, then from the file.
    fn next_imu(&mut self) -> Result<Option<ImuRecord>, InputError> {
        match self.pending.pop_front() {
            Some(r) => Ok(Some(r)),
            None => self.imu.next().transpose(),
        }
    }

    /// Reads ahead the first samples after the start and sets up the
    /// timing from their median interval.
    fn start_timing(&mut self) -> Result<ImuTiming, Error> {
        let first = self.first_imu()?;
        self.pending.push_back(first);
        while self.pending.len() <= NOMINAL_SAMPLES {
            match self.imu.next().transpose()? {
                Some(r) => self.pending.push_back(r),
                None => break,
            }
        }
        let first: Vec<ImuRecord> = self.pending.iter().copied().collect();
        Ok(ImuTiming::new(self.timing_rule, self.imu.path(), &first)?
            .integrated(self.imu.integrated()))
    }

    /// The next GNSS fix to use at the sample at `t` (the next sample at
    /// `next`), with its line: fixes at `t ≤ time < next` belong to this
    /// sample (the engine extrapolates to them); fixes before the start are
    /// counted and dropped.
    fn gnss_due(
        &mut self,
        t: f64,
        next: Option<f64>,
    ) -> Result<Option<(GnssFix, usize)>, InputError> {
        let Some(gnss) = self.gnss.as_mut() else {
            return Ok(None);
        };
        loop {
            let Some(time) = gnss.peek()?.map(|f| f.time) else {
                return Ok(None);
            };
            if time > self.start && next.map_or(time > t, |n| time >= n) {
                return Ok(None);
            }
            let Some((fix, line)) = gnss.take()? else {
                return Ok(None);
            };
            if fix.time <= self.start {
                self.fixes_before_start += 1;
                continue;
            }
            if self.outages.iter().any(|o| o.contains(fix.time)) {
                self.fixes_in_outage += 1;
                continue;
            }
            self.fixes_used += 1;
            if let Some(e) = self.sink.evaluation.as_mut() {
                e.drift.fix(fix.time);
            }
            if let Some(r) = self.smoother.as_mut() {
                r.fix(fix.time);
            }
            self.fix_track.push((fix.time, fix.pos.lat, fix.pos.lon));
            return Ok(Some((fix, line)));
        }
    }

    /// An odometer file none of whose readings the run reached is an error
    /// (an empty file, or one whose times miss the IMU's), never a run
    /// that silently had no odometer.
    fn check_odometer_file(&self) -> Result<(), Error> {
        match &self.odometer_file {
            Some(f) if f.reached == 0 => Err(InputError::file(
                f.path(),
                "no odometer reading at or before the last IMU sample (an empty file, or \
                 times that are not GPS seconds of week like the IMU's)",
            )
            .into()),
            _ => Ok(()),
        }
    }

    /// Reads and checks the GNSS lines after the last IMU sample, counting
    /// their fixes (none is used; a bad line is still an error).
    fn drain_gnss(&mut self) -> Result<(), InputError> {
        if let Some(gnss) = self.gnss.as_mut() {
            while gnss.take()?.is_some() {
                self.fixes_after_end += 1;
            }
        }
        Ok(())
    }
}

/// Runs `engine` over the job's data; `gnss` and `odometer` update it.
pub(crate) fn drive<const N: usize, S, F, A>(
    job: &mut Job<'_>,
    engine: &mut LooselyCoupled<f64, N, S, F, A>,
    mut gnss: impl FnMut(
        &mut LooselyCoupled<f64, N, S, F, A>,
        &GnssFix,
    ) -> Result<Adaptation, FilterError>,
    mut odometer: impl FnMut(
        &mut LooselyCoupled<f64, N, S, F, A>,
        &OdometerReading,
    ) -> Result<Adaptation, FilterError>,
) -> Result<(), Error>
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process> + Constrainable<N>,
    A: PriorAdapter<f64>,
{
    let label = job.sink.label;
    job.states = Some(super::state_files::StateFiles::create::<N, S>(
        &job.out,
        "result",
        job.output_interval,
    )?);
    let mut schedule = Schedule::new();
    let mut previous = (job.start, None);
    let mut timing = job.start_timing()?;
    let mut current = job.next_imu()?;
    if let (Some(_), Some(r), None) = (job.odometer_rate, &current, &job.odometer_file)
        && r.odometer.is_none()
    {
        return Err(InputError::at(
            job.imu.path(),
            r.line,
            8,
            "expected an 8th column (odometer speed, m/s): --odo is given",
        )
        .into());
    }
    let imu_path = job.imu.path().to_path_buf();
    let outcome = loop {
        let Some(sample) = current else {
            break job
                .drain_gnss()
                .map_err(Error::from)
                .and_then(|()| job.check_odometer_file());
        };
        match step(
            job,
            engine,
            &mut timing,
            &mut schedule,
            &sample,
            previous,
            (label, &imu_path),
            &mut gnss,
            &mut odometer,
        ) {
            Ok(following) => {
                previous = (sample.time, Some(sample.line));
                current = following;
            }
            Err(e) => break Err(e),
        }
    };
    job.timing = timing.report();
    outcome
}

/// One IMU sample and the aiding due at it; returns the next sample.
#[allow(clippy::too_many_arguments)]
fn step<const N: usize, S, F, A>(
    job: &mut Job<'_>,
    engine: &mut LooselyCoupled<f64, N, S, F, A>,
    timing: &mut ImuTiming,
    schedule: &mut Schedule,
    sample: &ImuRecord,
    previous: (f64, Option<usize>),
    (label, imu_path): (&str, &std::path::Path),
    gnss: &mut impl FnMut(
        &mut LooselyCoupled<f64, N, S, F, A>,
        &GnssFix,
    ) -> Result<Adaptation, FilterError>,
    odometer: &mut impl FnMut(
        &mut LooselyCoupled<f64, N, S, F, A>,
        &OdometerReading,
    ) -> Result<Adaptation, FilterError>,
) -> Result<Option<ImuRecord>, Error>
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process> + Constrainable<N>,
    A: PriorAdapter<f64>,
{
    let following = job.next_imu()?;
    let t = sample.time;
    let model = job.error_model;
    // Messages are formatted only on failure: nothing here allocates per
    // sample.
    let imu_line = || format!("{}:{}", imu_path.display(), sample.line);
    let diverged = |error: FilterError, step: Step, input: String| {
        let doing = match step {
            Step::Imu => "propagating",
            Step::Gnss(_) => "in the GNSS update",
            Step::Odometer => "in the odometer update",
            Step::ZeroVelocity => "in a zero-velocity update",
            Step::ZeroAngularRate => "in a zero-angular-rate update",
            Step::NonHolonomic => "in a non-holonomic update",
        };
        Error::Failed(format!(
            "{label} diverged at {t} s of week {doing} ({input}): {}",
            describe(&error, model, step)
        ))
    };
    let increment = timing.increment(sample, previous.0, previous.1)?;
    engine
        .imu(&increment)
        .map_err(|e| diverged(e, Step::Imu, format!("IMU line {}", imu_line())))?;
    record_epoch(job, engine)?;
    // The IMU says "no vibration, no manoeuvre"; the INS speed rules out a
    // smooth drive at constant velocity, which the IMU cannot tell apart.
    let standing = match job.constraints.zupt.as_mut() {
        Some((detector, z, _)) => {
            detector.push(&increment) && engine.solution().vel.norm() < z.max_speed
        }
        None => false,
    };
    job.constraints.counts.standstill_samples += usize::from(standing);
    if let Some((_, z, schedule)) = job.constraints.zupt.as_mut()
        && standing
        && schedule.due(t, z.rate)
    {
        let (v_std, w_std) = (z.velocity_std, z.angular_rate_std);
        let ins = engine.ins_context(t);
        let m = ZeroVelocity::new(v_std).measurement(engine.system(), &ins);
        engine
            .apply_with(&m, &mut ())
            .map_err(|e| diverged(e, Step::ZeroVelocity, format!("IMU line {}", imu_line())))?;
        record_epoch(job, engine)?;
        job.constraints.counts.zero_velocity += 1;
        if w_std > 0.0 {
            let ins = engine.ins_context(t);
            let m = ZeroAngularRate::new(w_std).measurement(engine.system(), &ins);
            engine.apply_with(&m, &mut ()).map_err(|e| {
                diverged(e, Step::ZeroAngularRate, format!("IMU line {}", imu_line()))
            })?;
            record_epoch(job, engine)?;
            job.constraints.counts.zero_angular_rate += 1;
        }
    }
    if let Some((model, rate, schedule)) = job.constraints.nhc.as_mut() {
        // At standstill the zero-velocity update says more.
        if schedule.due(t, *rate) && !standing {
            let ins = engine.ins_context(t);
            let m = model.nhc(engine.system(), &ins);
            engine
                .apply_with(&m, &mut ())
                .map_err(|e| diverged(e, Step::NonHolonomic, format!("IMU line {}", imu_line())))?;
            record_epoch(job, engine)?;
            job.constraints.counts.non_holonomic += 1;
        }
    }
    let mut update = None;
    while let Some((fix, line)) = job.gnss_due(t, following.as_ref().map(|f| f.time))? {
        let rows = if fix.vel.is_some() { 6 } else { 3 };
        let gnss_path = job.gnss.as_ref().map(GnssSource::path);
        let input = || match gnss_path {
            Some(p) => format!("GNSS line {}:{line}", p.display()),
            None => format!("GNSS line {line}"),
        };
        update = Some(gnss(engine, &fix).map_err(|e| diverged(e, Step::Gnss(rows), input()))?);
        record_epoch(job, engine)?;
    }
    // The speed, and its line in the odometer file (`None`: the IMU file).
    let speed = match job.odometer_file.as_mut() {
        Some(f) => f.speed_at(t)?.map(|(speed, line)| (speed, Some(line))),
        None => sample.odometer.map(|speed| (speed, None)),
    };
    if let (Some(rate), Some((speed, line))) = (job.odometer_rate, speed)
        && schedule.due(t, rate)
    {
        let reading = OdometerReading::new(t, speed);
        let input = || match (line, job.odometer_file.as_ref()) {
            (Some(l), Some(f)) => format!("odometer line {}:{l}", f.path().display()),
            _ => format!("odometer speed of IMU line {}", imu_line()),
        };
        update =
            Some(odometer(engine, &reading).map_err(|e| diverged(e, Step::Odometer, input()))?);
        record_epoch(job, engine)?;
    }
    // The navigation block of the error covariance, for the NEES and the
    // σ envelopes (only with a truth: a copy of P per sample otherwise
    // wasted).
    let covariance = job
        .sink
        .evaluation
        .is_some()
        .then(|| engine.covariance().fixed_view::<9, 9>(0, 0).into_owned());
    job.sink
        .sample(engine.solution(), update, covariance.as_ref())
        .map_err(|e| match e {
            Error::Failed(m) => Error::Failed(format!(
                "{label} diverged at {t} s of week after IMU line {}: {m}",
                imu_line()
            )),
            other => other,
        })?;
    if let Some(r) = job.smoother.as_mut() {
        r.sample(engine.solution(), engine.corrections())?;
    }
    // A covariance epoch (propagated or updated at this sample): the
    // filter's estimates and σ, at the output interval.
    if let Some(states) = job.states.as_mut()
        && engine.pending_interval() == 0.0
        && states.due(t)
    {
        let sigma = engine.std_devs();
        states.row(t, engine.corrections(), sigma.iter().copied())?;
    }
    Ok(following)
}

/// The update forms the pseudo-measurements need: 3 rows (zero velocity,
/// zero angular rate) and 2 (non-holonomic), without an adapter.
pub(crate) trait Constrainable<const N: usize>:
    UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>
    + UpdateForm<f64, N, ErrorMeasurement<f64, N, 2>, 2>
{
}

impl<const N: usize, F> Constrainable<N> for F where
    F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>
        + UpdateForm<f64, N, ErrorMeasurement<f64, N, 2>, 2>
{
}

/// Streams the covariance epoch the engine closed, if any, to the
/// smoother's record.
fn record_epoch<const N: usize, S, F, A>(
    job: &mut Job<'_>,
    engine: &mut LooselyCoupled<f64, N, S, F, A>,
) -> Result<(), Error>
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process>,
    A: PriorAdapter<f64>,
{
    match (job.smoother.as_mut(), engine.take_epoch()) {
        (Some(r), Some(e)) => r.epoch(&e),
        _ => Ok(()),
    }
}
