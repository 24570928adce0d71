//! Error-state measurement models of the aiding sensors.
//!
//! Each model is built per epoch from the INS solution ([`InsContext`]) and
//! a sensor reading, as an [`ErrorMeasurement`]: `z` is the INS-minus-sensor
//! difference, `predict(x) = H x`, `R` from the sensor's standard
//! deviations. `H` is given in each builder's documentation:
//!
//! | builder | m | rows |
//! |---|---|---|
//! | [`GnssAntenna::position_velocity`] | 6 | position, velocity with lever arm |
//! | [`GnssAntenna::position`] | 3 | position with lever arm |
//! | [`GnssAntenna::attitude_velocity_position`] | 9 | attitude, velocity, position (paper 004) |
//! | [`Odometer::forward`] | 1 | vehicle-frame forward speed, scale factor |
//! | [`Odometer::nhc`] | 2 | lateral and vertical vehicle velocity ≈ 0 |
//! | [`Odometer::forward_nhc`] | 3 | both (paper 003's velocity match) |
//! | [`ZeroVelocity::measurement`] | 3 | NED velocity ≈ 0 at standstill (ZUPT) |
//! | [`ZeroAngularRate::measurement`] | 3 | body rate ≈ Earth rate at standstill (ZARU) |
//!
//! The state layout (where the gyro bias and the odometer scale sit) comes
//! from an [`ErrorLayout`].

mod context;
mod difference;
mod gnss;
mod layout;
mod odometer;
mod reference;
mod standstill;

pub use context::InsContext;
pub use difference::ErrorMeasurement;
pub use gnss::{GnssAntenna, GnssFix};
pub(crate) use layout::fits as layout_fits;
pub use layout::ErrorLayout;
pub use odometer::{Odometer, OdometerReading};
pub use reference::AttitudeFix;
pub use standstill::{ZeroAngularRate, ZeroVelocity};
