//! SINS / odometer (dead-reckoning) integration, paper 003: the 16-state
//! error system with the odometer scale factor, and the odometer fault
//! processing compared in the paper — the fuzzy adaptive gain with a
//! windowed `R` estimate ([`FuzzyOdometer`]) and the max-threshold
//! baseline ([`MaxThreshold`]). Both are noise adapters for the odometer
//! update ([`LooselyCoupled::apply_with`](crate::engine::LooselyCoupled::apply_with)).

mod error_model;
mod fuzzy;
mod threshold;

pub use error_model::{InsOdometer16, ScaleFactorProcess, ODOMETER_SCALE};
pub use fuzzy::{FuzzyAdapter, FuzzyOdometer};

pub use threshold::{MaxThreshold, ThresholdReport};
