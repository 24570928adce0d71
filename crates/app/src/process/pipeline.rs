//! The processing loop: IMU samples in file order, the aiding due at each,
//! the outputs — one monomorphised loop per filter type.

use kestrel_io::input::Input as In;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use crate::experiment::{Adaptation, Health, HealthEvent, HealthEventKind};
use kestrel::adapter::PriorAdapter;
use kestrel::form::{Form, PredictForm, UpdateForm};
use kestrel::nav::engine::{ErrorSystem, LooselyCoupled};
use kestrel::nav::measurement::{
    ErrorMeasurement, GnssFix, OdometerReading, ZeroAngularRate, ZeroVelocity,
};
use kestrel::nav::ImuIncrement;
use kestrel::FilterError;

use super::constraints::Constraints;
use super::divergence::{describe, Step};
use super::evaluation::Thinned;
use super::outage::Outage;
use super::schedule::Schedule;
use super::sink::Sink;
use super::smooth::{ForwardRecord, SmoothedReport, SmoothedTraces};
use super::state_files::StateFiles;
use super::timing::{ImuTiming, TimingReport, TimingRule, NOMINAL_SAMPLES};
use super::{Inputs, OdometerInput};
use crate::config::process::{GnssFormat, Settings};
use crate::scenario::ErrorModelKind;
use crate::{Error, InputError};
use kestrel_io::gins::{
    GnssReader, ImuReader, ImuRecord, OdometerReader, RtklibReader, SpeedRecord,
};

/// The inputs of a run and its outputs: what the forward pass reads,
/// writes and counts.
pub(crate) struct Job<'p> {
    pub imu: ImuReader<In>,
    pub gnss: Option<GnssSource>,
    /// Odometer update rate (Hz) when odometer speeds are used.
    pub odometer_rate: Option<f64>,
    /// The odometer's own file (else the IMU file's odometer column).
    pub odometer_file: Option<OdometerFile>,
    pub outages: Vec<Outage>,
    pub start: f64,
    pub sink: Sink<'p>,
    /// What became of the GNSS fixes read.
    pub fixes: FixCounts,
    /// The error-state model (to name state components in errors).
    pub error_model: ErrorModelKind,
    /// The treatment of IMU gaps, and what was seen.
    pub timing_rule: TimingRule,
    pub timing: TimingReport,
    /// IMU records read ahead (to estimate the nominal interval).
    pub pending: VecDeque<ImuRecord>,
    /// The record for `--smooth`.
    pub smoother: Option<ForwardRecord>,
    /// What the smoother did.
    pub smoothed: Option<SmoothedReport>,
    /// The output folder and interval (for the state files).
    pub out: PathBuf,
    pub output_interval: f64,
    /// The forward run's IMU error estimates and σ (created with the
    /// engine's layout).
    pub states: Option<StateFiles>,
    /// The fixes used: (time, latitude, longitude), thinned.
    pub fix_track: Thinned<(f64, f64, f64)>,
    /// Standstill and non-holonomic pseudo-measurements.
    pub constraints: Constraints,
    /// The smoothed solution's errors, thinned (with a truth).
    pub smoothed_traces: SmoothedTraces,
    /// The filter-health monitor ([`Health`]).
    pub health: Health,
    /// Its events (alarms, refusals, recoveries), the first
    /// [`HEALTH_EVENTS`] of them.
    pub health_events: Vec<HealthEvent>,
    /// Stop the run at the first alarm (`--stop-on-divergence`).
    pub stop_on_divergence: bool,
}

/// The most health events a run keeps for its report.
pub(crate) const HEALTH_EVENTS: usize = 100;

/// The GNSS fixes of a run: used, skipped in outages, before the initial
/// time and after the last IMU sample (read and checked, not used).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FixCounts {
    /// Used in an update.
    pub used: usize,
    /// Skipped in an outage window.
    pub in_outage: usize,
    /// At or before the initial time.
    pub before_start: usize,
    /// After the last IMU sample.
    pub after_end: usize,
}

/// A reading of the odometer file is used for this long after its time, s:
/// longer, the odometer is taken to be silent (no update).
pub const ODOMETER_MAX_AGE: f64 = 1.0;

/// The odometer's own file, read forward: the speed at a time is the
/// latest reading at or before it.
pub(crate) struct OdometerFile {
    reader: OdometerReader<In>,
    ahead: Option<SpeedRecord>,
    latest: Option<SpeedRecord>,
    /// Readings that became the latest (reached by the run).
    reached: usize,
}

impl OdometerFile {
    pub(crate) fn new(reader: OdometerReader<In>) -> Self {
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
    Gins(GnssReader<In>),
    /// RTKLIB `.pos`.
    Rtklib(RtklibReader<In>),
}

impl GnssInput {
    /// The GNSS file `reader` (named `path`) in `format`; times in seconds
    /// of GPS week `week0`.
    pub(crate) fn new(reader: In, path: &std::path::Path, format: &GnssFormat, week0: u32) -> Self {
        match format {
            GnssFormat::Gins => Self::Gins(GnssReader::new(reader, path)),
            GnssFormat::Rtklib { quality } => {
                Self::Rtklib(RtklibReader::new(reader, path, week0, quality))
            }
        }
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

/// The GNSS file read ahead, each fix with its line: the alignment and
/// the gap threshold look ahead (the fixes they see stay buffered) and the
/// pass then takes every fix once, in order. The file is read once.
pub(crate) struct GnssSource {
    reader: GnssInput,
    ahead: VecDeque<(GnssFix, usize)>,
    /// The error of the line after the buffered fixes: reported when the
    /// pass reaches it, not when a look-ahead does.
    failed: Option<InputError>,
}

impl GnssSource {
    /// The GNSS file at its first fix (an error in the lines before it is
    /// returned here).
    pub(crate) fn open(reader: GnssInput) -> Result<Self, InputError> {
        let mut s = Self {
            reader,
            ahead: VecDeque::new(),
            failed: None,
        };
        s.fill(1);
        s.report_at_front()?;
        Ok(s)
    }

    /// Reads ahead until `n` fixes are buffered, the file ends or a line
    /// is bad (kept in `failed`).
    fn fill(&mut self, n: usize) {
        while self.ahead.len() < n && self.failed.is_none() {
            match self.reader.next() {
                Some(Ok(fix)) => {
                    let line = self.reader.last_line().unwrap_or(0);
                    self.ahead.push_back((fix, line));
                }
                Some(Err(e)) => self.failed = Some(e),
                None => return,
            }
        }
    }

    /// The bad line's error once every fix before it is consumed.
    fn report_at_front(&mut self) -> Result<(), InputError> {
        match self.failed.take() {
            Some(e) if self.ahead.is_empty() => Err(e),
            failed => {
                self.failed = failed;
                Ok(())
            }
        }
    }

    /// The error of a bad line a look-ahead stopped at (taken: a caller
    /// that cannot go on without the fixes past it reports it now).
    pub(crate) fn take_failure(&mut self) -> Option<InputError> {
        self.failed.take()
    }

    /// The next fix, not consumed.
    pub(crate) fn peek(&mut self) -> Result<Option<&GnssFix>, InputError> {
        self.fill(1);
        self.report_at_front()?;
        Ok(self.ahead.front().map(|(f, _)| f))
    }

    /// The `i`-th fix ahead (0 is the next), not consumed: read into the
    /// buffer if need be. `None` past the end of the file and past a bad
    /// line (whose error the pass gets when it reaches it).
    pub(crate) fn ahead(&mut self, i: usize) -> Result<Option<&GnssFix>, InputError> {
        self.fill(i + 1);
        self.report_at_front()?;
        Ok(self.ahead.get(i).map(|(f, _)| f))
    }

    /// The next fix and its line.
    fn take(&mut self) -> Result<Option<(GnssFix, usize)>, InputError> {
        self.fill(1);
        self.report_at_front()?;
        Ok(self.ahead.pop_front())
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

impl<'p> Job<'p> {
    /// The job of reading `imu` and `gnss` (and the odometer speeds
    /// `inputs` names, whose file is opened here) into `sink` and the
    /// smoother's record, as `settings` say.
    pub(crate) fn new(
        readers: super::setup::Readers,
        sink: Sink<'p>,
        smoother: Option<ForwardRecord>,
        settings: &Settings,
        inputs: &Inputs,
        dir: &std::path::Path,
    ) -> Result<Self, Error> {
        let super::setup::Readers {
            imu,
            imu_ahead,
            gnss,
            odometer,
            ..
        } = readers;
        let odometer_file = odometer.map(OdometerFile::new);
        Ok(Self {
            imu,
            gnss,
            odometer_rate: match inputs.odometer {
                OdometerInput::None => None,
                _ => settings.odometer.map(|o| o.rate),
            },
            odometer_file,
            outages: inputs.outages.clone(),
            start: settings.start.time,
            sink,
            fixes: FixCounts::default(),
            error_model: settings.error_model,
            timing_rule: settings.timing,
            timing: TimingReport::default(),
            pending: imu_ahead,
            smoother,
            smoothed: None,
            out: dir.to_path_buf(),
            output_interval: settings.output_interval,
            states: None,
            fix_track: Thinned::default(),
            constraints: Constraints::new(settings.nhc, settings.zupt),
            smoothed_traces: SmoothedTraces::default(),
            health: Health::new(),
            health_events: Vec::new(),
            stop_on_divergence: inputs.stop_on_divergence,
        })
    }

    /// The first IMU record after the start time.
    fn first_imu(&mut self) -> Result<ImuRecord, Error> {
        while let Some(r) = self.next_imu()? {
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
        // Back at the front: anything still read ahead comes after it.
        self.pending.push_front(first);
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
                self.fixes.before_start += 1;
                continue;
            }
            if self.outages.iter().any(|o| o.contains(fix.time)) {
                self.fixes.in_outage += 1;
                continue;
            }
            self.fixes.used += 1;
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

    /// With `--odo`, the first sample after the start must have the IMU
    /// file's odometer column (a file without it is refused at once, not
    /// run without an odometer).
    fn check_odometer_column(&self, first: Option<&ImuRecord>) -> Result<(), Error> {
        if let (Some(_), Some(r), None) = (self.odometer_rate, first, &self.odometer_file)
            && r.odometer.is_none()
        {
            return Err(InputError::at(
                self.imu.path(),
                r.line,
                8,
                "expected an 8th column (odometer speed, m/s): --odo is given",
            )
            .into());
        }
        Ok(())
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

    /// Keeps the health `event` (if any) of the filter `label`; an error
    /// for an alarm when the run stops on divergence.
    fn health_event(&mut self, label: &str, event: Option<HealthEvent>) -> Result<(), Error> {
        let Some(event) = event else {
            return Ok(());
        };
        if self.health_events.len() < HEALTH_EVENTS {
            self.health_events.push(event);
        }
        if self.stop_on_divergence && event.kind != HealthEventKind::Recovered {
            return Err(Error::Failed(format!(
                "{label} {event}; stopped (--stop-on-divergence)"
            )));
        }
        Ok(())
    }

    /// Reads and checks the GNSS lines after the last IMU sample, counting
    /// their fixes (none is used; a bad line is still an error).
    fn drain_gnss(&mut self) -> Result<(), InputError> {
        if let Some(gnss) = self.gnss.as_mut() {
            while gnss.take()?.is_some() {
                self.fixes.after_end += 1;
            }
        }
        Ok(())
    }
}

/// What a filter does with the aiding read from the files: the GNSS
/// update and the odometer update of the engine `E`.
pub(crate) trait FileAiding<E> {
    /// Updates `engine` with the GNSS fix `fix`.
    fn gnss(&mut self, engine: &mut E, fix: &GnssFix) -> Result<Adaptation, FilterError>;

    /// Updates `engine` with the odometer reading `reading`.
    fn odometer(
        &mut self,
        engine: &mut E,
        reading: &OdometerReading,
    ) -> Result<Adaptation, FilterError>;
}

/// Runs `engine` over the job's data; `aiding` updates it.
pub(crate) fn drive<const N: usize, S, F, A, G>(
    job: &mut Job<'_>,
    engine: &mut LooselyCoupled<f64, N, S, F, A>,
    aiding: G,
) -> Result<(), Error>
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process> + Constrainable<N>,
    A: PriorAdapter<f64>,
    G: FileAiding<LooselyCoupled<f64, N, S, F, A>>,
{
    job.states = Some(StateFiles::create::<N, S>(
        &job.out,
        "result",
        job.output_interval,
    )?);
    let timing = job.start_timing()?;
    let first = job.next_imu()?;
    job.check_odometer_column(first.as_ref())?;
    let imu_path = job.imu.path().to_path_buf();
    let mut pass = Pass {
        label: job.sink.label,
        imu_path: &imu_path,
        job,
        engine,
        aiding,
        timing,
        schedule: Schedule::new(),
    };
    let outcome = pass.run(first);
    pass.job.timing = pass.timing.report();
    outcome
}

/// One forward pass: the job, the engine and its aiding, and what the
/// pass carries from one IMU sample to the next.
struct Pass<'a, 'p, const N: usize, S, F, A, G> {
    job: &'a mut Job<'p>,
    engine: &'a mut LooselyCoupled<f64, N, S, F, A>,
    aiding: G,
    /// The filter's label and the IMU file, for messages.
    label: &'static str,
    imu_path: &'a Path,
    /// The IMU time line (intervals, gaps).
    timing: ImuTiming,
    /// The odometer updates' schedule.
    schedule: Schedule,
}

/// Where the pass is, to name a failure: the sample's time and IMU line.
/// Messages are formatted only on failure: nothing here allocates per
/// sample.
#[derive(Clone, Copy)]
struct At<'a> {
    label: &'static str,
    model: ErrorModelKind,
    imu_path: &'a Path,
    time: f64,
    line: usize,
}

impl At<'_> {
    /// The IMU line of the sample, `FILE:LINE`.
    fn imu_line(&self) -> String {
        format!("{}:{}", self.imu_path.display(), self.line)
    }

    /// The input of a step the IMU line drives (propagation, constraints).
    fn imu_input(&self) -> String {
        format!("IMU line {}", self.imu_line())
    }

    /// The filter's `error` in `step` on `input`, in the user's terms.
    fn diverged(&self, error: FilterError, step: Step, input: String) -> Error {
        let doing = match step {
            Step::Imu => "propagating",
            Step::Gnss(_) => "in the GNSS update",
            Step::Odometer => "in the odometer update",
            Step::ZeroVelocity => "in a zero-velocity update",
            Step::ZeroAngularRate => "in a zero-angular-rate update",
            Step::NonHolonomic => "in a non-holonomic update",
        };
        Error::Failed(format!(
            "{} diverged at {} s of week {doing} ({input}): {}",
            self.label,
            self.time,
            describe(&error, self.model, step)
        ))
    }
}

impl<const N: usize, S, F, A, G> Pass<'_, '_, N, S, F, A, G>
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process> + Constrainable<N>,
    A: PriorAdapter<f64>,
    G: FileAiding<LooselyCoupled<f64, N, S, F, A>>,
{
    /// The samples from `first` to the end of the IMU file, then the
    /// checks of the other files' ends.
    fn run(&mut self, first: Option<ImuRecord>) -> Result<(), Error> {
        let mut previous = (self.job.start, None);
        let mut current = first;
        while let Some(sample) = current {
            current = self.step(&sample, previous)?;
            previous = (sample.time, Some(sample.line));
        }
        self.job.drain_gnss()?;
        self.job.check_odometer_file()
    }

    /// One IMU sample and the aiding due at it; returns the next sample.
    fn step(
        &mut self,
        sample: &ImuRecord,
        previous: (f64, Option<usize>),
    ) -> Result<Option<ImuRecord>, Error> {
        let following = self.job.next_imu()?;
        let at = At {
            label: self.label,
            model: self.job.error_model,
            imu_path: self.imu_path,
            time: sample.time,
            line: sample.line,
        };
        let increment = self.timing.increment(sample, previous.0, previous.1)?;
        self.engine
            .imu(&increment)
            .map_err(|e| at.diverged(e, Step::Imu, at.imu_input()))?;
        self.record_epoch()?;
        let standing = self.standing(&increment);
        self.zero_velocity(at, standing)?;
        self.non_holonomic(at, standing)?;
        let gnss = self.gnss(at, following.as_ref().map(|f| f.time))?;
        // An odometer update at the same sample is the one reported.
        let update = self.odometer(at, sample)?.or(gnss);
        self.output(at, update)?;
        Ok(following)
    }

    /// Whether the vehicle stands still at this sample (counted). The IMU
    /// says "no vibration, no manoeuvre"; the INS speed rules out a smooth
    /// drive at constant velocity, which the IMU cannot tell apart.
    fn standing(&mut self, increment: &ImuIncrement) -> bool {
        let standing = match self.job.constraints.zupt.as_mut() {
            Some((detector, z, _)) => {
                detector.push(increment) && self.engine.solution().vel.norm() < z.max_speed
            }
            None => false,
        };
        self.job.constraints.counts.standstill_samples += usize::from(standing);
        standing
    }

    /// The zero-velocity (and zero-angular-rate) updates, when standing
    /// and due.
    fn zero_velocity(&mut self, at: At<'_>, standing: bool) -> Result<(), Error> {
        let Some((_, z, schedule)) = self.job.constraints.zupt.as_mut() else {
            return Ok(());
        };
        if !(standing && schedule.due(at.time, z.rate)) {
            return Ok(());
        }
        let (v_std, w_std) = (z.velocity_std, z.angular_rate_std);
        let ins = self.engine.ins_context(at.time);
        let m = ZeroVelocity::new(v_std).measurement(self.engine.system(), &ins);
        self.engine
            .apply_with(&m, &mut ())
            .map_err(|e| at.diverged(e, Step::ZeroVelocity, at.imu_input()))?;
        self.record_epoch()?;
        self.job.constraints.counts.zero_velocity += 1;
        if w_std > 0.0 {
            let ins = self.engine.ins_context(at.time);
            let m = ZeroAngularRate::new(w_std).measurement(self.engine.system(), &ins);
            self.engine
                .apply_with(&m, &mut ())
                .map_err(|e| at.diverged(e, Step::ZeroAngularRate, at.imu_input()))?;
            self.record_epoch()?;
            self.job.constraints.counts.zero_angular_rate += 1;
        }
        Ok(())
    }

    /// The non-holonomic update, when due and not standing (at standstill
    /// the zero-velocity update says more).
    fn non_holonomic(&mut self, at: At<'_>, standing: bool) -> Result<(), Error> {
        let Some((model, rate, schedule)) = self.job.constraints.nhc.as_mut() else {
            return Ok(());
        };
        if !schedule.due(at.time, *rate) || standing {
            return Ok(());
        }
        let ins = self.engine.ins_context(at.time);
        let m = model.nhc(self.engine.system(), &ins);
        self.engine
            .apply_with(&m, &mut ())
            .map_err(|e| at.diverged(e, Step::NonHolonomic, at.imu_input()))?;
        self.record_epoch()?;
        self.job.constraints.counts.non_holonomic += 1;
        Ok(())
    }

    /// The GNSS updates due at this sample (the next one at `next`); what
    /// the last of them did.
    fn gnss(&mut self, at: At<'_>, next: Option<f64>) -> Result<Option<Adaptation>, Error> {
        let mut update = None;
        while let Some((fix, line)) = self.job.gnss_due(at.time, next)? {
            let rows = if fix.vel.is_some() { 6 } else { 3 };
            let adaptation = self.aiding.gnss(self.engine, &fix).map_err(|e| {
                let input = match self.job.gnss.as_ref() {
                    Some(g) => format!("GNSS line {}:{line}", g.path().display()),
                    None => format!("GNSS line {line}"),
                };
                at.diverged(e, Step::Gnss(rows), input)
            })?;
            update = Some(adaptation);
            self.record_epoch()?;
            let event = self.job.health.update(at.time, "GNSS", &adaptation);
            self.job.health_event(self.label, event)?;
        }
        Ok(update)
    }

    /// The odometer update, when a speed is known and the update due; what
    /// it did.
    fn odometer(&mut self, at: At<'_>, sample: &ImuRecord) -> Result<Option<Adaptation>, Error> {
        // The speed, and its line in the odometer file (`None`: the IMU file).
        let speed = match self.job.odometer_file.as_mut() {
            Some(f) => f
                .speed_at(at.time)?
                .map(|(speed, line)| (speed, Some(line))),
            None => sample.odometer.map(|speed| (speed, None)),
        };
        let (Some(rate), Some((speed, line))) = (self.job.odometer_rate, speed) else {
            return Ok(None);
        };
        if !self.schedule.due(at.time, rate) {
            return Ok(None);
        }
        let reading = OdometerReading::new(at.time, speed);
        let adaptation = self.aiding.odometer(self.engine, &reading).map_err(|e| {
            let input = match (line, self.job.odometer_file.as_ref()) {
                (Some(l), Some(f)) => format!("odometer line {}:{l}", f.path().display()),
                _ => format!("odometer speed of IMU line {}", at.imu_line()),
            };
            at.diverged(e, Step::Odometer, input)
        })?;
        self.record_epoch()?;
        let event = self.job.health.update(at.time, "odometer", &adaptation);
        self.job.health_event(self.label, event)?;
        Ok(Some(adaptation))
    }

    /// The sample's solution to the outputs: the result files and the
    /// comparison, the smoother's record, the state files.
    fn output(&mut self, at: At<'_>, update: Option<Adaptation>) -> Result<(), Error> {
        // The navigation block of the error covariance, for the NEES and
        // the σ envelopes (only with a truth: a copy of P per sample
        // otherwise wasted).
        let covariance = self.job.sink.evaluation.is_some().then(|| {
            self.engine
                .covariance()
                .fixed_view::<9, 9>(0, 0)
                .into_owned()
        });
        self.job
            .sink
            .sample(self.engine.solution(), update, covariance.as_ref())
            .map_err(|e| match e {
                Error::Failed(m) => Error::Failed(format!(
                    "{} diverged at {} s of week after IMU line {}: {m}",
                    at.label,
                    at.time,
                    at.imu_line()
                )),
                other => other,
            })?;
        // With a truth, the position NEES after an update.
        let nees = self
            .job
            .sink
            .evaluation
            .as_mut()
            .and_then(|e| e.sample_nees.take());
        if update.is_some() {
            let event = self.job.health.nees(at.time, nees);
            self.job.health_event(self.label, event)?;
        }
        if let Some(r) = self.job.smoother.as_mut() {
            r.sample(self.engine.solution(), self.engine.corrections())?;
        }
        // A covariance epoch (propagated or updated at this sample): the
        // filter's estimates and σ, at the output interval.
        if let Some(states) = self.job.states.as_mut()
            && self.engine.pending_interval() == 0.0
            && states.due(at.time)
        {
            let sigma = self.engine.std_devs();
            states.row(at.time, self.engine.corrections(), sigma.iter().copied())?;
        }
        Ok(())
    }

    /// Streams the covariance epoch the engine closed, if any, to the
    /// smoother's record.
    fn record_epoch(&mut self) -> Result<(), Error> {
        match (self.job.smoother.as_mut(), self.engine.take_epoch()) {
            (Some(r), Some(e)) => r.epoch(&e),
            _ => Ok(()),
        }
    }
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
