//! Why a trajectory description cannot be flown.

use std::fmt;

/// What is wrong with a segment (or, with index `usize::MAX`, with the
/// trajectory's own settings).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrajectoryErrorKind {
    /// A duration, edge, rate, radius or deceleration is not finite and
    /// positive where it must be (or a value is NaN / infinite).
    InvalidParameter,
    /// `Stationary` while moving.
    NotAtRest,
    /// The speed would become negative.
    NegativeSpeed,
    /// A turn by radius, or a climb by vertical speed, at zero speed.
    NeedsSpeed,
    /// A vertical speed at least as large as the speed.
    TooSteep,
    /// `CruiseUntil` a time already passed.
    TimeInPast,
    /// Two parallel manoeuvres drive the same quantity.
    ParallelConflict,
}

/// A trajectory that cannot be built, with the index of the offending
/// top-level segment.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Geodetic};
/// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, TrajectoryErrorKind, Vehicle};
/// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 5.0)
///     .then(Segment::Stationary { duration: 1.0 });
/// let err = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap_err();
/// assert_eq!((err.segment, err.kind), (0, TrajectoryErrorKind::NotAtRest));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrajectoryError {
    /// Index of the segment in [`TrajectorySpec::segments`](super::TrajectorySpec::segments).
    pub segment: usize,
    /// What is wrong.
    pub kind: TrajectoryErrorKind,
}

impl fmt::Display for TrajectoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.kind {
            TrajectoryErrorKind::InvalidParameter => "a parameter is not finite or not positive",
            TrajectoryErrorKind::NotAtRest => "stationary while moving",
            TrajectoryErrorKind::NegativeSpeed => "the speed would become negative",
            TrajectoryErrorKind::NeedsSpeed => "the manoeuvre needs a non-zero speed",
            TrajectoryErrorKind::TooSteep => "the vertical speed exceeds the speed",
            TrajectoryErrorKind::TimeInPast => "the end time has already passed",
            TrajectoryErrorKind::ParallelConflict => "parallel manoeuvres drive the same quantity",
        };
        if self.segment == usize::MAX {
            write!(f, "invalid trajectory settings: {what}")
        } else {
            write!(f, "segment {}: {what}", self.segment)
        }
    }
}

impl std::error::Error for TrajectoryError {}
