//! The plain innovation χ² gate: reject, do not reweight.

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::{FilterError, Real};

use crate::chi_square::significance_threshold;

/// What [`ChiSquareGate`] did in one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GateReport<T: Real> {
    /// `νᵀ C⁻¹ ν` (0 if `C` was not positive definite; nothing is then
    /// rejected).
    pub statistic: T,
    /// The threshold it was compared with.
    pub threshold: T,
    /// Whether this gate rejected the measurement.
    pub rejected: bool,
}

impl<T: Real> Default for GateReport<T> {
    fn default() -> Self {
        Self {
            statistic: T::zero(),
            threshold: T::zero(),
            rejected: false,
        }
    }
}

/// Rejects a measurement whose innovation fails the χ² test
/// `νᵀ C⁻¹ ν > χ²_{1−α}(M)`, `C = H P⁻ Hᵀ + R` (the global test of paper
/// 002, eq. 9–10, used as a hard gate instead of the inflation of
/// [`HuberInflation`](crate::HuberInflation)). A rejected update leaves the
/// filter at its prior.
///
/// The test uses the innovation and covariance left by any adapter before
/// this one in a tuple; put the gate first to test the raw innovation.
///
/// ```
/// use kestrel_adaptive::ChiSquareGate;
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// // 3σ gate on a scalar measurement: χ²₀.₉₉₇₃(1) ≈ 9.
/// let mut gate = ChiSquareGate::<f64, 1>::new(0.0027).unwrap();
/// let mut step = GainStep::new(Vector1::new(4.0), Matrix1::new(1.0), None, Matrix1::new(1.0))
///     .unwrap();
/// let mut report = Default::default();
/// gate.before_gain(&mut step, &mut report); // 16 / 2 = 8 < 9
/// assert!(!report.rejected && !step.is_rejected());
/// assert!((report.statistic - 8.0).abs() < 1e-12);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChiSquareGate<T: Real, const M: usize> {
    threshold: T,
}

impl<T: Real, const M: usize> ChiSquareGate<T, M> {
    /// The gate at significance `significance ∈ (0, 1)` (the probability
    /// that a consistent innovation is rejected): threshold
    /// `χ²_{1−significance}(M)`.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"significance"` outside `(0, 1)`,
    /// or `"dof"` for `M = 0`.
    pub fn new(significance: T) -> Result<Self, FilterError> {
        Ok(Self {
            threshold: significance_threshold(significance, M)?,
        })
    }

    /// The gate with an explicit threshold on `νᵀ C⁻¹ ν`.
    ///
    /// # Errors
    /// `InvalidParameter { name: "threshold", valid: "finite and greater than 0" }` unless it is finite and
    /// positive.
    pub fn with_threshold(threshold: T) -> Result<Self, FilterError> {
        if !(threshold.is_finite() && threshold > T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "threshold",
                valid: "finite and greater than 0",
            });
        }
        Ok(Self { threshold })
    }

    /// The threshold on `νᵀ C⁻¹ ν`.
    pub fn threshold(&self) -> T {
        self.threshold
    }
}

impl<T: Real, const M: usize> PriorAdapter<T> for ChiSquareGate<T, M> {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for ChiSquareGate<T, M> {
    type Report = GateReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        report.threshold = self.threshold;
        let Some(statistic) = step.mahalanobis() else {
            return;
        };
        report.statistic = statistic;
        if statistic > self.threshold {
            report.rejected = true;
            step.reject();
        }
    }
}
