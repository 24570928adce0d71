//! Sensor models: IMU errors, GNSS, odometer and attitude reference, each
//! drawing from its own seeded stream (see [`SensorStream`]).

mod attitude;
mod gnss;
mod gnss_config;
mod imu;
mod imu_errors;
mod markov;
mod multipath;
mod odometer;
mod rng;
mod schedule;
mod simulated;
mod window;

pub use attitude::{AttitudeConfig, AttitudeSensor};
pub use gnss::GnssSensor;
pub use gnss_config::{GnssConfig, NoiseWindow, Outlier, OutlierKind, ReportedStd};
pub use imu::ImuSensor;
pub use imu_errors::ImuErrors;
pub use markov::{GaussMarkov, GaussMarkov3};
pub use multipath::MultipathBursts;
pub use odometer::{OdometerConfig, OdometerFault, OdometerFaultKind, OdometerSensor};
pub use rng::{sensor_rng, SensorStream, SimRng};
pub use simulated::Simulated;
pub use window::TimeWindow;
