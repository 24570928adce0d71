//! Why a run did not complete.

use kestrel::adaptive::federated::FusionError;
use kestrel::FilterError;

use kestrel::sim::TrajectoryError;

/// The error of a run.
///
/// ```
/// use kestrel_app::experiment::RunError;
/// let e = RunError::NonFinite { filter: "KF", time: 12.5 };
/// assert_eq!(e.to_string(), "KF diverged at 12.5 s: non-finite navigation solution");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// The scenario's trajectory (or the IMU rate) is invalid.
    Trajectory(TrajectoryError),
    /// This filter kind is not built by the runner.
    Unsupported {
        /// The filter's label.
        filter: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// The filter kind does not fit the scenario (error model,
    /// measurement or a missing sensor).
    Incompatible {
        /// The filter's label.
        filter: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// A parameter of the filter kind was refused by its adapter.
    InvalidParameter {
        /// The filter's label.
        filter: &'static str,
        /// The adapter's error.
        error: FilterError,
    },
    /// The filter failed (e.g. lost positive definiteness) at `time`.
    Filter {
        /// The filter's label.
        filter: &'static str,
        /// Simulation time, s.
        time: f64,
        /// The filter's error.
        error: FilterError,
    },
    /// The federated filter's fusion or information sharing failed at `time`.
    Fusion {
        /// The filter's label.
        filter: &'static str,
        /// Simulation time, s.
        time: f64,
        /// The fusion error.
        error: FusionError,
    },
    /// The run would be longer than [`MAX_IMU_SAMPLES`](super::MAX_IMU_SAMPLES)
    /// IMU samples (duration × IMU rate): refused before any work.
    TooLong {
        /// The duration, s.
        duration: f64,
        /// The IMU rate, Hz.
        rate: f64,
    },
    /// The navigation solution became non-finite at `time`.
    NonFinite {
        /// The filter's label.
        filter: &'static str,
        /// Simulation time, s.
        time: f64,
    },
}

impl core::fmt::Display for RunError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Trajectory(e) => write!(f, "invalid trajectory: {e}"),
            Self::Unsupported { filter, reason } => {
                write!(f, "{filter} is not supported: {reason}")
            }
            Self::Incompatible { filter, reason } => {
                write!(f, "{filter} does not fit the scenario: {reason}")
            }
            Self::InvalidParameter { filter, error } => {
                write!(f, "{filter}: invalid parameter: {error}")
            }
            Self::Filter {
                filter,
                time,
                error,
            } => write!(f, "{filter} diverged at {time} s: {error}"),
            Self::Fusion {
                filter,
                time,
                error,
            } => write!(f, "{filter} diverged at {time} s: {error}"),
            Self::TooLong { duration, rate } => write!(
                f,
                "{duration} s at {rate} Hz would be {} IMU samples, more than the limit of {} \
                 (about 28 h at 200 Hz): shorten the duration or lower the IMU rate",
                duration * rate,
                super::MAX_IMU_SAMPLES
            ),
            Self::NonFinite { filter, time } => {
                write!(
                    f,
                    "{filter} diverged at {time} s: non-finite navigation solution"
                )
            }
        }
    }
}

impl std::error::Error for RunError {}

impl From<TrajectoryError> for RunError {
    fn from(e: TrajectoryError) -> Self {
        Self::Trajectory(e)
    }
}
