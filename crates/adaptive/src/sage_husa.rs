//! Simplified Sage-Husa estimation of the measurement noise covariance `R`
//! (paper 000, eq. 9).

use kestrel_core::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter};
use kestrel_core::linalg::FactoredCovariance;
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

/// Online estimate of the measurement noise covariance `R` from the post-fit
/// residuals (simplified Sage-Husa; `Q` is taken as known), paper 000, eq. 9:
///
/// ```text
/// R̂_k = (1 − d_k) R̂_{k−1} + d_k [ (I − H K) ν νᵀ (I − H K)ᵀ + H P_k Hᵀ ]
/// d_k = (1 − b) / (1 − b^{k+1})
/// ```
///
/// `(I − H K) ν` is the post-fit residual and `H P_k Hᵀ` the posterior
/// measurement covariance ([`Posterior::post_fit_residual`],
/// [`Posterior::posterior_covariance`]); with `C = H P⁻ Hᵀ + R` their
/// expected sum is exactly the `R` the gain used (`R C⁻¹ R + R − R C⁻¹ R`),
/// so the estimator is unbiased at a fixed point, and as a sum of positive
/// semi-definite terms it keeps `R̂` positive definite. `k = 1, 2, …` counts
/// the estimates; the weights make `R̂_k` the exponentially weighted mean
/// (factor `b` per epoch) of the epochs' samples with the initial `R̂_0`
/// counted as one sample.
///
/// Each update, [`before_gain`](NoiseAdapter::before_gain) replaces `R` by
/// `R̂` (the first time, `R̂_0` is the `R` the update arrives with unless
/// [`with_initial`](Self::with_initial) gave one), and
/// [`after_update`](NoiseAdapter::after_update) folds the epoch into `R̂` for
/// the next gain.
///
/// - Forgetting factor `b`: any value in `(0, 1]` is accepted; the paper
///   recommends `[0.95, 0.99]` (an effective memory of 20 to 100 epochs).
///   `b = 1` forgets nothing: `d_k` is the formula's limit `1 / (k + 1)`
///   and `R̂_k` the plain mean of `R̂_0` and the `k` samples.
///   With a short memory a single outlier dominates `R̂` and makes it
///   strongly anisotropic; in `f32` the covariance of such a filter can then
///   lose definiteness, so keep `f32` filters in the recommended range.
/// - Floor (optional): a lower bound on the diagonal of `R̂`, applied after
///   each estimate, so near-perfect measurements cannot drive `R̂` to zero.
/// - An estimate that is not positive definite to working precision (only
///   possible through rounding) is discarded and the previous `R̂` kept.
/// - Skip on fade (on by default): no estimate in an epoch in which an
///   earlier member of the adapter tuple faded the covariance, the
///   paper's rule "fading when diverging, Sage-Husa otherwise". See
///   [`ImprovedAdaptive`](crate::ImprovedAdaptive) for the composition that
///   also lets the earlier members test against `R̂`.
///
/// ```
/// use kestrel_adaptive::SageHusa;
/// use kestrel_core::Ekf;
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// use kestrel_models::{LinearMeasurement, LinearProcess};
///
/// let process = LinearProcess::new(Matrix1::new(1.0), Matrix1::new(0.0));
/// let sensor = LinearMeasurement::new(Matrix1::new(1.0), Matrix1::new(1.0));
/// let mut kf = Ekf::new(Vector1::new(0.0), Matrix1::new(1.0))
///     .unwrap()
///     .with_adapter(SageHusa::new(0.95).unwrap());
/// kf.predict(&process, 1.0).unwrap();
/// let report = kf.update(&sensor, &Vector1::new(2.0)).unwrap();
/// // C = 2, K = ½: post-fit residual 1, H P Hᵀ = ½; d₁ = 1/(1 + b).
/// let d: f64 = 1.0 / 1.95;
/// assert!((report.adapters.weight - d).abs() < 1e-12);
/// let r: f64 = kf.adapter().estimate()[0];
/// assert!((r - ((1.0 - d) * 1.0 + d * 1.5)).abs() < 1e-12);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SageHusa<T: Real, const M: usize> {
    forgetting: T,
    /// `b^{k+1}` for the next estimate `k`.
    power: T,
    /// `R̂` while it is the first update's `R`, which is not factored here.
    nominal: SMatrix<T, M, M>,
    /// `R̂` with the factor its check computed: from
    /// [`with_initial`](Self::with_initial) or the first estimate on.
    factored: Option<FactoredCovariance<T, M>>,
    initialized: bool,
    floor: SVector<T, M>,
    skip_when_faded: bool,
    /// Whether this epoch's estimate is skipped (set in `before_gain`).
    skip: bool,
    count: u32,
}

/// What [`SageHusa`] did at one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SageHusaReport<T> {
    /// The weight `d_k` of this epoch's sample (0 when no estimate was made).
    pub weight: T,
    /// Whether `R̂` was updated from this epoch.
    pub estimated: bool,
    /// Whether the estimate was skipped because an earlier member faded.
    pub skipped_for_fade: bool,
    /// Whether the new estimate was not positive definite and was discarded.
    pub discarded: bool,
    /// The trace of the `R̂` the gain of this update used.
    pub trace: T,
    /// The number of estimates made so far, `k`.
    pub count: u32,
}

impl<T: Real> Default for SageHusaReport<T> {
    fn default() -> Self {
        Self {
            weight: T::zero(),
            estimated: false,
            skipped_for_fade: false,
            discarded: false,
            trace: T::zero(),
            count: 0,
        }
    }
}

impl<T: Real, const M: usize> SageHusa<T, M> {
    /// An estimator with forgetting factor `b ∈ (0, 1]` (recommended
    /// `[0.95, 0.99]`), starting from the `R` of the first update, no floor,
    /// skipping epochs faded by an earlier member. `b = 1` forgets nothing:
    /// `d_k` is its limit `1 / (k + 1)`, every sample weighs the same.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"forgetting"` unless `0 < b ≤ 1`.
    pub fn new(b: T) -> Result<Self, FilterError> {
        if !(b > T::zero() && b <= T::one()) {
            return Err(FilterError::InvalidParameter {
                name: "forgetting",
                valid: "0 < b ≤ 1",
            });
        }
        Ok(Self::unchecked(b))
    }

    fn unchecked(b: T) -> Self {
        Self {
            forgetting: b,
            power: b * b,
            nominal: SMatrix::zeros(),
            factored: None,
            initialized: false,
            floor: SVector::zeros(),
            skip_when_faded: true,
            skip: false,
            count: 0,
        }
    }

    /// The published set-up (Yuan, Yan, Pang and Zhang, 2015; paper 000 in
    /// `crates/core/REFERENCES.md`): `b = 0.95`, the fast end of its range, so that
    /// `R̂` follows a change of the noise level within about 20 epochs.
    ///
    /// # Errors
    /// None for this `b`; the `Result` keeps one rule for every adapter's
    /// constructor.
    pub fn as_published() -> Result<Self, FilterError> {
        Self::new(lit(0.95))
    }

    /// Starts from `R̂_0 = r0` (lower triangle used) instead of the first
    /// update's `R`.
    ///
    /// # Errors
    /// `"initial"` unless `r0` is finite and positive definite.
    pub fn with_initial(mut self, r0: SMatrix<T, M, M>) -> Result<Self, FilterError> {
        let Ok(factored) = FactoredCovariance::new(r0) else {
            return Err(FilterError::InvalidParameter {
                name: "initial",
                valid: "a finite, symmetric, positive definite matrix",
            });
        };
        self.factored = Some(factored);
        self.initialized = true;
        Ok(self)
    }

    /// Keeps every diagonal element of `R̂` at or above `floor` (one value per
    /// measurement component, each finite and `≥ 0`).
    ///
    /// # Errors
    /// `"floor"` if a value is negative or not finite.
    pub fn with_floor(mut self, floor: SVector<T, M>) -> Result<Self, FilterError> {
        if !floor.iter().all(|f| f.is_finite() && *f >= T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "floor",
                valid: "finite and non-negative in every component",
            });
        }
        self.floor = floor;
        Ok(self)
    }

    /// Whether to skip the estimate in an epoch in which an earlier member
    /// of the adapter tuple faded the covariance (default `true`).
    pub fn with_skip_when_faded(mut self, skip: bool) -> Self {
        self.skip_when_faded = skip;
        self
    }

    /// The forgetting factor `b`.
    pub fn forgetting(&self) -> T {
        self.forgetting
    }

    /// The current estimate `R̂` (zero before the first update unless an
    /// initial value was given).
    pub fn estimate(&self) -> &SMatrix<T, M, M> {
        match &self.factored {
            Some(r) => r.matrix(),
            None => &self.nominal,
        }
    }

    /// The number of estimates made, `k`.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Puts `R̂` in place of the step's `R` (taking `R̂_0` from the step the
    /// first time). `R̂` goes with the factor its check computed, so the
    /// form does not factor it again.
    pub(crate) fn apply(&mut self, step: &mut GainStep<T, M>, report: &mut SageHusaReport<T>) {
        if self.initialized {
            match &self.factored {
                Some(r) => step.set_factored_noise(r),
                None => step.set_noise(self.nominal),
            }
        } else {
            self.nominal = *step.noise();
            self.initialized = true;
        }
        report.trace = self.estimate().trace();
        report.count = self.count;
    }

    /// Decides whether this epoch is estimated: not if the covariance has
    /// been faded so far at this update (and skipping is on).
    pub(crate) fn note_fade(&mut self, step: &GainStep<T, M>) {
        self.skip = self.skip_when_faded && step.fade_factor() != T::one();
    }

    /// The exponentially weighted update of `R̂` with this epoch's sample.
    fn estimate_from(&mut self, posterior: &Posterior<'_, T, M>, report: &mut SageHusaReport<T>) {
        let (e, posterior_covariance) = posterior.post_fit_residual_and_covariance();
        // (1 − b) / (1 − b^{k+1}), or its limit 1 / (k + 1) at b = 1 (the
        // count is k − 1 before this estimate).
        let d = if self.forgetting == T::one() {
            T::one() / (lit::<T>(f64::from(self.count)) + lit(2.0))
        } else {
            (T::one() - self.forgetting) / (T::one() - self.power)
        };
        // One pass: (1 − d) R̂ + d (H P Hᵀ + e eᵀ). e eᵀ is exactly
        // symmetric; so is the posterior covariance, and so is the sum.
        let previous = self.estimate();
        let mut next = SMatrix::from_fn(|i, j| {
            let sample = posterior_covariance[(i, j)] + e[i] * e[j];
            previous[(i, j)] * (T::one() - d) + sample * d
        });
        for i in 0..M {
            next[(i, i)] = next[(i, i)].max(self.floor[i]);
        }
        if let Ok(factored) = FactoredCovariance::new(next) {
            self.factored = Some(factored);
            self.power *= self.forgetting;
            self.count = self.count.saturating_add(1);
            report.weight = d;
            report.estimated = true;
            report.count = self.count;
        } else {
            report.discarded = true;
        }
    }
}

impl<T: Real, const M: usize> PriorAdapter<T> for SageHusa<T, M> {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for SageHusa<T, M> {
    type Report = SageHusaReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        self.apply(step, report);
        self.note_fade(step);
    }

    fn after_update(&mut self, posterior: &Posterior<'_, T, M>, report: &mut Self::Report) {
        if self.skip {
            report.skipped_for_fade = true;
        } else {
            self.estimate_from(posterior, report);
        }
    }
}
