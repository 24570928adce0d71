//! The loosely coupled integration engine.
//!
//! [`LooselyCoupled`] runs the strapdown mechanisation at IMU rate and an
//! error-state kestrel filter at the aiding epochs, with closed-loop
//! feedback. The error system ([`Ins15`], [`Ins18`],
//! [`InsOdometer16`](crate::odometer::InsOdometer16), or any
//! [`ErrorSystem`]) fixes the state layout and the process model; the filter
//! type (covariance form, UKF, SR-UKF, with any adapter tuple) is a type
//! parameter.
//!
//! Design choices:
//! - Covariance rate: the covariance is propagated once per configurable
//!   interval (e.g. 0.1 s) with `Φ` from the interval's mean specific force,
//!   linearised at the current solution, and always up to the current IMU
//!   sample before an update. Per IMU sample only the mechanisation runs.
//! - Epoch alignment: an aiding epoch between two IMU samples is processed
//!   at the earlier one, with the INS solution extrapolated to the epoch
//!   (first order, less than one IMU period) to form the measurement.
//! - Feedback: after every update the attitude, velocity and position are
//!   corrected, the sensor-error estimates accumulated into
//!   [`SensorCorrections`] (subtracted from later readings) and the error
//!   state reset to zero; the covariance is kept (identity reset Jacobian).
//! - Smoothing: with [`LooselyCoupled::record_epochs`] the engine keeps
//!   what a Rauch–Tung–Striebel pass over the closed-loop error state
//!   needs, one [`ForwardEpoch`] per covariance epoch.

mod feedback;
mod loosely;
mod record;
mod run;
mod system;

pub use feedback::{feed_back, SensorCorrections};
pub use loosely::LooselyCoupled;
pub use record::ForwardEpoch;
pub use run::{Epoch, Timed};
pub use system::{ErrorSystem, InitialUncertainty, Ins15, Ins18, Ins21};
