//! Random multipath / non-line-of-sight bursts of a GNSS receiver in an
//! urban canyon.

use nalgebra::Vector3;
use rand::RngExt;

use super::rng::{uniform, SimRng};

/// Randomly timed bursts of multipath / NLOS error: while no burst is
/// active, each fix starts one with probability `onset_probability`; a
/// burst lasts a duration uniform in `duration` (s) and carries a bias
/// drawn once per burst, uniform in `±position` per NED axis (m). The
/// bias builds up linearly over `rise` s (a reflected signal slowly
/// taking over as the geometry changes; `0` = a step) and falls back the
/// same way before the end; on top, every fix of the burst gets an error
/// uniform in `±position_jitter` (m). The velocity, measured from Doppler
/// and not from the biased ranges, gets its own bias, drawn once per burst
/// uniform in `±velocity_bias` and present for the whole burst, plus a
/// per-fix error uniform in `±velocity` (m/s). All draws come from the receiver's own
/// multipath stream.
///
/// ```
/// use kestrel_nav::{nalgebra::Vector3};
/// use kestrel_sim::MultipathBursts;
/// let m = MultipathBursts {
///     onset_probability: 0.02,
///     duration: (10.0, 60.0),
///     rise: 5.0,
///     position: Vector3::new(10.0, 10.0, 30.0),
///     position_jitter: Vector3::repeat(1.0),
///     velocity_bias: Vector3::new(0.1, 0.1, 0.2),
///     velocity: Vector3::new(0.2, 0.2, 0.4),
/// };
/// assert_eq!(m.duration.1, 60.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultipathBursts {
    /// Probability per fix that a burst starts while none is active, in
    /// [0, 1].
    pub onset_probability: f64,
    /// Range of the burst length, s.
    pub duration: (f64, f64),
    /// Build-up (and fall-off) time of the bias, s.
    pub rise: f64,
    /// Largest bias per axis north, east, down, m.
    pub position: Vector3<f64>,
    /// Half-width of the per-fix position error per axis, m.
    pub position_jitter: Vector3<f64>,
    /// Largest velocity bias per axis north, east, down (m/s), drawn once
    /// per burst like the position bias and present for the whole burst.
    pub velocity_bias: Vector3<f64>,
    /// Half-width of the per-fix velocity error per axis, m/s.
    pub velocity: Vector3<f64>,
}

/// A burst in progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Burst {
    start: f64,
    end: f64,
    bias: Vector3<f64>,
    velocity_bias: Vector3<f64>,
}

impl Burst {
    /// The error of the fix at `t` (position m, velocity m/s), or `None`
    /// once the burst is over.
    pub(crate) fn error(
        &self,
        m: &MultipathBursts,
        t: f64,
        rng: &mut SimRng,
    ) -> Option<(Vector3<f64>, Vector3<f64>)> {
        if t >= self.end {
            return None;
        }
        // Trapezoid envelope: up over `rise`, down over `rise` before the
        // end (shortened for bursts shorter than two rises).
        let rise = m.rise.min(0.5 * (self.end - self.start));
        let envelope = if rise <= 0.0 {
            1.0
        } else {
            ((t - self.start).min(self.end - t) / rise).min(1.0)
        };
        let pos = self.bias * envelope + signed(rng, &m.position_jitter);
        let vel = self.velocity_bias + signed(rng, &m.velocity);
        Some((pos, vel))
    }
}

/// Starts a burst at `t` with probability `onset_probability`.
pub(crate) fn maybe_start(m: &MultipathBursts, t: f64, rng: &mut SimRng) -> Option<Burst> {
    if rng.random::<f64>() >= m.onset_probability {
        return None;
    }
    let length = uniform(rng, m.duration.0, m.duration.1);
    Some(Burst {
        start: t,
        end: t + length,
        bias: signed(rng, &m.position),
        velocity_bias: signed(rng, &m.velocity_bias),
    })
}

/// Per-axis uniform draws in `±amplitude`.
fn signed(rng: &mut SimRng, amplitude: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(
        uniform(rng, -amplitude.x, amplitude.x),
        uniform(rng, -amplitude.y, amplitude.y),
        uniform(rng, -amplitude.z, amplitude.z),
    )
}
