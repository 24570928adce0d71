//! Trajectories built from manoeuvres, with exact truth and exact IMU
//! increments.
//!
//! A [`TrajectorySpec`] lists [`Segment`]s; [`Trajectory::new`] compiles
//! them into closed-form profiles of speed, track, flight-path angle and
//! side-slip (raised-cosine transitions, so accelerations and rates are
//! continuous); [`Trajectory::stream`] yields `(truth, increment)` pairs at
//! the IMU rate. See [`ImuStream`] for how the increments are computed.

mod compile;
mod error;
mod motion;
mod path;
mod profile;
mod segment;
mod spec;
mod stream;

pub use error::{TrajectoryError, TrajectoryErrorKind};
pub use motion::Motion;
pub use path::Trajectory;
pub use segment::{ClimbRate, Segment, TurnRate, Vehicle};
pub use spec::TrajectorySpec;
pub use stream::ImuStream;
