//! χ² compression of outlying innovations (paper 000, eq. 13–14).

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

use crate::chi_square::significance_threshold;

/// Compression of an outlying innovation, paper 000, eq. 13–14: with
/// `τ = νᵀ C⁻¹ ν` (`C = H P⁻ Hᵀ + R`) and the threshold `c = χ²_{1−α}(m)`,
/// the gain is applied to
///
/// ```text
/// ν' = Y(τ) ν,   Y(τ) = 1 if τ ≤ c,   sqrt(c / τ) if τ > c
/// ```
///
/// so an outlier moves the estimate no further than an innovation on the
/// edge of the test would (`ν'ᵀ C⁻¹ ν' = c`). (The paper writes the
/// threshold as `D²/λ` with `D = sqrt(λ c)` and `λ` the largest eigenvalue
/// of `K C Kᵀ`; `λ` cancels.) When `τ ≤ c` the innovation is not touched at
/// all: the factor is exactly 1.
///
/// The measurement dimension `M` is a parameter of the type because the
/// threshold depends on it; it is computed once, in the constructor.
/// Significance `α ∈ (0, 1)`; the paper uses 0.05 or 0.02.
///
/// ```
/// use kestrel_adaptive::OutlierCompression;
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
///
/// // C = 4, ν = 10: τ = 25 > c = 3.8415 (α = 0.05, m = 1).
/// let mut step = GainStep::new(Vector1::new(10.0), Matrix1::new(3.0), None, Matrix1::new(1.0))
///     .unwrap();
/// let mut compression = OutlierCompression::<f64, 1>::new(0.05).unwrap();
/// let mut report = Default::default();
/// compression.before_gain(&mut step, &mut report);
/// let c = compression.threshold();
/// assert!((report.factor - (c / 25.0).sqrt()).abs() < 1e-15);
/// assert!((step.mahalanobis().unwrap() - c).abs() < 1e-12);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutlierCompression<T, const M: usize> {
    threshold: T,
}

/// What [`OutlierCompression`] did at one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompressionReport<T> {
    /// The factor `Y(τ)` the innovation was multiplied by (exactly 1 when
    /// not compressed).
    pub factor: T,
    /// The test statistic `τ = νᵀ C⁻¹ ν`.
    pub statistic: T,
    /// Whether the innovation was compressed (`τ > c`).
    pub compressed: bool,
}

impl<T: Real> Default for CompressionReport<T> {
    fn default() -> Self {
        Self {
            factor: T::one(),
            statistic: T::zero(),
            compressed: false,
        }
    }
}

impl<T: Real, const M: usize> OutlierCompression<T, M> {
    /// Compression at significance `significance` (`c = χ²_{1−α}(M)`).
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"significance"` unless
    /// `0 < α < 1`; `"dof"` if `M = 0`.
    pub fn new(significance: T) -> Result<Self, FilterError> {
        Ok(Self {
            threshold: significance_threshold(significance, M)?,
        })
    }

    /// Compression at the published `α = 0.05` (Yuan, Yan, Pang and Zhang,
    /// *The Application of Improved Adaptive Kalman Filter to GPS/SINS*,
    /// J. Air Force Eng. Univ. 16(5), 2015; paper 000 in
    /// `crates/core/REFERENCES.md`).
    ///
    /// # Errors
    /// `"dof"` if `M = 0`.
    pub fn as_published() -> Result<Self, FilterError> {
        Self::new(lit(0.05))
    }

    /// Compression with the threshold `c` given directly (`c > 0`, finite).
    ///
    /// # Errors
    /// `"threshold"` unless `c` is finite and positive.
    pub fn with_threshold(c: T) -> Result<Self, FilterError> {
        if !(c.is_finite() && c > T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "threshold",
                valid: "finite and greater than 0",
            });
        }
        Ok(Self { threshold: c })
    }

    /// The threshold `c`.
    pub fn threshold(&self) -> T {
        self.threshold
    }
}

impl<T: Real, const M: usize> PriorAdapter<T> for OutlierCompression<T, M> {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for OutlierCompression<T, M> {
    type Report = CompressionReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        let Some(tau) = step.mahalanobis() else {
            return;
        };
        report.statistic = tau;
        if tau > self.threshold {
            let factor = (self.threshold / tau).sqrt();
            step.scale_innovation(factor);
            report.factor = factor;
            report.compressed = true;
        }
    }
}
