//! What an update did.

use nalgebra::{SMatrix, SVector};

use crate::Real;

/// The outcome of a successful update: the innovation, its covariance, the
/// normalised innovation squared, and what the noise adapters changed.
///
/// `R` is the adapter report type ([`NoiseAdapter::Report`](crate::adapter::NoiseAdapter::Report)),
/// `()` for a filter without adapters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpdateReport<T: Real, const M: usize, R = ()> {
    /// The innovation `ν = z ⊟ h(x⁻)` before any adapter.
    pub innovation: SVector<T, M>,
    /// The innovation the gain was applied to (after compression or scaling).
    pub innovation_used: SVector<T, M>,
    /// The innovation covariance `C = H P⁻ Hᵀ + R` from the models, before
    /// the adapters' `before_gain` (`P⁻` includes an after-predict fade).
    pub nominal_innovation_covariance: SMatrix<T, M, M>,
    /// The innovation covariance the gain used (with any fade or new `R`).
    pub innovation_covariance: SMatrix<T, M, M>,
    /// The measurement noise covariance the gain used.
    pub noise: SMatrix<T, M, M>,
    /// Normalised innovation squared `νᵀ C⁻¹ ν` of the raw innovation against
    /// the nominal covariance: the consistency statistic, `χ²(M)` when the
    /// filter is consistent.
    pub nis: T,
    /// `νᵀ C⁻¹ ν` of the innovation used against the covariance used.
    pub adapted_nis: T,
    /// The fade applied to the propagated covariance at this update (1 = none).
    pub fade: T,
    /// Whether an adapter rejected the measurement (the state is the prior).
    pub rejected: bool,
    /// Whether the covariance form used sequential scalar updates.
    pub sequential: bool,
    /// The adapters' own reports.
    pub adapters: R,
}
