//! RMS and maximum errors over the compared epochs.

use kestrel::nav::experiment::{EpochRecord, PositionAxes};
use kestrel::nav::nalgebra::Vector3;

/// The error statistics of a run against the truth.
///
/// The sums are formed in the order and the axes of the experiment
/// runner's summary, so equal records give bit-equal RMS values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorStats {
    /// Axes of the position values.
    pub axes: PositionAxes,
    /// Epochs compared with the truth.
    pub epochs: usize,
    /// Position RMS per axis of `axes`, m.
    pub rms_position: Vector3<f64>,
    /// Velocity RMS north, east, down, m/s.
    pub rms_velocity: Vector3<f64>,
    /// Attitude RMS north, east, down, rad.
    pub rms_attitude: Vector3<f64>,
    /// Largest |error| per position axis of `axes`, m.
    pub max_position: Vector3<f64>,
    /// Largest |error| per velocity axis, m/s.
    pub max_velocity: Vector3<f64>,
    /// Largest |error| per attitude axis, rad.
    pub max_attitude: Vector3<f64>,
    /// Largest 3-D position error, m.
    pub max_position_3d: f64,
}

/// Sums of squares while the run goes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Accumulator {
    axes: PositionAxes,
    n: usize,
    pos: Vector3<f64>,
    vel: Vector3<f64>,
    att: Vector3<f64>,
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
            pos: Vector3::zeros(),
            vel: Vector3::zeros(),
            att: Vector3::zeros(),
            max_pos: Vector3::zeros(),
            max_vel: Vector3::zeros(),
            max_att: Vector3::zeros(),
            max_3d: 0.0,
        }
    }

    pub(crate) fn add(&mut self, r: &EpochRecord) {
        let p = self.axes.from_ned(&r.position);
        self.n += 1;
        self.max_3d = self.max_3d.max(r.position.norm());
        self.pos += p.component_mul(&p);
        self.vel += r.velocity.component_mul(&r.velocity);
        self.att += r.attitude.component_mul(&r.attitude);
        self.max_pos = self.max_pos.sup(&p.abs());
        self.max_vel = self.max_vel.sup(&r.velocity.abs());
        self.max_att = self.max_att.sup(&r.attitude.abs());
    }

    pub(crate) fn finish(&self) -> ErrorStats {
        let n = self.n.max(1) as f64;
        let rms = |s: &Vector3<f64>| (s / n).map(f64::sqrt);
        ErrorStats {
            axes: self.axes,
            epochs: self.n,
            rms_position: rms(&self.pos),
            rms_velocity: rms(&self.vel),
            rms_attitude: rms(&self.att),
            max_position: self.max_pos,
            max_velocity: self.max_vel,
            max_attitude: self.max_att,
            max_position_3d: self.max_3d,
        }
    }
}
