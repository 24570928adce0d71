//! Turns the segment list into closed-form channel profiles.

use super::error::{TrajectoryError, TrajectoryErrorKind as Kind};
use super::profile::{Channel, Piece};
use super::segment::{ClimbRate, Segment, TurnRate};
use super::spec::TrajectorySpec;

/// The four independent kinematic channels of a trajectory.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Channels {
    /// Speed along the path, m/s.
    pub speed: Channel,
    /// Track (direction of the horizontal velocity), rad.
    pub track: Channel,
    /// Flight-path angle (= pitch), rad, positive up.
    pub path: Channel,
    /// Side-slip: vehicle yaw = track − slip, rad.
    pub slip: Channel,
}

/// Values of the channels where a segment starts.
#[derive(Clone, Copy)]
struct Start {
    t: f64,
    speed: f64,
    path: f64,
    slip: f64,
}

/// Tolerance on times and speeds that are zero up to rounding.
const EPS: f64 = 1e-9;

/// Compiles `spec`; returns the channels and the total duration (s).
pub(crate) fn compile(spec: &TrajectorySpec) -> Result<(Channels, f64), TrajectoryError> {
    let settings_ok = [
        spec.heading,
        spec.speed,
        spec.start.lat,
        spec.start.lon,
        spec.start.h,
        spec.mounting.roll,
        spec.mounting.pitch,
        spec.mounting.yaw,
    ]
    .iter()
    .all(|v| v.is_finite())
        && spec.speed >= 0.0
        && positive(spec.edge)
        && positive(spec.pitch_transition);
    if !settings_ok {
        return Err(TrajectoryError {
            segment: usize::MAX,
            kind: Kind::InvalidParameter,
        });
    }
    let mut c = Compiler {
        ch: Channels {
            speed: Channel::new(0.0, spec.speed),
            track: Channel::new(0.0, spec.heading),
            path: Channel::new(0.0, 0.0),
            slip: Channel::new(0.0, 0.0),
        },
        edge: spec.edge,
        pitch_transition: spec.pitch_transition,
    };
    let mut t = 0.0;
    for (index, seg) in spec.segments.iter().enumerate() {
        let start = Start {
            t,
            speed: c.ch.speed.end_value(),
            path: c.ch.path.end_value(),
            slip: c.ch.slip.end_value(),
        };
        t = c.segment(seg, start).map_err(|kind| TrajectoryError {
            segment: index,
            kind,
        })?;
    }
    for ch in [
        &mut c.ch.speed,
        &mut c.ch.track,
        &mut c.ch.path,
        &mut c.ch.slip,
    ] {
        ch.hold_until(t);
    }
    Ok((c.ch, t))
}

fn positive(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

fn non_negative(x: f64) -> bool {
    x.is_finite() && x >= 0.0
}

fn check(ok: bool, kind: Kind) -> Result<(), Kind> {
    if ok {
        Ok(())
    } else {
        Err(kind)
    }
}

struct Compiler {
    ch: Channels,
    edge: f64,
    pitch_transition: f64,
}

/// Appends a piece, refusing to overlap what a parallel manoeuvre already
/// put on the channel.
fn push(ch: &mut Channel, piece: Piece) -> Result<(), Kind> {
    check(piece.t0 >= ch.end_time() - EPS, Kind::ParallelConflict)?;
    ch.push(piece);
    Ok(())
}

/// A rate trapezoid with raised-cosine edges `te`: the value changes by
/// exactly `delta` over `[t0, t0 + span]`, the rate holding
/// `delta / (span − te)` between the edges.
fn ramp(ch: &mut Channel, t0: f64, span: f64, delta: f64, te: f64) -> Result<(), Kind> {
    let t1 = t0 + span;
    let r = delta / (span - te);
    let x0 = ch.end_value();
    push(ch, Piece::rise(t0, t0 + te, x0, r))?;
    let x1 = ch.end_value();
    push(ch, Piece::linear(t0 + te, t1 - te, x1, r))?;
    let x2 = ch.end_value();
    push(ch, Piece::fall(t1 - te, t1, x2, r))?;
    Ok(())
}

impl Compiler {
    /// Compiles one segment; returns its end time.
    fn segment(&mut self, seg: &Segment, s: Start) -> Result<f64, Kind> {
        match *seg {
            Segment::Cruise { duration } => {
                check(non_negative(duration), Kind::InvalidParameter)?;
                Ok(s.t + duration)
            }
            Segment::CruiseUntil { time } => {
                check(time.is_finite(), Kind::InvalidParameter)?;
                check(time >= s.t - EPS, Kind::TimeInPast)?;
                Ok(time.max(s.t))
            }
            Segment::Stationary { duration } => {
                check(non_negative(duration), Kind::InvalidParameter)?;
                check(s.speed.abs() <= EPS, Kind::NotAtRest)?;
                Ok(s.t + duration)
            }
            Segment::Accelerate { accel, duration } => {
                check(
                    accel.is_finite() && positive(duration),
                    Kind::InvalidParameter,
                )?;
                self.speed_change(s, accel * duration, duration)
            }
            Segment::AccelerateTo { speed, accel } => {
                check(
                    non_negative(speed) && positive(accel),
                    Kind::InvalidParameter,
                )?;
                let delta = speed - s.speed;
                self.speed_change(s, delta, delta.abs() / accel)
            }
            Segment::Stop { decel } => {
                check(positive(decel), Kind::InvalidParameter)?;
                self.speed_change(s, -s.speed, s.speed / decel)
            }
            Segment::Climb { climb, duration } => {
                check(positive(duration), Kind::InvalidParameter)?;
                let gamma = match climb {
                    ClimbRate::Pitch(p) => {
                        check(p.is_finite() && p.abs() < 1.5, Kind::InvalidParameter)?;
                        p
                    }
                    ClimbRate::Vertical(vz) => {
                        check(vz.is_finite(), Kind::InvalidParameter)?;
                        check(s.speed > EPS, Kind::NeedsSpeed)?;
                        check(vz.abs() < s.speed, Kind::TooSteep)?;
                        (vz / s.speed).asin()
                    }
                };
                let tt = self.pitch_transition.min(0.5 * duration);
                let t1 = s.t + duration;
                let ch = &mut self.ch.path;
                push(ch, Piece::hann_step(s.t, s.t + tt, s.path, gamma - s.path))?;
                push(ch, Piece::hold(s.t + tt, t1 - tt, gamma))?;
                push(ch, Piece::hann_step(t1 - tt, t1, gamma, s.path - gamma))?;
                Ok(t1)
            }
            Segment::Turn { turn, angle } => {
                check(angle.is_finite(), Kind::InvalidParameter)?;
                let rate = match turn {
                    TurnRate::Rate(r) => {
                        check(positive(r), Kind::InvalidParameter)?;
                        r
                    }
                    TurnRate::Radius(radius) => {
                        check(positive(radius), Kind::InvalidParameter)?;
                        check(s.speed > EPS, Kind::NeedsSpeed)?;
                        s.speed / radius
                    }
                };
                if angle == 0.0 {
                    return Ok(s.t);
                }
                let hold = angle.abs() / rate;
                let te = self.edge.min(hold);
                ramp(&mut self.ch.track, s.t, hold + te, angle, te)?;
                Ok(s.t + hold + te)
            }
            Segment::SideSlip { angle, duration } => {
                check(
                    angle.is_finite() && positive(duration),
                    Kind::InvalidParameter,
                )?;
                let t1 = s.t + duration;
                push(&mut self.ch.slip, Piece::hann_pulse(s.t, t1, s.slip, angle))?;
                Ok(t1)
            }
            Segment::Parallel(ref members) => {
                let mut end = s.t;
                for m in members {
                    end = end.max(self.segment(m, s)?);
                }
                Ok(end)
            }
        }
    }

    /// Speed change by `delta` over `span` s with raised-cosine edges.
    fn speed_change(&mut self, s: Start, delta: f64, span: f64) -> Result<f64, Kind> {
        check(s.speed + delta >= -EPS, Kind::NegativeSpeed)?;
        if span <= 0.0 || delta == 0.0 {
            return Ok(s.t + span.max(0.0));
        }
        let te = self.edge.min(0.5 * span);
        ramp(&mut self.ch.speed, s.t, span, delta, te)?;
        Ok(s.t + span)
    }
}
