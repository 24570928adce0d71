//! What an update did.

use nalgebra::{SMatrix, SVector};

use crate::Real;

/// The outcome of a successful update: the innovation, the normalised
/// innovation squared, and what the noise adapters changed.
///
/// Everything in it is `O(M)`, so a caller that keeps the report copies a
/// few vectors and scalars. The `M × M` matrices of the update (the nominal
/// and the used innovation covariance, the noise used) are in the
/// [`UpdateDetail`] that [`Filter::update_detailed`](crate::Filter::update_detailed)
/// returns.
///
/// `R` is the adapter report type ([`NoiseAdapter::Report`](crate::adapter::NoiseAdapter::Report)),
/// `()` for a filter without adapters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpdateReport<T: Real, const M: usize, R = ()> {
    /// The innovation `ν = z ⊟ h(x⁻)` before any adapter.
    pub innovation: SVector<T, M>,
    /// The innovation the gain was applied to (after compression or scaling).
    pub innovation_used: SVector<T, M>,
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

/// An [`UpdateReport`] with the update's `M × M` matrices, from
/// [`Filter::update_detailed`](crate::Filter::update_detailed) and
/// [`Filter::update_detailed_with`](crate::Filter::update_detailed_with).
///
/// The matrices are a kilobyte at `M = 6`; [`Filter::update`](crate::Filter::update)
/// leaves them out so that a caller who does not read them does not copy
/// them.
///
/// ```
/// use kestrel_core::{Ekf, MeasurementModel, LinearizedMeasurement, nalgebra::{Matrix1, Vector1}};
///
/// struct Direct;
/// impl MeasurementModel<f64, 1, 1> for Direct {
///     fn predict(&self, x: &Vector1<f64>) -> Vector1<f64> { *x }
///     fn noise(&self) -> Matrix1<f64> { Matrix1::new(3.0) }
/// }
/// impl LinearizedMeasurement<f64, 1, 1> for Direct {
///     fn jacobian(&self, _x: &Vector1<f64>) -> Matrix1<f64> { Matrix1::new(1.0) }
/// }
///
/// let mut kf = Ekf::new(Vector1::new(0.0), Matrix1::new(1.0))?;
/// let detail = kf.update_detailed(&Direct, &Vector1::new(2.0))?;
/// // C = P + R = 1 + 3; no adapter, so nominal and used agree.
/// assert_eq!(detail.innovation_covariance[0], 4.0);
/// assert_eq!(detail.nominal_innovation_covariance, detail.innovation_covariance);
/// assert_eq!(detail.noise[0], 3.0);
/// assert_eq!(detail.report.nis, 1.0); // 2² / 4
/// # Ok::<(), kestrel_core::FilterError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpdateDetail<T: Real, const M: usize, R = ()> {
    /// What [`Filter::update`](crate::Filter::update) returns.
    pub report: UpdateReport<T, M, R>,
    /// The innovation covariance `C = H P⁻ Hᵀ + R` from the models, before
    /// the adapters' `before_gain` (`P⁻` includes an after-predict fade).
    pub nominal_innovation_covariance: SMatrix<T, M, M>,
    /// The innovation covariance the gain used (with any fade or new `R`).
    pub innovation_covariance: SMatrix<T, M, M>,
    /// The measurement noise covariance the gain used.
    pub noise: SMatrix<T, M, M>,
}

/// What an update returns: an [`UpdateReport`], or an [`UpdateDetail`]
/// with the update's matrices. The forms build their result through it, so
/// a report is written where the caller wants it and the matrices it drops
/// are never stored.
///
/// ```
/// use kestrel_core::{UpdateDetail, UpdateOutcome, UpdateReport, nalgebra::{Matrix1, Vector1}};
/// let report = UpdateReport {
///     innovation: Vector1::new(2.0),
///     innovation_used: Vector1::new(2.0),
///     nis: 1.0,
///     adapted_nis: 1.0,
///     fade: 1.0,
///     rejected: false,
///     sequential: false,
///     adapters: (),
/// };
/// let (c, r) = (Matrix1::new(4.0), Matrix1::new(3.0));
/// let lean: UpdateReport<f64, 1> = UpdateOutcome::assemble(report, &c, &c, &r);
/// let detail: UpdateDetail<f64, 1> = UpdateOutcome::assemble(report, &c, &c, &r);
/// assert_eq!(lean, detail.report);
/// assert_eq!(detail.noise, r);
/// ```
pub trait UpdateOutcome<T: Real, const M: usize, R>: Sized {
    /// The outcome of an update with report `report`, nominal innovation
    /// covariance `nominal`, innovation covariance used `used` and noise
    /// used `noise` (see [`UpdateDetail`]).
    fn assemble(
        report: UpdateReport<T, M, R>,
        nominal: &SMatrix<T, M, M>,
        used: &SMatrix<T, M, M>,
        noise: &SMatrix<T, M, M>,
    ) -> Self;
}

impl<T: Real, const M: usize, R> UpdateOutcome<T, M, R> for UpdateReport<T, M, R> {
    #[inline(always)]
    fn assemble(
        report: UpdateReport<T, M, R>,
        _: &SMatrix<T, M, M>,
        _: &SMatrix<T, M, M>,
        _: &SMatrix<T, M, M>,
    ) -> Self {
        report
    }
}

impl<T: Real, const M: usize, R> UpdateOutcome<T, M, R> for UpdateDetail<T, M, R> {
    #[inline(always)]
    fn assemble(
        report: UpdateReport<T, M, R>,
        nominal: &SMatrix<T, M, M>,
        used: &SMatrix<T, M, M>,
        noise: &SMatrix<T, M, M>,
    ) -> Self {
        Self {
            report,
            nominal_innovation_covariance: *nominal,
            innovation_covariance: *used,
            noise: *noise,
        }
    }
}
