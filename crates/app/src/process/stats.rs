//! RMS and maximum errors over the compared epochs, summed so that they
//! never overflow: a finite error always gives a finite RMS (≤ its maximum).

use crate::experiment::{EpochRecord, PositionAxes};
use kestrel::nav::nalgebra::Vector3;

/// The error statistics of a run against the truth.
///
/// The RMS values are sums of squares scaled by the largest value so far
/// (as in LAPACK's `dnrm2`), so errors up to the largest double give a
/// finite RMS; they agree with the plain `√(Σx²/n)` to a few units in the
/// last place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorStats {
    /// Axes of the position values.
    pub axes: PositionAxes,
    /// Epochs compared with the truth.
    pub epochs: usize,
    /// Position RMS per axis of `axes`, m.
    pub rms_position: Vector3<f64>,
    /// Largest |error| per position axis of `axes`, m.
    pub max_position: Vector3<f64>,
    /// Largest 3-D position error, m.
    pub max_position_3d: f64,
    /// Velocity and attitude statistics; `None` against a position-only
    /// reference (never zeros that look like a result).
    pub motion: Option<MotionStats>,
}

/// Velocity and attitude error statistics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionStats {
    /// Velocity RMS north, east, down, m/s.
    pub rms_velocity: Vector3<f64>,
    /// Attitude RMS north, east, down, rad.
    pub rms_attitude: Vector3<f64>,
    /// Largest |error| per velocity axis, m/s.
    pub max_velocity: Vector3<f64>,
    /// Largest |error| per attitude axis, rad.
    pub max_attitude: Vector3<f64>,
}

/// A sum of squares kept as `scale² · ssq` with `scale` the largest |x|
/// so far, so it never overflows.
///
/// ```
/// use kestrel_app::process::SumOfSquares;
/// let mut s = SumOfSquares::default();
/// for x in [3.0, -4.0] { s.add(x); }
/// assert!((s.rms(2) - 12.5f64.sqrt()).abs() < 1e-15);
/// let mut huge = SumOfSquares::default();
/// for x in [1e300, 1e300] { huge.add(x); }
/// assert_eq!(huge.rms(2), 1e300);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SumOfSquares {
    scale: f64,
    ssq: f64,
}

impl SumOfSquares {
    /// Adds `x²`.
    pub fn add(&mut self, x: f64) {
        let a = x.abs();
        if a == 0.0 {
            return;
        }
        if a > self.scale {
            let r = self.scale / a;
            self.ssq = 1.0 + self.ssq * r * r;
            self.scale = a;
        } else {
            let r = a / self.scale;
            self.ssq += r * r;
        }
    }

    /// `√(Σx² / n)`.
    pub fn rms(&self, n: usize) -> f64 {
        if n == 0 {
            return 0.0;
        }
        self.scale * (self.ssq / n as f64).sqrt()
    }
}

/// Sums of squares while the run goes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Accumulator {
    axes: PositionAxes,
    n: usize,
    /// Epochs with velocity and attitude errors.
    motion: usize,
    pos: [SumOfSquares; 3],
    vel: [SumOfSquares; 3],
    att: [SumOfSquares; 3],
    max_pos: Vector3<f64>,
    max_vel: Vector3<f64>,
    max_att: Vector3<f64>,
    max_3d: f64,
}

impl Accumulator {
    pub(crate) fn new(axes: PositionAxes) -> Self {
        Self {
            axes,
            n: 0,
            motion: 0,
            pos: Default::default(),
            vel: Default::default(),
            att: Default::default(),
            max_pos: Vector3::zeros(),
            max_vel: Vector3::zeros(),
            max_att: Vector3::zeros(),
            max_3d: 0.0,
        }
    }

    /// Epochs added.
    pub(crate) fn epochs(&self) -> usize {
        self.n
    }

    /// Adds the errors of `r`; `motion`: whether its velocity and attitude
    /// errors are known (else only the position is added).
    pub(crate) fn add(&mut self, r: &EpochRecord, motion: bool) {
        let p = self.axes.from_ned(&r.position);
        self.n += 1;
        self.max_3d = self.max_3d.max(r.position.norm());
        for i in 0..3 {
            self.pos[i].add(p[i]);
        }
        self.max_pos = self.max_pos.sup(&p.abs());
        if motion {
            self.motion += 1;
            for i in 0..3 {
                self.vel[i].add(r.velocity[i]);
                self.att[i].add(r.attitude[i]);
            }
            self.max_vel = self.max_vel.sup(&r.velocity.abs());
            self.max_att = self.max_att.sup(&r.attitude.abs());
        }
    }

    /// The statistics, `None` over no epoch (never a 0 that looks like a
    /// result).
    pub(crate) fn finish(&self) -> Option<ErrorStats> {
        if self.n == 0 {
            return None;
        }
        let rms = |s: &[SumOfSquares; 3], n: usize| Vector3::from_fn(|i, _| s[i].rms(n));
        Some(ErrorStats {
            axes: self.axes,
            epochs: self.n,
            rms_position: rms(&self.pos, self.n),
            max_position: self.max_pos,
            max_position_3d: self.max_3d,
            motion: (self.motion > 0).then(|| MotionStats {
                rms_velocity: rms(&self.vel, self.motion),
                rms_attitude: rms(&self.att, self.motion),
                max_velocity: self.max_vel,
                max_attitude: self.max_att,
            }),
        })
    }
}
