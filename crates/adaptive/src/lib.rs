//! # kestrel-adaptive
//!
//! Noise adapters and federated fusion for kestrel filters. The hook traits
//! the adapters implement ([`NoiseAdapter`], [`PriorAdapter`]) live in
//! `kestrel-core`. Every adapter works in measurement space, so it runs
//! unchanged with the covariance form, the UKF and the square-root UKF, in
//! `f32` and `f64`, without allocating. Adapters compose as tuples, run in
//! order, and each one reports what it did in the update report.
//!
//! ```
//! use kestrel_adaptive::{ChiSquareGate, HuberInflation};
//! use kestrel_core::nalgebra::{Matrix2, Vector2};
//! use kestrel_core::Ekf;
//! use kestrel_models::{LinearMeasurement, LinearProcess};
//!
//! // A gate for gross errors first, then Huber inflation of R (paper 002).
//! let adapter = (
//!     ChiSquareGate::<f64, 1>::new(0.001).unwrap(),
//!     HuberInflation::<f64, 1>::as_published().unwrap(),
//! );
//! let mut kf = Ekf::new(Vector2::zeros(), Matrix2::identity())
//!     .unwrap()
//!     .with_adapter(adapter);
//! let process = LinearProcess::new(
//!     Matrix2::new(1.0, 1.0, 0.0, 1.0),
//!     Matrix2::identity() * 0.01,
//! );
//! let sensor = LinearMeasurement::new(
//!     kestrel_core::nalgebra::RowVector2::new(1.0, 0.0),
//!     kestrel_core::nalgebra::Matrix1::new(0.25),
//! );
//! kf.predict(&process, 1.0).unwrap();
//! let report = kf.update(&sensor, &kestrel_core::nalgebra::Vector1::new(0.3)).unwrap();
//! let (gate, huber) = report.adapters;
//! assert!(!gate.rejected);
//! assert_eq!(huber.inflated, 0);
//! ```
//!
//! - [`chi_square_quantile`]: χ² thresholds for innovation tests.
//! - [`SageHusa`]: online estimate of `R` from post-fit residuals (paper 000, eq. 9).
//! - [`DivergenceFading`]: fading memory when `νᵀν > γ tr C` (paper 000, eq. 10–12).
//! - [`StrongTracking`]: the suboptimal fading factor of strong tracking (paper 004).
//! - [`OutlierCompression`]: χ² compression of outlying innovations (paper 000, eq. 13–14).
//! - [`ImprovedAdaptive`], [`SageHusaFading`]: the improved adaptive filter of
//!   paper 000 and its Sage-Husa + fading baseline.
//! - [`federated`]: the federated filter of paper 001 ([`FederatedFilter`]):
//!   heterogeneous local filters, information fusion, sharing-factor reset
//!   (fixed or adaptive by EDOP) and fault isolation.
//! - [`HuberInflation`]: χ² test with per-component Huber inflation of `R`,
//!   the ICT-EREKF (paper 002, eq. 9–15).
//! - [`ChiSquareGate`]: rejects measurements failing `νᵀ C⁻¹ ν ≤ χ²_{1−α}(m)`.
//! - [`fuzzy`]: an allocation-free Mamdani fuzzy inference engine.
//! - [`FuzzyGain`]: fuzzy adaptive odometer gain `α₁` (paper 003, eq. 5),
//!   with the default rule base [`odometer_engine`].
//! - [`WindowedNoise`]: `R` from a window of innovations, projected to be
//!   positive definite (paper 003, eq. 7–8; [`project_spd`]).
//! - [`ConsistencyMonitor`]: filter health: the NIS (or, with a truth, the
//!   NEES) tested window by window, an alarm after three failing windows.
#![no_std]
#![deny(missing_docs)]

pub use kestrel_core::adapter::{NoiseAdapter, PriorAdapter};

mod chi_square;
pub use chi_square::{chi_square_quantile, significance_threshold};

mod divergence_fading;
mod improved;
mod outlier_compression;
mod sage_husa;
mod strong_tracking;
pub use divergence_fading::{DivergenceFading, DivergenceReport};
pub use improved::{CompositionReport, ImprovedAdaptive, SageHusaComposition, SageHusaFading};
pub use outlier_compression::{CompressionReport, OutlierCompression};
pub use sage_husa::{SageHusa, SageHusaReport};
pub use strong_tracking::{StrongTracking, StrongTrackingReport};

pub mod federated;
pub use federated::FederatedFilter;

mod chi_square_gate;
pub mod fuzzy;
mod monitor;
pub use monitor::{ConsistencyMonitor, MonitorEvent, SampleDependence};
mod fuzzy_gain;
mod gated_huber;
mod huber_inflation;
mod spd;
mod windowed_noise;
pub use chi_square_gate::{ChiSquareGate, GateReport};
pub use fuzzy_gain::{
    match_factor, odometer_engine, FuzzyGain, FuzzyGainReport, GainDecision, OdometerEngine,
    OdometerInputs, ODOMETER_RULES, ODOMETER_UNUSABLE,
};
pub use gated_huber::{gated_huber, GatedHuber};
pub use huber_inflation::{HuberInflation, HuberReport, InflationShape};
pub use spd::{project_spd, symmetric_eigen, SpdProjection};
pub use windowed_noise::{WindowedNoise, WindowedNoiseReport};
