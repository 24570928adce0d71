//! The comparison with a reference trajectory (`--truth`).
//!
//! The solution is compared at every truth epoch inside its span, not only
//! at the aiding epochs: drift between fixes and in outages is what a
//! reference is for. The solution is known at every IMU sample (100 Hz or
//! more); at a truth epoch between two samples it is interpolated linearly
//! (position, velocity) and spherically (attitude), which at 5 ms spacing
//! is exact to micrometres. A truth epoch within 1 µs of a sample is
//! compared with that sample itself, after its update. Nothing is held per
//! epoch: errors stream to `errors.csv`, statistics are running sums, and
//! the plots keep a bounded, evenly thinned subset.

use kestrel_io::input::Input as In;
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use crate::experiment::{Adaptation, EpochRecord, PositionAxes};
use kestrel::nav::{Ellipsoid, Geodetic, NavError, NavState};

use super::consistency::Consistency;
use super::drift::DriftTable;
use super::stats::Accumulator;
use crate::config::process::TruthFormat;
use crate::output::EpochCsvWriter;
use crate::{Error, InputError};
use kestrel::nav::nalgebra::{SMatrix, UnitQuaternion, Vector3};
use kestrel_io::gins::{NavReader, RtklibReader, WEEK_SECONDS};

/// Truth times within this many seconds of a sample are the same instant.
const SAME_TIME: f64 = 1e-6;

/// At most this many records are kept for the plots (each kind).
const PLOT_RECORDS: usize = 20_000;

/// A reference epoch: the state, and whether its velocity and attitude
/// are known (`false` for a position-only reference).
#[derive(Clone, Copy, Debug)]
struct Reference {
    state: NavState,
    full: bool,
}

/// The reader of the truth: the file in its format, or the epochs an
/// earlier comparison of the same run read, replayed from its scratch copy.
enum TruthReader {
    Nav(NavReader<In>),
    Rtklib(RtklibReader<In>),
    Replay {
        reader: BufReader<File>,
        /// The truth file's name, for errors.
        path: std::path::PathBuf,
    },
}

/// The truth, read forward as the run goes.
pub(crate) struct Truth {
    reader: TruthReader,
    next: Option<Reference>,
    /// The week of the file's first line: later weeks continue its
    /// seconds of week (as the IMU and GNSS times do across a rollover).
    first_week: Option<u32>,
    /// Where every epoch read is copied for a replay (the smoother's
    /// comparison), so the file is read once.
    tee: Option<(BufWriter<File>, std::path::PathBuf)>,
}

/// Numbers in a replayed epoch: time, latitude, longitude, height,
/// velocity (3), attitude quaternion (4), whether full.
const REPLAY_LEN: usize = 12;

impl Truth {
    /// The truth file `reader` (named `path`) in `format`; RTKLIB times in
    /// seconds of GPS week `week0`.
    pub(crate) fn new(reader: In, path: &Path, format: &TruthFormat, week0: u32) -> Self {
        Self {
            reader: match format {
                TruthFormat::Nav => TruthReader::Nav(NavReader::new(reader, path)),
                TruthFormat::Rtklib { quality } => {
                    TruthReader::Rtklib(RtklibReader::new(reader, path, week0, quality))
                }
            },
            next: None,
            first_week: None,
            tee: None,
        }
    }

    /// The same truth, every epoch it reads also written to `copy` (a
    /// scratch file) for [`replay`](Self::replay).
    pub(crate) fn tee(mut self, copy: std::path::PathBuf) -> Result<Self, Error> {
        let file = super::sink::create_output(&copy)?;
        self.tee = Some((BufWriter::with_capacity(1 << 16, file), copy));
        Ok(self)
    }

    /// The epochs a [`tee`](Self::tee)'d truth wrote to `copy`, in order
    /// (`original` names the truth file in errors). The copy may still be
    /// growing when this opens it: it is read after the forward pass.
    pub(crate) fn replay(copy: &Path, original: Option<&Path>) -> Result<Self, Error> {
        // The copy is created here, empty, if the forward comparison has
        // not made it yet; the forward pass appends to the same file.
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(copy)
            .map_err(|e| Error::io(copy, e))?;
        Ok(Self {
            reader: TruthReader::Replay {
                reader: BufReader::with_capacity(1 << 16, file),
                path: original.unwrap_or(copy).to_path_buf(),
            },
            next: None,
            first_week: None,
            tee: None,
        })
    }

    /// Flushes the copy of a tee'd truth (before its replay is read).
    pub(crate) fn flush_copy(&mut self) -> Result<(), Error> {
        if let Some((w, path)) = self.tee.as_mut() {
            w.flush().map_err(|e| Error::io(path, e))?;
        }
        Ok(())
    }

    /// The next truth epoch, not consumed.
    fn peek(&mut self) -> Result<Option<Reference>, InputError> {
        if self.next.is_none() {
            self.next = self.read()?;
            if let (Some(r), Some((w, path))) = (self.next, self.tee.as_mut()) {
                let s = &r.state;
                let q = s.att.quaternion();
                let values = [
                    s.time,
                    s.pos.lat,
                    s.pos.lon,
                    s.pos.h,
                    s.vel.x,
                    s.vel.y,
                    s.vel.z,
                    q.w,
                    q.i,
                    q.j,
                    q.k,
                    f64::from(u8::from(r.full)),
                ];
                for v in values {
                    w.write_all(&v.to_le_bytes()).map_err(|e| {
                        InputError::file(
                            path,
                            format!("cannot copy the truth for the smoother: {e}"),
                        )
                    })?;
                }
            }
        }
        Ok(self.next)
    }

    /// The next epoch from the reader.
    fn read(&mut self) -> Result<Option<Reference>, InputError> {
        Ok(match &mut self.reader {
            TruthReader::Nav(r) => match r.next() {
                Some(r) => {
                    let mut r = r?;
                    let first = *self.first_week.get_or_insert(r.week);
                    r.state.time += f64::from(r.week.saturating_sub(first)) * WEEK_SECONDS;
                    Some(Reference {
                        state: r.state,
                        full: true,
                    })
                }
                None => None,
            },
            TruthReader::Rtklib(r) => match r.next() {
                Some(f) => {
                    let f = f?;
                    Some(Reference {
                        state: NavState {
                            time: f.time,
                            pos: f.pos,
                            vel: Vector3::zeros(),
                            att: UnitQuaternion::identity(),
                        },
                        full: false,
                    })
                }
                None => None,
            },
            TruthReader::Replay { reader, path } => {
                let mut bytes = [0u8; 8 * REPLAY_LEN];
                match reader.read_exact(&mut bytes) {
                    Ok(()) => {}
                    Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(None),
                    Err(e) => {
                        return Err(InputError::file(
                            path,
                            format!("cannot read the truth's copy: {e}"),
                        ));
                    }
                }
                let v: Vec<f64> = bytes
                    .chunks_exact(8)
                    .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                    .collect();
                let att = UnitQuaternion::new_unchecked(kestrel::nav::nalgebra::Quaternion::new(
                    v[7], v[8], v[9], v[10],
                ));
                Some(Reference {
                    state: NavState {
                        time: v[0],
                        pos: kestrel::nav::Geodetic::new(v[1], v[2], v[3]),
                        vel: Vector3::new(v[4], v[5], v[6]),
                        att,
                    },
                    full: v[11] != 0.0,
                })
            }
        })
    }
}

/// The covariance of the navigation errors `[φ, δv, δr]` (NED; rad, m/s,
/// m): the first 9 × 9 block of the error-state covariance.
pub(crate) type NavCovariance = SMatrix<f64, 9, 9>;

/// Records kept for the plots: every `stride`-th, the stride doubling
/// whenever the store is full, so memory stays bounded.
#[derive(Debug)]
pub(crate) struct Thinned<R = EpochRecord> {
    pub records: Vec<R>,
    stride: usize,
    seen: usize,
}

impl<R> Default for Thinned<R> {
    fn default() -> Self {
        Self {
            records: Vec::new(),
            stride: 1,
            seen: 0,
        }
    }
}

impl<R> Thinned<R> {
    /// Whether the next [`push`](Self::push) would keep its record (so a
    /// costly record need only be built then; else call
    /// [`skip`](Self::skip)).
    pub(crate) fn wants(&self) -> bool {
        self.seen.is_multiple_of(self.stride.max(1))
    }

    /// Counts a record not built (one [`wants`](Self::wants) declined).
    pub(crate) fn skip(&mut self) {
        self.stride = self.stride.max(1);
        self.seen += 1;
    }

    pub(crate) fn push(&mut self, r: R) {
        self.stride = self.stride.max(1);
        if self.seen.is_multiple_of(self.stride) {
            if self.records.len() == PLOT_RECORDS {
                let mut k = 0;
                self.records.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
            }
            if self.seen.is_multiple_of(self.stride) {
                self.records.push(r);
            }
        }
        self.seen += 1;
    }
}

/// What the comparison found.
pub(crate) struct Evaluation {
    earth: Ellipsoid,
    truth: Truth,
    /// The GNSS antenna's lever arm when the truth is at the antenna.
    antenna: Option<Vector3<f64>>,
    previous: Option<NavState>,
    /// The navigation-error covariance (φ, δv, δr; NED) at the previous
    /// sample.
    previous_covariance: Option<NavCovariance>,
    /// The position NEES over the compared epochs (when the caller gives
    /// covariances).
    pub consistency: Consistency,
    /// The NEES at the compared epochs, thinned for the plots.
    pub nees: Thinned<(f64, f64)>,
    /// The NEES at the truth epoch of the last sample, if one fell on it
    /// (for the health monitor, which takes it after an update).
    pub sample_nees: Option<f64>,
    /// The σ of the navigation errors (attitude rad, velocity m/s,
    /// position m; NED) at the compared epochs, thinned in step with
    /// `errors` (NaN without a covariance).
    pub sigmas: Thinned<[f64; 9]>,
    csv: EpochCsvWriter<BufWriter<File>>,
    csv_path: PathBuf,
    /// Over every compared epoch, and over the aiding epochs only.
    pub all: Accumulator,
    pub aiding: Accumulator,
    pub drift: DriftTable,
    /// For the plots: errors at compared epochs, and the aiding epochs.
    pub errors: Thinned,
    pub updates: Thinned,
    /// Truth epochs before the first sample (not compared).
    pub before: usize,
    /// The first truth epoch read, s of week.
    first_truth: Option<f64>,
}

/// Where a comparison writes and what it is told.
pub(crate) struct EvaluationSetup {
    pub earth: Ellipsoid,
    pub axes: PositionAxes,
    pub truth: Truth,
    pub antenna: Option<Vector3<f64>>,
    pub csv_path: PathBuf,
    pub drift: DriftTable,
}

impl Evaluation {
    pub(crate) fn new(s: EvaluationSetup) -> Result<Self, Error> {
        let file = super::sink::create_output(&s.csv_path)?;
        let csv =
            EpochCsvWriter::with_update_column(BufWriter::with_capacity(1 << 16, file), s.axes)
                .map_err(|e| Error::io(&s.csv_path, e))?;
        Ok(Self {
            earth: s.earth,
            truth: s.truth,
            antenna: s.antenna,
            previous: None,
            previous_covariance: None,
            consistency: Consistency::default(),
            nees: Thinned::default(),
            sample_nees: None,
            sigmas: Thinned::default(),
            csv,
            csv_path: s.csv_path,
            all: Accumulator::new(s.axes),
            aiding: Accumulator::new(s.axes),
            drift: s.drift,
            errors: Thinned::default(),
            updates: Thinned::default(),
            before: 0,
            first_truth: None,
        })
    }

    /// Compares the truth epochs up to the sample `nav` (with the update
    /// made at it, if any) with the solution.
    pub(crate) fn sample(
        &mut self,
        nav: &NavState,
        update: Option<Adaptation>,
        covariance: Option<&NavCovariance>,
    ) -> Result<(), Error> {
        let t = nav.time;
        while let Some(reference) = self.truth.peek()? {
            let truth = reference.state;
            if truth.time > t + SAME_TIME {
                break;
            }
            self.truth.next = None;
            self.first_truth.get_or_insert(truth.time);
            if truth.time >= t - SAME_TIME {
                let r = self.error(nav, &reference, update)?;
                let nees = self.check(truth.time, &r.position, covariance);
                self.sample_nees = nees;
                self.record(r.with_nees(nees), &reference, update)?;
            } else if let Some(p) = self.previous.filter(|p| truth.time > p.time) {
                let between = interpolate(&p, nav, truth.time);
                let r = self.error(&between, &reference, None)?;
                let w = (truth.time - p.time) / (t - p.time);
                let cov = match (&self.previous_covariance, covariance) {
                    (Some(a), Some(b)) => Some(a + (b - a) * w),
                    _ => None,
                };
                let nees = self.check(truth.time, &r.position, cov.as_ref());
                self.record(r.with_nees(nees), &reference, None)?;
            } else {
                self.before += 1;
            }
        }
        self.previous = Some(*nav);
        self.previous_covariance = covariance.copied();
        Ok(())
    }

    /// The NEES of the position error `dr` (NED) at `t` with covariance
    /// `p`, if there is one.
    fn check(&mut self, t: f64, dr: &Vector3<f64>, p: Option<&NavCovariance>) -> Option<f64> {
        let sigma = p.map_or([f64::NAN; 9], |p| {
            core::array::from_fn(|i| p[(i, i)].max(0.0).sqrt())
        });
        self.sigmas.push(sigma);
        let position = p.map(|p| p.fixed_view::<3, 3>(6, 6).into_owned());
        let nees = position.and_then(|p| self.consistency.add(dr, &p));
        if let Some(nees) = nees {
            self.nees.push((t, nees));
        }
        nees
    }

    /// The errors of `nav` against `reference`, with the update made at
    /// it (NaN velocity and attitude errors for a position-only reference).
    fn error(
        &mut self,
        nav: &NavState,
        reference: &Reference,
        update: Option<Adaptation>,
    ) -> Result<EpochRecord, Error> {
        let truth = &reference.state;
        let mut nav = *nav;
        if let Some(lever) = self.antenna {
            // The solution's antenna: the lever arm turned into NED.
            nav.pos = self.earth.displace(&nav.pos, &(nav.att * lever));
        }
        let mut e = NavError::between(&self.earth, &nav, truth);
        if !reference.full {
            e.dv = Vector3::repeat(f64::NAN);
            e.phi = Vector3::repeat(f64::NAN);
        }
        let finite = e.dr.iter().all(|v| v.is_finite())
            && (!reference.full || e.to_vector().iter().all(|v| v.is_finite()));
        if !finite {
            return Err(Error::Failed(format!(
                "its error against the truth at {} s of week is not a finite number",
                truth.time
            )));
        }
        Ok(EpochRecord {
            time: truth.time,
            position: e.dr,
            velocity: e.dv,
            attitude: e.phi,
            adaptation: update.unwrap_or_default(),
            position_nees: None,
        })
    }

    /// Adds the compared epoch `r` to the statistics and writes its row.
    fn record(
        &mut self,
        r: EpochRecord,
        reference: &Reference,
        update: Option<Adaptation>,
    ) -> Result<(), Error> {
        self.all.add(&r, reference.full);
        self.drift.add(r.time, &r.position);
        self.errors.push(r);
        if update.is_some() {
            self.aiding.add(&r, reference.full);
            self.updates.push(r);
        }
        self.csv
            .write_compared(&r, update.is_some(), !reference.full)
            .map_err(|e| Error::io(&self.csv_path, e))
    }

    /// The error file's name.
    pub(crate) fn csv_path(&self) -> &Path {
        &self.csv_path
    }

    /// Why no epoch was compared in a run from `start` to `end` (s of week).
    pub(crate) fn why_nothing_compared(&mut self, start: f64, end: f64) -> String {
        let first = match self.first_truth {
            Some(t) => Some(t),
            None => self.truth.peek().ok().flatten().map(|r| r.state.time),
        };
        match first {
            None => "no truth epoch to compare with: the file has no data lines".to_owned(),
            Some(t) if t > end => format!(
                "no truth epoch to compare with: the truth starts at {t} s of week, after the \
                 run's last IMU sample at {end} s"
            ),
            Some(t) => format!(
                "no truth epoch to compare with: its {} epochs from {t} s of week all lie \
                 before the first IMU sample after the initial time {start} s (and within 1 µs \
                 of none)",
                self.before
            ),
        }
    }

    /// Flushes the error file; puts it in place when the run `succeeded`,
    /// otherwise removes it.
    /// Flushes the truth's copy for the smoother's replay.
    pub(crate) fn flush_truth_copy(&mut self) -> Result<(), Error> {
        self.truth.flush_copy()
    }

    pub(crate) fn finish(&mut self, succeeded: bool) -> Result<(), Error> {
        let flushed = self.csv.flush().map_err(|e| Error::io(&self.csv_path, e));
        super::sink::keep_or_discard(&self.csv_path, succeeded && flushed.is_ok())?;
        flushed
    }
}

/// The solution at `t` between the samples `a` and `b`.
fn interpolate(a: &NavState, b: &NavState, t: f64) -> NavState {
    let f = (t - a.time) / (b.time - a.time);
    let lerp = |x: f64, y: f64| x + f * (y - x);
    let mut dlon = b.pos.lon - a.pos.lon;
    // Across the antimeridian, the short way round.
    if dlon > std::f64::consts::PI {
        dlon -= std::f64::consts::TAU;
    } else if dlon < -std::f64::consts::PI {
        dlon += std::f64::consts::TAU;
    }
    NavState {
        time: t,
        pos: Geodetic::new(
            lerp(a.pos.lat, b.pos.lat),
            a.pos.lon + f * dlon,
            lerp(a.pos.h, b.pos.h),
        ),
        vel: a.vel + (b.vel - a.vel) * f,
        att: a.att.slerp(&b.att, f),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel::nav::nalgebra::Vector3;
    use kestrel::nav::Euler;

    #[test]
    fn interpolation_is_exact_at_the_ends_and_linear_between() {
        let a = NavState::new(
            1.0,
            Geodetic::new(0.5, 3.1, 10.0),
            Vector3::new(1.0, 2.0, 3.0),
            Euler::new(0.0, 0.0, 0.1),
        );
        let b = NavState::new(
            1.01,
            Geodetic::new(0.5001, -3.1, 12.0),
            Vector3::new(3.0, 2.0, 1.0),
            Euler::new(0.0, 0.0, 0.3),
        );
        let m = interpolate(&a, &b, 1.005);
        assert!((m.pos.h - 11.0).abs() < 1e-12);
        assert!((m.vel - Vector3::new(2.0, 2.0, 2.0)).norm() < 1e-12);
        // Across ±π the longitude goes the short way.
        // 3.1 to −3.1 is 2π − 6.2 eastwards.
        assert!((m.pos.lon - (3.1 + 0.5 * (std::f64::consts::TAU - 6.2))).abs() < 1e-12);
        assert!((m.att.euler_angles().2 - 0.2).abs() < 1e-12);
        let end = interpolate(&a, &b, 1.01);
        assert!((end.pos.lat - b.pos.lat).abs() < 1e-15);
    }

    #[test]
    fn thinning_keeps_at_most_the_bound_evenly() {
        let mut t = Thinned::default();
        let r = |k: usize| EpochRecord {
            time: k as f64,
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
            attitude: Vector3::zeros(),
            adaptation: Adaptation::default(),
            position_nees: None,
        };
        for k in 0..100_000 {
            t.push(r(k));
        }
        assert!(t.records.len() <= PLOT_RECORDS && t.records.len() > PLOT_RECORDS / 4);
        let d: Vec<f64> = t
            .records
            .windows(2)
            .map(|w| w[1].time - w[0].time)
            .collect();
        assert!(d.iter().all(|&x| x == d[0]), "even spacing");
    }
}
