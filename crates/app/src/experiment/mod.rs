//! Running a [`Scenario`](crate::scenario::Scenario) with one of its
//! filters: the missing piece between the papers' experiments as data and
//! their results.
//!
//! [`run`] simulates the scenario's truth and sensors from a seed
//! ([`Simulation`]), builds the concrete filter of a runtime
//! [`FilterKind`](crate::scenario::FilterKind) (one monomorphised loop per
//! kind, chosen by a `match`; nothing is dynamically dispatched inside the
//! loop), runs the [`LooselyCoupled`](kestrel::nav::engine::LooselyCoupled) engine
//! and reports every aiding epoch ([`EpochRecord`]: navigation errors
//! against the truth and what the adapters did) and a [`RunSummary`] (RMS
//! per axis). [`run_with`] streams the records to a callback instead of
//! storing them; [`run_together`] runs several filters on one simulation
//! (each sample handed to every filter in turn), for the cost of
//! simulating once and with each filter's results unchanged.
//!
//! The building blocks are public for loops over other data sources
//! (recorded files): [`build_filter`] turns a kind into its adapter or
//! odometer processing for a [`FilterLoop`], [`closed_loop_ekf`] builds
//! the filter, [`GnssAiding`] and [`OdometerAiding`] are the update steps
//! on any [`AidedEngine`], and [`Adaptation::from_update`] reads what the
//! adapters did ([`Describe`]), so such a loop computes exactly what the
//! in-memory runner computes.
//!
//! Design choices:
//! - Identical data: the sensors draw only from the seed and the truth,
//!   never from the filter, so every filter kind of a scenario sees the
//!   same IMU, GNSS, attitude and odometer data for the same seed
//!   ([`RunSummary::data_digest`] fingerprints it).
//! - Aiding at the IMU samples: every simulated sensor samples at an IMU
//!   time, so the engine updates right after that sample and the
//!   navigation errors are taken against the truth of the same instant.
//! - Records and RMS: one record per aiding update, with the errors of
//!   the solution just after it; the RMS is taken over these records, the
//!   position in the axes the paper prints ([`PositionAxes::for_scenario`]:
//!   east, north, up — longitude, latitude, height — for 000, 002 and 004),
//!   velocity and attitude in north, east, down.
//! - Paper 004's nine-row measurement is formed when the attitude reference
//!   and a GNSS fix arrive at the same sample (both 1 Hz in the scenario).
//! - The filter's `R` is the scenario's [`FilterSetup::r`](crate::scenario::FilterSetup::r)
//!   (the adaptive filters' initial `R`), not the σ a receiver reports.
//! - Divergence is an error ([`RunError::Filter`], [`RunError::Fusion`],
//!   [`RunError::NonFinite`])
//!   naming the filter and the time, never a panic.
//! - Paper 001's federated filters: a local EKF on the GNSS position and a
//!   local UKF or SR-UKF on the GNSS velocity over the common 15-state
//!   error model, EDOP information sharing, the fused estimate fed back
//!   in closed loop by the runner's own loop (the engine hosts a single
//!   filter).
//! - Every other kind is the closed-loop error-state EKF with the
//!   kind's adapter; paper 003's odometer processing is applied per update
//!   ([`MaxThreshold`](kestrel::nav::odometer::MaxThreshold),
//!   [`FuzzyOdometer`](kestrel::nav::odometer::FuzzyOdometer), whose R window
//!   must be 10, 20 or 50: it is a compile-time length).

mod aiding;
mod data;
mod dispatch;
mod error;
mod federated;
mod health;
mod options;
mod precision;
mod record;
mod run;
mod summary;

pub use aiding::{AidedEngine, GnssAiding, GnssNoise, OdometerAiding, OdometerProcessing};
pub use data::{SensorSample, Simulation, MAX_IMU_SAMPLES};
pub use dispatch::{build_filter, closed_loop_ekf, BuildError, FilterLoop};
pub use error::RunError;
pub use health::{Health, HealthCheck, HealthEvent, HealthEventKind, HealthSummary};
pub use options::{PositionAxes, RunOptions};
pub use precision::{
    compare_federated_precision, MaxDifference, Outcome, Precision, PrecisionOptions,
    PrecisionReport, PrecisionRun, PrecisionSetup, StateScaling,
};
pub use record::{Adaptation, Describe, EpochRecord};
pub use run::{run, run_together, run_with, RunResult};
pub use summary::{RunSummary, ScaleEstimate};
