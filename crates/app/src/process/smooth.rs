//! `process --smooth`: a Rauch–Tung–Striebel pass over the closed-loop
//! error state of the forward run.
//!
//! The formulation. The forward filter is the closed-loop error-state EKF:
//! after each update the error estimate is fed back into the navigation
//! solution (and the sensor corrections) and reset to zero, so the prior
//! error state of every covariance epoch is zero. Expressed relative to the
//! solution the mechanisation reached at an epoch *before* that epoch's
//! feedback, the posterior error state is the feedback itself, and the
//! sequence of epochs is an ordinary linear(ised) RTS record: transition
//! `Φ`, prior `(0, P⁻)`, posterior `(feedback, P⁺)`
//! ([`ForwardEpoch::rts`]). The backward pass
//! ([`rts_step`](kestrel::smoother::rts_step)) gives the smoothed error
//! state `xˢ` of each epoch in those coordinates; `xˢ − feedback` corrects
//! the forward solution *after* the feedback (first order: the feedback is
//! additive in the error state). Between two covariance epochs `k` and
//! `k + 1` the forward solution is the mechanisation from epoch `k`, whose
//! correction runs from `xˢ_k − feedback_k` to `xˢ_{k+1}`: it is
//! interpolated linearly in time (the error dynamics are slow against the
//! 0.1 s epoch interval), and so are the smoothed variances. After the last
//! epoch the smoothed solution is the forward one.
//!
//! This is the closed-loop RTS smoother of the INS/GNSS literature, e.g.
//! E.-H. Shin, *Estimation Techniques for Low-Cost Inertial Navigation*,
//! PhD thesis, University of Calgary, UCGE Report 20219, 2005, §5.3, and
//! H. Liu, S. Nassar, N. El-Sheimy, "Two-filter smoothing for accurate
//! INS/GPS land-vehicle navigation in urban centers", *IEEE Transactions on
//! Vehicular Technology* 59(9): 4256–4267, 2010 (which compares it with the
//! two-filter form); the RTS recursion itself is Rauch, Tung and Striebel,
//! *AIAA Journal* 3(8), 1965.
//!
//! Memory stays bounded: the forward pass streams its epochs and every
//! IMU sample's solution to binary working files in the run's scratch
//! folder, the backward pass reads the epochs from the end and streams the
//! corrections to a third file, and the last pass reads the samples
//! forwards and the corrections backwards. The files go with the scratch
//! folder when the run ends, whether it succeeded, failed or was stopped. Only the GNSS fix times
//! (for the outage and gap table) are kept in memory: 8 bytes per fix.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::experiment::EpochRecord;
use kestrel::nalgebra::{Quaternion, SMatrix, SVector, UnitQuaternion, Vector3};
use kestrel::nav::engine::{feed_back, ForwardEpoch, SensorCorrections};
use kestrel::nav::measurement::ErrorLayout;
use kestrel::nav::{Ellipsoid, Geodetic, ImuBiases, NavState};
use kestrel::smoother::{rts_step, Smoothed};
use kestrel::Euclidean;

use super::evaluation::{Evaluation, NavCovariance};
use super::sink::{create_output, keep_or_discard, Sink, SinkSetup};
use super::state_files::StateFiles;
use super::stats::ErrorStats;
use super::traces::StateRow;
use super::{Consistency, Silent, WindowDrift};
use crate::progress;
use crate::Error;

/// The forward run's record for the smoother, and where the smoothed
/// result goes.
pub(crate) struct ForwardRecord {
    epochs: BinaryFile,
    samples: BinaryFile,
    corrections: BinaryFile,
    /// Times of the GNSS fixes used (for the drift table of the smoothed
    /// solution).
    fixes: Vec<f64>,
    pub setup: SmoothSetup,
    /// Epochs written.
    count: usize,
    /// Reused per-record buffer.
    buffer: Vec<u8>,
}

/// What the smoothed output needs from the run's set-up.
pub(crate) struct SmoothSetup {
    pub label: &'static str,
    pub week: u32,
    pub interval: f64,
    pub earth: Ellipsoid,
    pub nav_path: PathBuf,
    pub csv_path: PathBuf,
    /// The output folder (the smoothed estimates and σ go there).
    pub out: PathBuf,
    pub evaluation: Option<Evaluation>,
}

impl Drop for SmoothSetup {
    /// A run that ends before the smoothed output (a failed forward pass)
    /// removes the smoothed error file it had started.
    fn drop(&mut self) {
        if let Some(mut e) = self.evaluation.take() {
            let _ = e.finish(false);
        }
    }
}

/// What the smoothed run keeps for the figures, thinned.
#[derive(Debug, Default)]
pub(crate) struct SmoothedTraces {
    /// Errors at the compared epochs, with the σ of the navigation errors
    /// in step.
    pub errors: Vec<EpochRecord>,
    pub sigmas: Vec<[f64; 9]>,
    /// Position NEES `(time, NEES)`.
    pub nees: Vec<(f64, f64)>,
    /// (time, latitude, longitude).
    pub track: Vec<(f64, f64, f64)>,
    /// Estimates and σ per covariance epoch.
    pub states: Vec<StateRow>,
}

/// What the smoothing did.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothedReport {
    /// Covariance epochs smoothed.
    pub epochs: usize,
    /// Errors of the smoothed solution at every truth epoch (with a truth).
    pub errors: Option<ErrorStats>,
    /// Its drift in each outage window and data gap (with a truth).
    pub drift: Vec<WindowDrift>,
    /// Its position NEES with the smoothed covariance (with a truth).
    pub consistency: Option<Consistency>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// A hidden binary file in the output folder, removed when dropped.
struct BinaryFile {
    path: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl BinaryFile {
    fn create(path: PathBuf) -> Result<Self, Error> {
        let file = create_output(&path)?;
        Ok(Self {
            writer: Some(BufWriter::with_capacity(1 << 16, file)),
            path,
        })
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), Error> {
        match self.writer.as_mut() {
            Some(w) => w
                .write_all(bytes)
                .map_err(|e| Error::io(&self.path.clone(), e)),
            None => Ok(()),
        }
    }

    /// Flushes and reopens the file for reading.
    fn reader(&mut self) -> Result<BufReader<File>, Error> {
        let partial = self.path.clone();
        if let Some(mut w) = self.writer.take() {
            w.flush().map_err(|e| Error::io(&partial, e))?;
        }
        let f = File::open(&partial).map_err(|e| Error::io(&partial, e))?;
        Ok(BufReader::with_capacity(1 << 16, f))
    }
}

impl Drop for BinaryFile {
    fn drop(&mut self) {
        self.writer = None;
        // Best effort: a scratch file, never a result.
        let _ = keep_or_discard(&self.path, false);
    }
}

fn put(buffer: &mut Vec<u8>, values: impl IntoIterator<Item = f64>) {
    for v in values {
        buffer.extend_from_slice(&v.to_le_bytes());
    }
}

/// Reads `count` numbers from `bytes` at `*at`.
fn take<const K: usize>(bytes: &[u8], at: &mut usize) -> [f64; K] {
    core::array::from_fn(|_| {
        let v = f64::from_le_bytes(bytes[*at..*at + 8].try_into().expect("8 bytes"));
        *at += 8;
        v
    })
}

fn next_f64(bytes: &[u8], at: &mut usize) -> f64 {
    take::<1>(bytes, at)[0]
}

/// Numbers in one epoch record: time, feedback, `P⁻` and `P⁺` (lower
/// triangles), `Φ`.
const fn epoch_len(n: usize) -> usize {
    1 + n + n * (n + 1) + n * n
}

/// Numbers in one sample record: time, latitude, longitude, height,
/// velocity, attitude quaternion (w, i, j, k), then the sensor corrections
/// in use (gyro and accelerometer bias and scale factor, odometer scale).
const SAMPLE_LEN: usize = 11 + 13;

/// Numbers in one correction record: time, correction after and before
/// feedback, variances, the position block's off-diagonal covariances.
const fn correction_len(n: usize) -> usize {
    1 + 3 * n + 3
}

fn lower<const N: usize>(p: &SMatrix<f64, N, N>) -> impl Iterator<Item = f64> + '_ {
    (0..N).flat_map(move |j| (j..N).map(move |i| p[(i, j)]))
}

fn read_lower<const N: usize>(bytes: &[u8], at: &mut usize) -> SMatrix<f64, N, N> {
    let mut p = SMatrix::zeros();
    for j in 0..N {
        for i in j..N {
            let v = next_f64(bytes, at);
            p[(i, j)] = v;
            p[(j, i)] = v;
        }
    }
    p
}

impl ForwardRecord {
    /// Scratch files in `out`; the smoothed result as `setup` says.
    pub(crate) fn new(out: &Path, setup: SmoothSetup) -> Result<Self, Error> {
        Ok(Self {
            epochs: BinaryFile::create(out.join(".work-smoother-epochs"))?,
            samples: BinaryFile::create(out.join(".work-smoother-samples"))?,
            corrections: BinaryFile::create(out.join(".work-smoother-corrections"))?,
            fixes: Vec::new(),
            setup,
            count: 0,
            buffer: Vec::new(),
        })
    }

    /// Appends a closed covariance epoch.
    pub(crate) fn epoch<const N: usize>(&mut self, e: &ForwardEpoch<f64, N>) -> Result<(), Error> {
        self.buffer.clear();
        put(&mut self.buffer, [e.time]);
        put(&mut self.buffer, e.feedback.iter().copied());
        put(&mut self.buffer, lower(&e.prior_covariance));
        put(&mut self.buffer, lower(&e.posterior_covariance));
        put(&mut self.buffer, e.transition.iter().copied());
        self.count += 1;
        self.epochs.write(&self.buffer)
    }

    /// Appends the forward solution after an IMU sample and the sensor
    /// corrections in use.
    pub(crate) fn sample(&mut self, nav: &NavState, c: &SensorCorrections) -> Result<(), Error> {
        let q = nav.att.quaternion();
        let mut b = [0u8; SAMPLE_LEN * 8];
        let i = &c.imu;
        let values = [
            nav.time,
            nav.pos.lat,
            nav.pos.lon,
            nav.pos.h,
            nav.vel.x,
            nav.vel.y,
            nav.vel.z,
            q.w,
            q.i,
            q.j,
            q.k,
        ]
        .into_iter()
        .chain(i.gyro.iter().copied())
        .chain(i.accel.iter().copied())
        .chain(i.gyro_scale.iter().copied())
        .chain(i.accel_scale.iter().copied())
        .chain([c.odometer_scale]);
        for (chunk, v) in b.chunks_exact_mut(8).zip(values) {
            chunk.copy_from_slice(&v.to_le_bytes());
        }
        self.samples.write(&b)
    }

    /// Notes a GNSS fix used at time `t`.
    pub(crate) fn fix(&mut self, t: f64) {
        self.fixes.push(t);
    }

    /// The backward pass and the smoothed output, after the forward run
    /// (whose last, still open epoch is `last`). `L` is the error layout.
    pub(crate) fn finish<const N: usize, L: ErrorLayout<N>>(
        mut self,
        last: ForwardEpoch<f64, N>,
    ) -> Result<(SmoothedReport, SmoothedTraces), Error> {
        self.epoch(&last)?;
        self.backward::<N>()?;
        self.output::<N, L>()
    }

    /// Smooths the epochs from the last to the first, writing one
    /// correction record per epoch (in that reverse order).
    fn backward<const N: usize>(&mut self) -> Result<(), Error> {
        let size = epoch_len(N) * 8;
        let mut reader = self.epochs.reader()?;
        let epochs_path = self.epochs.path.clone();
        let out = &mut self.corrections;
        let mut bytes = vec![0u8; size];
        let mut read = |k: usize| -> Result<ForwardEpoch<f64, N>, Error> {
            reader
                .seek(SeekFrom::Start((k * size) as u64))
                .and_then(|_| reader.read_exact(&mut bytes))
                .map_err(|e| Error::io(&epochs_path, e))?;
            let mut at = 0;
            let time = next_f64(&bytes, &mut at);
            let mut feedback = SVector::<f64, N>::zeros();
            for v in feedback.iter_mut() {
                *v = next_f64(&bytes, &mut at);
            }
            let prior_covariance = read_lower::<N>(&bytes, &mut at);
            let posterior_covariance = read_lower::<N>(&bytes, &mut at);
            let mut transition = SMatrix::<f64, N, N>::zeros();
            for v in transition.iter_mut() {
                *v = next_f64(&bytes, &mut at);
            }
            Ok(ForwardEpoch {
                time,
                transition,
                prior_covariance,
                feedback,
                posterior_covariance,
            })
        };
        let n = self.count;
        let mut next = read(n - 1)?;
        let mut smoothed = Smoothed {
            state: next.feedback,
            covariance: next.posterior_covariance,
        };
        let mut buffer = Vec::with_capacity(correction_len(N) * 8);
        let mut write = |e: &ForwardEpoch<f64, N>, s: &Smoothed<f64, N>| {
            buffer.clear();
            put(&mut buffer, [e.time]);
            put(&mut buffer, (s.state - e.feedback).iter().copied());
            put(&mut buffer, s.state.iter().copied());
            put(&mut buffer, s.covariance.diagonal().iter().copied());
            let c = &s.covariance;
            put(&mut buffer, [c[(7, 6)], c[(8, 6)], c[(8, 7)]]);
            out.write(&buffer)
        };
        write(&next, &smoothed)?;
        for k in (0..n - 1).rev() {
            let this = read(k)?;
            smoothed = rts_step(&Euclidean, &this.rts(), &next.rts(), &smoothed).map_err(|e| {
                Error::Failed(format!(
                    "the smoother failed at the covariance epoch at {} s of week: {e}",
                    this.time
                ))
            })?;
            write(&this, &smoothed)?;
            next = this;
        }
        Ok(())
    }

    /// Reads the samples forwards and the corrections backwards, applies
    /// the interpolated correction to every sample and writes the smoothed
    /// result.
    fn output<const N: usize, L: ErrorLayout<N>>(
        mut self,
    ) -> Result<(SmoothedReport, SmoothedTraces), Error> {
        let corrections = Corrections::<N>::new(
            self.corrections.reader()?,
            &self.corrections.path,
            self.count,
        );
        let samples = Samples {
            reader: self.samples.reader()?,
            path: self.samples.path.clone(),
            bytes: [0u8; SAMPLE_LEN * 8],
        };
        let mut silent = Silent;
        let setup = &mut self.setup;
        let mut sink = Sink::new(SinkSetup {
            label: setup.label,
            week: setup.week,
            interval: setup.interval,
            nav_path: &setup.nav_path,
            csv_path: &setup.csv_path,
            evaluation: setup.evaluation.take(),
            progress: progress::Ticker::new(&mut silent, 0.0, 0.0),
        })?;
        let mut states = StateFiles::create::<N, L>(&setup.out, "smoothed", setup.interval)?;
        let outcome = correct::<N, L>(
            samples,
            corrections,
            &self.fixes,
            setup.earth,
            &mut sink,
            &mut states,
        );
        let finished = sink.finish(outcome.is_ok());
        let states_rows = std::mem::take(&mut states.rows.records);
        let state_files = states.finish(outcome.is_ok() && finished.is_ok());
        outcome?;
        finished?;
        let mut files = vec![setup.nav_path.clone(), setup.csv_path.clone()];
        files.extend(state_files?);
        Ok(smoothed_results(self.count, sink, states_rows, files))
    }
}

/// Applies the smoothed corrections to the forward `samples` in time
/// order: each smoothed sample to `sink` (with the GNSS `fixes` for its
/// drift table), the estimates and σ at the covariance epochs to
/// `states`.
fn correct<const N: usize, L: ErrorLayout<N>>(
    mut samples: Samples,
    corrections: Corrections<N>,
    fixes: &[f64],
    earth: Ellipsoid,
    sink: &mut Sink<'_>,
    states: &mut StateFiles,
) -> Result<(), Error> {
    let mut fixes = fixes.iter().copied().peekable();
    let mut bracket = Bracket::new(corrections)?;
    let mut pending: Option<(NavState, NavCovariance)> = None;
    loop {
        let read = samples.next()?;
        // Fixes belong to the sample before the next one's time.
        if let Some((p, position)) = pending.take() {
            let next_time = read.as_ref().map_or(f64::INFINITY, |(n, _)| n.time);
            while let Some(t) = fixes.next_if(|&t| t < next_time) {
                if let Some(e) = sink.evaluation.as_mut() {
                    e.drift.fix(t);
                }
            }
            sink.sample(&p, None, Some(&position))?;
        }
        let Some((nav, mut sensors)) = read else {
            break;
        };
        let c = bracket.at(nav.time)?;
        let mut smoothed = nav;
        // A zero correction (after the last update) leaves the forward
        // solution bit for bit.
        if c.dx.iter().any(|v| *v != 0.0) {
            feed_back::<f64, N, L>(&c.dx, &earth, &mut smoothed, &mut sensors);
        }
        if c.at_epoch && states.due(nav.time) {
            let sigma = c.variance.iter().map(|v| v.max(0.0).sqrt());
            states.row(nav.time, &sensors, sigma)?;
        }
        pending = Some((smoothed, c.position));
    }
    Ok(())
}

/// The smoothed run's report and traces from its closed outputs: the
/// `epochs` smoothed, the `sink` (with the comparison with the truth, if
/// any), the estimate rows kept and the `files` written so far.
fn smoothed_results(
    epochs: usize,
    mut sink: Sink<'_>,
    states: Vec<StateRow>,
    mut files: Vec<PathBuf>,
) -> (SmoothedReport, SmoothedTraces) {
    let (mut errors, mut drift) = (None, Vec::new());
    let mut traces = SmoothedTraces {
        track: std::mem::take(&mut sink.track.records),
        states,
        ..SmoothedTraces::default()
    };
    let mut consistency = None;
    if let Some(e) = sink.evaluation.take() {
        errors = e.all.finish();
        drift = e.drift.clone().finish(sink.end_time);
        files.push(e.csv_path().to_path_buf());
        consistency = Some(e.consistency);
        traces.errors = e.errors.records;
        traces.sigmas = e.sigmas.records;
        traces.nees = e.nees.records;
    }
    let report = SmoothedReport {
        epochs,
        errors,
        drift,
        consistency,
        files,
    };
    (report, traces)
}

/// The forward run's samples file, read forwards.
struct Samples {
    reader: BufReader<File>,
    path: PathBuf,
    /// One record.
    bytes: [u8; SAMPLE_LEN * 8],
}

impl Samples {
    /// The next sample's solution and sensor corrections; `None` at the
    /// end.
    fn next(&mut self) -> Result<Option<(NavState, SensorCorrections)>, Error> {
        match self.reader.read_exact(&mut self.bytes) {
            Ok(()) => Ok(Some(decode_sample(&self.bytes))),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(None),
            Err(e) => Err(Error::io(&self.path, e)),
        }
    }
}

fn decode_sample(bytes: &[u8]) -> (NavState, SensorCorrections) {
    let mut at = 0;
    let v = take::<SAMPLE_LEN>(bytes, &mut at);
    let nav = NavState {
        time: v[0],
        pos: Geodetic::new(v[1], v[2], v[3]),
        vel: Vector3::new(v[4], v[5], v[6]),
        att: UnitQuaternion::new_unchecked(Quaternion::new(v[7], v[8], v[9], v[10])),
    };
    let v3 = |k: usize| Vector3::new(v[k], v[k + 1], v[k + 2]);
    let c = SensorCorrections {
        imu: ImuBiases {
            gyro: v3(11),
            accel: v3(14),
            gyro_scale: v3(17),
            accel_scale: v3(20),
        },
        odometer_scale: v[23],
    };
    (nav, c)
}

/// One epoch's smoothed correction.
#[derive(Clone, Copy)]
struct Correction<const N: usize> {
    time: f64,
    /// Applied to the forward solution after the epoch's feedback.
    after: SVector<f64, N>,
    /// Applied to the mechanised solution reaching the epoch.
    before: SVector<f64, N>,
    /// Smoothed variances.
    variance: SVector<f64, N>,
    /// Smoothed navigation-error covariance: variances and the position
    /// block (NED).
    position: NavCovariance,
}

/// The corrections file, read from its end (forward in time).
struct Corrections<const N: usize> {
    reader: BufReader<File>,
    path: PathBuf,
    left: usize,
    bytes: Vec<u8>,
}

impl<const N: usize> Corrections<N> {
    fn new(reader: BufReader<File>, path: &Path, count: usize) -> Self {
        Self {
            reader,
            path: path.to_path_buf(),
            left: count,
            bytes: vec![0u8; correction_len(N) * 8],
        }
    }

    fn next(&mut self) -> Result<Option<Correction<N>>, Error> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        let size = self.bytes.len();
        self.reader
            .seek(SeekFrom::Start((self.left * size) as u64))
            .and_then(|_| self.reader.read_exact(&mut self.bytes))
            .map_err(|e| Error::io(&self.path, e))?;
        let mut at = 0;
        let time = next_f64(&self.bytes, &mut at);
        let mut vectors = [SVector::<f64, N>::zeros(); 3];
        for v in &mut vectors {
            for x in v.iter_mut() {
                *x = next_f64(&self.bytes, &mut at);
            }
        }
        let [after, before, variance] = vectors;
        let [ne, nd, ed] = take::<3>(&self.bytes, &mut at);
        // The navigation block: the variances, and the position
        // covariances the NEES needs.
        let mut position = NavCovariance::from_diagonal(&variance.fixed_rows::<9>(0).into_owned());
        for (i, j, v) in [(7, 6, ne), (8, 6, nd), (8, 7, ed)] {
            position[(i, j)] = v;
            position[(j, i)] = v;
        }
        Ok(Some(Correction {
            time,
            after,
            before,
            variance,
            position,
        }))
    }
}

/// The smoothed correction at an IMU sample.
struct Interpolated<const N: usize> {
    /// Applied to the forward solution.
    dx: SVector<f64, N>,
    /// Smoothed variances.
    variance: SVector<f64, N>,
    /// Smoothed navigation-error covariance (see [`Correction`]).
    position: NavCovariance,
    /// Whether the sample is a covariance epoch.
    at_epoch: bool,
}

/// The corrections around the sample being corrected: the epoch at or
/// before it and the next one.
struct Bracket<const N: usize> {
    corrections: Corrections<N>,
    current: Option<Correction<N>>,
    following: Option<Correction<N>>,
}

impl<const N: usize> Bracket<N> {
    /// At the first two epochs of `corrections`.
    fn new(mut corrections: Corrections<N>) -> Result<Self, Error> {
        let current = corrections.next()?;
        let following = corrections.next()?;
        Ok(Self {
            corrections,
            current,
            following,
        })
    }

    /// The correction at `t` (not before the previous call's): the
    /// epoch's at an epoch, linear in time between two, the last one's
    /// after the last.
    fn at(&mut self, t: f64) -> Result<Interpolated<N>, Error> {
        while self.following.as_ref().is_some_and(|f| f.time <= t) {
            self.current = self.following;
            self.following = self.corrections.next()?;
        }
        let at_epoch = self.current.as_ref().is_some_and(|c| c.time == t);
        let (dx, variance, position) = match (&self.current, &self.following) {
            (Some(c), _) if c.time == t => (c.after, c.variance, c.position),
            (Some(c), Some(f)) => {
                let w = (t - c.time) / (f.time - c.time);
                (
                    c.after + (f.before - c.after) * w,
                    c.variance + (f.variance - c.variance) * w,
                    c.position + (f.position - c.position) * w,
                )
            }
            (Some(c), None) => (c.after, c.variance, c.position),
            (None, _) => {
                return Err(Error::Failed(format!(
                    "internal error: an IMU sample at {t} s of week before the first \
                     covariance epoch"
                )))
            }
        };
        Ok(Interpolated {
            dx,
            variance,
            position,
            at_epoch,
        })
    }
}
