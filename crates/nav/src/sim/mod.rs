//! Simulation: trajectories with exact truth and IMU increments, and
//! sensor models (IMU errors, GNSS, odometer, attitude) driven by seeded
//! random number generators. The sensors deliver the
//! [`measurement`](crate::measurement) types the filters use, wrapped in
//! [`Simulated`] where the simulation also knows whether it corrupted them.

pub mod sensors;
pub mod trajectory;

pub use sensors::{
    sensor_rng, AttitudeConfig, AttitudeSensor, GaussMarkov, GaussMarkov3, GnssConfig, GnssSensor,
    ImuErrors, ImuSensor, MultipathBursts, NoiseWindow, OdometerConfig, OdometerFault,
    OdometerFaultKind, OdometerSensor, Outlier, OutlierKind, ReportedStd, SensorStream, SimRng,
    Simulated, TimeWindow,
};
pub use trajectory::{
    ClimbRate, ImuStream, Motion, Segment, Trajectory, TrajectoryError, TrajectoryErrorKind,
    TrajectorySpec, TurnRate, Vehicle,
};
