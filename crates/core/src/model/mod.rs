//! The traits a user implements to describe a system: how the state evolves
//! ([`ProcessModel`]), what a sensor sees ([`MeasurementModel`]), and, for
//! the covariance form, their Jacobians.

mod measurement;
mod process;

pub use measurement::{LinearizedMeasurement, MeasurementModel};
pub use process::{LinearizedProcess, ProcessModel};
