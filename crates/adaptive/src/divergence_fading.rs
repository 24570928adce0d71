//! Fading memory triggered by a divergence test on the innovation (paper 000,
//! eq. 10–12).

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

use crate::chi_square_quantile;

/// Fading memory with a divergence test, paper 000, eq. 10–12.
///
/// The filter is judged divergent when the innovation is too large for its
/// covariance `C = H P⁻ Hᵀ + R` (eq. 11, with reserve coefficient `γ ≥ 1`;
/// `γ = 1` is the strictest test):
///
/// ```text
/// νᵀν ≤ γ · tr(C)
/// ```
///
/// When the test fails, the propagated covariance is faded,
/// `P⁻ = Φ (λ P) Φᵀ + Q` (eq. 10), with the `λ` that makes `tr(C) = νᵀν`
/// (eq. 12), clamped to `[1, λ_max]`:
///
/// ```text
/// λ = (νᵀν − tr(H Q Hᵀ + R)) / tr(H Φ P Φᵀ Hᵀ)
/// ```
///
/// (With `γ ≥ 1` a failed test already implies `λ > 1`.) `R` is the noise in
/// use when the adapter runs, so after an `R` estimator (see
/// [`ImprovedAdaptive`](crate::ImprovedAdaptive)) it is the estimate. If an
/// earlier member has already faded, `tr(H Φ P Φᵀ Hᵀ)` includes that fade
/// and `λ` is the factor on top of it.
///
/// **Consistent model.** `νᵀν ≤ λ_max(C) · νᵀC⁻¹ν ≤ tr(C) · νᵀC⁻¹ν`, so the
/// test can only fail when the NIS exceeds `γ`: with
/// `γ = χ²_{1−α}(m)` ([`with_false_alarm`](Self::with_false_alarm)) a
/// consistent filter fades in at most a fraction `α` of its updates. With
/// `γ = 1`, a consistent 1-D filter fades whenever `ν² > C`, i.e. in 32 % of
/// its updates.
///
/// Parameters: `γ ∈ [1, ∞)`, `λ_max ∈ [1, ∞]` (infinity: no upper clamp).
///
/// ```
/// use kestrel_adaptive::DivergenceFading;
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
///
/// // H Φ P Φᵀ Hᵀ = 3, H Q Hᵀ = 1, R = 5: C = 9. ν = 6: νᵀν = 36 > 2 · 9.
/// let mut step = GainStep::new(
///     Vector1::new(6.0),
///     Matrix1::new(4.0),
///     Some((Matrix1::new(3.0), Matrix1::new(1.0))),
///     Matrix1::new(5.0),
/// ).unwrap();
/// let mut fading = DivergenceFading::new(2.0, 100.0).unwrap();
/// let mut report = Default::default();
/// fading.before_gain(&mut step, &mut report);
/// // λ = (36 − 1 − 5) / 3 = 10, and then tr C = 30 + 1 + 5 = νᵀν.
/// assert_eq!(report.fade, 10.0);
/// assert_eq!(step.innovation_covariance()[0], 36.0);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivergenceFading<T> {
    reserve: T,
    max_fade: T,
}

/// What [`DivergenceFading`] did at one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivergenceReport<T> {
    /// The fade `λ` applied (1 when the test passed).
    pub fade: T,
    /// Whether the divergence test failed.
    pub diverged: bool,
    /// The test statistic `νᵀν`.
    pub statistic: T,
    /// The bound `γ · tr(C)` it was compared with.
    pub bound: T,
}

impl<T: Real> Default for DivergenceReport<T> {
    fn default() -> Self {
        Self {
            fade: T::one(),
            diverged: false,
            statistic: T::zero(),
            bound: T::zero(),
        }
    }
}

impl<T: Real> DivergenceFading<T> {
    /// A divergence test with reserve coefficient `reserve` (`γ ≥ 1`) and
    /// fades clamped to `max_fade` (`λ_max ≥ 1`, may be infinite).
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"reserve"` unless `γ` is finite
    /// and `≥ 1`; `"max_fade"` unless `λ_max ≥ 1` (NaN refused).
    pub fn new(reserve: T, max_fade: T) -> Result<Self, FilterError> {
        if !(reserve.is_finite() && reserve >= T::one()) {
            return Err(FilterError::InvalidParameter {
                name: "reserve",
                valid: "finite and at least 1",
            });
        }
        // Also refuses NaN.
        let valid = max_fade >= T::one();
        if !valid {
            return Err(FilterError::InvalidParameter {
                name: "max_fade",
                valid: "at least 1",
            });
        }
        Ok(Self { reserve, max_fade })
    }

    /// The test with `γ = χ²_{1−α}(m)`, so that a consistent filter with
    /// `m`-dimensional measurements fades in at most a fraction `α` of its
    /// updates (see the type's documentation).
    ///
    /// # Errors
    /// `"probability"` unless `0 < α < 1`, `"dof"` if `m = 0`, `"max_fade"`
    /// as in [`new`](Self::new).
    pub fn with_false_alarm(alpha: f64, m: usize, max_fade: T) -> Result<Self, FilterError> {
        let gamma = chi_square_quantile(1.0 - alpha, m)?;
        Self::new(lit::<T>(gamma.max(1.0)), max_fade)
    }

    /// The reserve coefficient `γ`.
    pub fn reserve(&self) -> T {
        self.reserve
    }

    /// The upper clamp `λ_max`.
    pub fn max_fade(&self) -> T {
        self.max_fade
    }
}

impl<T: Real> PriorAdapter<T> for DivergenceFading<T> {
    const NEEDS_SPLIT: bool = true;
}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for DivergenceFading<T> {
    type Report = DivergenceReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        let statistic = step.innovation().norm_squared();
        let bound = self.reserve * step.innovation_covariance().trace();
        report.statistic = statistic;
        report.bound = bound;
        // Passes on NaN too (the forms refuse NaN before adapters run).
        let diverged = statistic > bound;
        if !diverged {
            return;
        }
        report.diverged = true;
        let (propagated, process) = match step.split() {
            Some((p, q)) => (p.trace() * step.fade_factor(), q.trace()),
            None => (step.predicted_covariance().trace(), T::zero()),
        };
        let fadeable = propagated > T::zero();
        if !fadeable {
            // Nothing to fade: the prior carries no propagated uncertainty.
            return;
        }
        let lambda = (statistic - process - step.noise().trace()) / propagated;
        // Written so that a NaN ratio gives 1, not λ_max.
        let lambda = if lambda > T::one() { lambda } else { T::one() };
        let lambda = lambda.min(self.max_fade);
        step.fade(lambda);
        report.fade = lambda;
    }
}
