//! The manoeuvres a trajectory is built from.

/// The kind of vehicle: it decides the roll attitude in turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vehicle {
    /// Banks into coordinated turns: `tan φ = V χ' / g₀` (roll φ, speed V,
    /// turn rate χ', g₀ = 9.80665 m/s²), so the specific force stays close
    /// to the vehicle x–z plane (exactly so in a level turn where local gravity
    /// is g₀ and the Earth's rotation is ignored).
    Aircraft,
    /// Stays level in roll (a car); the pitch follows the road grade.
    Ground,
}

/// How a turn is flown or driven.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TurnRate {
    /// Turn rate, rad/s (magnitude; the direction comes from the angle).
    Rate(f64),
    /// Turn radius, m, at the speed held when the turn starts.
    Radius(f64),
}

/// How steep a climb (or, negative, a descent) is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClimbRate {
    /// Flight-path angle (= pitch, no angle of attack), rad, positive up.
    Pitch(f64),
    /// Vertical speed, m/s, positive up, at the speed held when the climb
    /// starts.
    Vertical(f64),
}

/// One manoeuvre. Speed, track, flight-path angle and side-slip change
/// smoothly (raised-cosine edges) so accelerations and angular rates are
/// continuous; edge lengths are set on the
/// [`TrajectorySpec`](super::TrajectorySpec).
///
/// Angles are radians; the `*_deg` constructors take degrees.
///
/// ```
/// use kestrel_sim::{Segment, TurnRate};
/// let s = Segment::turn_rate_deg(3.0, -90.0);
/// assert!(matches!(s, Segment::Turn { turn: TurnRate::Rate(_), .. }));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Segment {
    /// Constant velocity (level flight, a straight drive; at rest if the
    /// speed is zero) for `duration` s.
    Cruise {
        /// Length, s.
        duration: f64,
    },
    /// Constant velocity until the absolute time `time` (s from the start):
    /// lets a scenario pin events to the clock whatever the manoeuvres took.
    CruiseUntil {
        /// End time, s from the start.
        time: f64,
    },
    /// At rest for `duration` s; the speed must already be zero.
    Stationary {
        /// Length, s.
        duration: f64,
    },
    /// Speed change of exactly `accel · duration` in exactly `duration` s
    /// (the mean acceleration is `accel`; the raised-cosine edges make the
    /// peak slightly larger). Negative `accel` decelerates.
    Accelerate {
        /// Mean acceleration along the path, m/s².
        accel: f64,
        /// Length, s.
        duration: f64,
    },
    /// Speed change to `speed` at the mean acceleration magnitude `accel`.
    AccelerateTo {
        /// Target speed, m/s.
        speed: f64,
        /// Mean acceleration magnitude, m/s² (> 0).
        accel: f64,
    },
    /// Decelerate to rest at the mean deceleration `decel` (m/s², > 0).
    Stop {
        /// Mean deceleration magnitude, m/s².
        decel: f64,
    },
    /// Climb (or descend) at constant speed: the flight-path angle rises to
    /// the climb angle, holds, and returns to level within `duration` s.
    /// For a ground vehicle this is a road grade.
    Climb {
        /// The climb angle or vertical speed.
        climb: ClimbRate,
        /// Length including both pitch transitions, s.
        duration: f64,
    },
    /// A turn at constant speed through `angle` (rad; positive turns right,
    /// i.e. clockwise seen from above). The rate ramps up and down over the
    /// edge time and holds the nominal value in between, so the turn lasts
    /// `|angle| / rate + edge`.
    Turn {
        /// Rate or radius of the turn.
        turn: TurnRate,
        /// Heading change, rad.
        angle: f64,
    },
    /// A side-slip event: the vehicle yaws away from the direction of travel
    /// by up to `angle` (rad) and back within `duration` s while the track is
    /// unchanged, so it moves sideways in its own axes (the motion an
    /// odometer does not see).
    SideSlip {
        /// Peak slip angle (vehicle yaw = track − slip), rad.
        angle: f64,
        /// Length, s.
        duration: f64,
    },
    /// Manoeuvres flown at the same time (e.g. an accelerating climbing
    /// turn). Each must drive different quantities (speed, track, path
    /// angle, slip); all start together and the segment lasts as long as
    /// the longest. Rates that depend on the speed (turn radius, vertical
    /// speed) use the speed at the start.
    Parallel(Vec<Segment>),
}

impl Segment {
    /// A turn at `rate_deg_s` (°/s) through `angle_deg` (°, positive right).
    ///
    /// ```
    /// let s = kestrel_sim::Segment::turn_rate_deg(2.0, 90.0);
    /// assert!(matches!(s, kestrel_sim::Segment::Turn { .. }));
    /// ```
    pub fn turn_rate_deg(rate_deg_s: f64, angle_deg: f64) -> Self {
        Self::Turn {
            turn: TurnRate::Rate(rate_deg_s.to_radians()),
            angle: angle_deg.to_radians(),
        }
    }

    /// A turn of radius `radius_m` (m) through `angle_deg` (°, positive right).
    ///
    /// ```
    /// let s = kestrel_sim::Segment::turn_radius_deg(10.0, -90.0);
    /// assert!(matches!(s, kestrel_sim::Segment::Turn { .. }));
    /// ```
    pub fn turn_radius_deg(radius_m: f64, angle_deg: f64) -> Self {
        Self::Turn {
            turn: TurnRate::Radius(radius_m),
            angle: angle_deg.to_radians(),
        }
    }

    /// A climb at the flight-path angle `pitch_deg` (°, negative descends)
    /// lasting `duration` s.
    ///
    /// ```
    /// let s = kestrel_sim::Segment::climb_pitch_deg(5.0, 60.0);
    /// assert!(matches!(s, kestrel_sim::Segment::Climb { .. }));
    /// ```
    pub fn climb_pitch_deg(pitch_deg: f64, duration: f64) -> Self {
        Self::Climb {
            climb: ClimbRate::Pitch(pitch_deg.to_radians()),
            duration,
        }
    }

    /// A climb at the vertical speed `rate_m_s` (m/s, negative descends)
    /// lasting `duration` s.
    ///
    /// ```
    /// let s = kestrel_sim::Segment::climb_rate(-5.0, 100.0);
    /// assert!(matches!(s, kestrel_sim::Segment::Climb { .. }));
    /// ```
    pub fn climb_rate(rate_m_s: f64, duration: f64) -> Self {
        Self::Climb {
            climb: ClimbRate::Vertical(rate_m_s),
            duration,
        }
    }

    /// A side-slip event peaking at `angle_deg` (°) lasting `duration` s.
    ///
    /// ```
    /// let s = kestrel_sim::Segment::side_slip_deg(5.0, 2.0);
    /// assert!(matches!(s, kestrel_sim::Segment::SideSlip { .. }));
    /// ```
    pub fn side_slip_deg(angle_deg: f64, duration: f64) -> Self {
        Self::SideSlip {
            angle: angle_deg.to_radians(),
            duration,
        }
    }
}
