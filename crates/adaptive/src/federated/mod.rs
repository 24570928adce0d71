//! Federated filtering (paper 001, after Carlson): local filters of possibly
//! different forms sharing a common state, fused in information form, reset
//! with information-sharing factors, with fault isolation.
//!
//! - [`FederatedFilter`]: the locals, the fusion
//!   `P_g = (Σ P_i⁻¹)⁻¹`, `x_g = P_g Σ P_i⁻¹ x_i`, the reset
//!   `x_i = x_g`, `P_i = β_i⁻¹ P_g` and the isolation bookkeeping.
//! - [`Sharing`]: fixed shares, the paper's adaptive shares from
//!   `EDOP_i = sqrt(tr(P_i P_iᵀ))` (eq. 25, generalised to `L` locals as
//!   `β_i ∝ 1 / EDOP_i`), or no reset. A master filter is a local that is
//!   only predicted, holding its share `β_m`.
//! - [`SharedNoise`]: the process model of local `i`, noise `β_i⁻¹ Q`.
//! - [`Isolation`]: isolate a local after `K` consecutive epochs failing the
//!   innovation test `NIS > χ²_{1−α}(m)`, re-admit after `K_r` passing ones.
//! - [`LocalFilter`] / [`LocalSet`]: what fusion needs of a local (every
//!   kestrel [`Filter`](kestrel_core::Filter) is one) and of a tuple or
//!   array of them.
//! - [`Information`] and [`fuse`]: the information-form fusion itself.
//!
//! Decisions beyond the paper:
//! - An isolated local is still reset, to the fused estimate with the fused
//!   covariance (`β = 1`, unscaled `Q`), but not fused: its innovation test
//!   then checks its sensor against the healthy fusion with the correct
//!   covariance, so a persistent fault keeps failing and a recovery passes.
//! - The shares of the admitted locals are renormalised to the configured
//!   total when others are isolated, so the healthy fusion keeps all the
//!   information.
//! - A re-admitted local joins fusion one epoch later, after its reset to
//!   its share (see [`FederatedFilter::fuse`]).
//! - With every local isolated, [`FederatedFilter::fuse`] returns
//!   [`FusionError::AllIsolated`] and keeps the last fused estimate.

mod error;
mod filter;
mod information;
mod isolation;
mod local;
mod report;
mod set;
mod shared_noise;
mod sharing;

pub use error::FusionError;
pub use filter::FederatedFilter;
pub use information::{fuse, Information};
pub use isolation::{Isolation, LocalStatus, Verdict};
pub use local::LocalFilter;
pub use report::{FusionReport, LocalReport};
pub use set::{LocalSet, PredictLocal, PredictSet};
pub use shared_noise::SharedNoise;
pub use sharing::{edop, edop_shares, Policy, Sharing};
