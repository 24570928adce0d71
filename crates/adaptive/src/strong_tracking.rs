//! The suboptimal fading factor of the strong tracking filter (paper 004).

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

/// Strong-tracking fading, paper 004: at every update the propagated
/// covariance is faded, `P⁻ = λ_k Φ P Φᵀ + Q`, by the suboptimal fading
/// factor
///
/// ```text
/// λ_k = max{1, tr(N_k) / tr(M_k)}
/// N_k = V_k − H Q Hᵀ − β R_k,   M_k = H Φ P Φᵀ Hᵀ
/// V_1 = ν₁ν₁ᵀ,   V_k = (ρ V_{k−1} + ν_k ν_kᵀ) / (1 + ρ)
/// ```
///
/// with forgetting factor `ρ` (≈ 0.95) and softening coefficient `β ≥ 1`,
/// optionally clamped to `λ_max`. Only traces enter `λ`, so the adapter keeps
/// `tr(V_k)` (the same recursion on `νᵀν`) instead of the matrix.
///
/// `V_k` estimates `E[ννᵀ] = M_k + H Q Hᵀ + R`, so with `β = 1` a consistent
/// filter has `tr N_k ≈ tr M_k` and fades in about half of its updates; `β`
/// is the margin that keeps `λ = 1` on a consistent model: `λ > 1` requires
/// `tr V_k > tr M_k + tr(H Q Hᵀ) + β tr R`.
///
/// Parameters: `ρ ∈ [0, 1]`, `β ∈ [1, ∞)`, `λ_max ∈ [1, ∞]`.
///
/// ```
/// use kestrel_adaptive::StrongTracking;
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
///
/// // M = 2, H Q Hᵀ = 1, R = 1, ν = 4: V₁ = 16, N = 16 − 1 − 2 · 1 = 13.
/// let mut step = GainStep::new(
///     Vector1::new(4.0),
///     Matrix1::new(3.0),
///     Some((Matrix1::new(2.0), Matrix1::new(1.0))),
///     Matrix1::new(1.0),
/// ).unwrap();
/// let mut st = StrongTracking::new(0.95, 2.0).unwrap();
/// let mut report = Default::default();
/// st.before_gain(&mut step, &mut report);
/// assert_eq!(report.fade, 6.5);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrongTracking<T> {
    rho: T,
    softening: T,
    max_fade: T,
    /// `tr V_{k−1}`.
    v_trace: T,
    started: bool,
}

/// What [`StrongTracking`] did at one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrongTrackingReport<T> {
    /// The fade `λ_k` applied (1 when none).
    pub fade: T,
    /// `tr V_k`.
    pub v_trace: T,
    /// `tr N_k`.
    pub n_trace: T,
    /// `tr M_k`.
    pub m_trace: T,
}

impl<T: Real> Default for StrongTrackingReport<T> {
    fn default() -> Self {
        Self {
            fade: T::one(),
            v_trace: T::zero(),
            n_trace: T::zero(),
            m_trace: T::zero(),
        }
    }
}

impl<T: Real> StrongTracking<T> {
    /// Strong tracking with forgetting factor `rho` (`ρ ∈ [0, 1]`) and
    /// softening coefficient `softening` (`β ≥ 1`), no upper clamp.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"rho"` unless `0 ≤ ρ ≤ 1`,
    /// `"softening"` unless `β` is finite and `≥ 1`.
    pub fn new(rho: T, softening: T) -> Result<Self, FilterError> {
        if !(rho >= T::zero() && rho <= T::one()) {
            return Err(FilterError::InvalidParameter {
                name: "rho",
                valid: "0 ≤ ρ ≤ 1",
            });
        }
        if !(softening.is_finite() && softening >= T::one()) {
            return Err(FilterError::InvalidParameter {
                name: "softening",
                valid: "finite and at least 1",
            });
        }
        Ok(Self {
            rho,
            softening,
            max_fade: lit(f64::INFINITY),
            v_trace: T::zero(),
            started: false,
        })
    }

    /// The same adapter with fades clamped to `max_fade` (`λ_max ≥ 1`).
    ///
    /// # Errors
    /// `"max_fade"` unless `λ_max ≥ 1` (NaN refused).
    pub fn with_max_fade(mut self, max_fade: T) -> Result<Self, FilterError> {
        // Also refuses NaN.
        let valid = max_fade >= T::one();
        if !valid {
            return Err(FilterError::InvalidParameter {
                name: "max_fade",
                valid: "at least 1",
            });
        }
        self.max_fade = max_fade;
        Ok(self)
    }

    /// The forgetting factor `ρ`.
    pub fn rho(&self) -> T {
        self.rho
    }

    /// The softening coefficient `β`.
    pub fn softening(&self) -> T {
        self.softening
    }
}

impl<T: Real> PriorAdapter<T> for StrongTracking<T> {
    const NEEDS_SPLIT: bool = true;
}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for StrongTracking<T> {
    type Report = StrongTrackingReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        let latest = step.innovation().norm_squared();
        let v = if self.started {
            (self.rho * self.v_trace + latest) / (T::one() + self.rho)
        } else {
            latest
        };
        self.v_trace = v;
        self.started = true;
        let (propagated, process) = match step.split() {
            Some((p, q)) => (p.trace() * step.fade_factor(), q.trace()),
            None => (step.predicted_covariance().trace(), T::zero()),
        };
        let n = v - process - self.softening * step.noise().trace();
        report.v_trace = v;
        report.n_trace = n;
        report.m_trace = propagated;
        let fadeable = propagated > T::zero();
        if !fadeable {
            return;
        }
        let ratio = n / propagated;
        if ratio > T::one() {
            let lambda = ratio.min(self.max_fade);
            step.fade(lambda);
            report.fade = lambda;
        }
    }
}
