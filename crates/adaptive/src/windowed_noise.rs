//! Measurement noise estimated from a sliding window of innovations (paper
//! 003, eq. 7–8).

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::real::{epsilon, lit};
use kestrel_core::{FilterError, Real};

use crate::spd::project_spd;

/// What [`WindowedNoise`] did in one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowedNoiseReport<T: Real> {
    /// Innovations in the window after this epoch.
    pub samples: usize,
    /// Whether the estimate replaced `R` (the window was full).
    pub estimated: bool,
    /// The smallest eigenvalue of `Ĉ − H P⁻ Hᵀ` before projection (0 when
    /// not estimated).
    pub min_eigenvalue: T,
    /// The eigenvalue floor applied (0 when not estimated).
    pub floor: T,
    /// How many eigenvalues were raised to the floor.
    pub raised: usize,
}

impl<T: Real> Default for WindowedNoiseReport<T> {
    fn default() -> Self {
        Self {
            samples: 0,
            estimated: false,
            min_eigenvalue: T::zero(),
            floor: T::zero(),
            raised: 0,
        }
    }
}

/// Innovation-based estimate of `R` over the last `W` innovations (paper 003,
/// eq. 7–8):
///
/// `Ĉ = (1/W) Σ_{j=k−W+1..k} νⱼ νⱼᵀ`, `Rₖ = Ĉ − H P⁻ Hᵀ`,
///
/// with `νⱼ` the innovations as this adapter receives them (so after a
/// [`FuzzyGain`](crate::FuzzyGain) placed before it in a tuple: the
/// corrected innovations) and `H P⁻ Hᵀ` this epoch's predicted measurement
/// covariance. The difference can be indefinite, so `Rₖ` is projected onto
/// the positive definite matrices by raising its eigenvalues to at least
/// `f = max(min_variance, 128 M ε tr(H P⁻ Hᵀ))` ([`project_spd`], which
/// also keeps `f ≥ 16 M ε λ_max`); the relative term only matters in
/// `f32`, where a smaller variance is below the rounding of the update.
/// Until `W` innovations have been seen the model's `R` is used unchanged.
///
/// The current innovation is pushed before the estimate (the window ends at
/// `k`, as in eq. 7); innovations of measurements an earlier adapter
/// rejected are not pushed. Put gates before this adapter: a rejection by a
/// later one cannot take the innovation back out of the window.
///
/// ```
/// use kestrel_adaptive::WindowedNoise;
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// let mut est = WindowedNoise::<f64, 1, 2>::new(1e-6).unwrap();
/// let mut report = Default::default();
/// for nu in [3.0, -1.0] {
///     let mut step = GainStep::new(Vector1::new(nu), Matrix1::new(1.0), None, Matrix1::new(9.0))
///         .unwrap();
///     est.before_gain(&mut step, &mut report);
///     if nu == -1.0 {
///         // Ĉ = (9 + 1) / 2 = 5, R = 5 − 1.
///         assert!((step.noise()[0] - 4.0).abs() < 1e-14);
///     }
/// }
/// assert!(report.estimated);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowedNoise<T: Real, const M: usize, const W: usize> {
    window: [SVector<T, M>; W],
    next: usize,
    len: usize,
    min_variance: T,
}

impl<T: Real, const M: usize, const W: usize> WindowedNoise<T, M, W> {
    /// The estimator with eigenvalue floor `min_variance > 0` (in the units
    /// of `R`; choose it well below the expected noise variance).
    ///
    /// # Errors
    /// `InvalidParameter { name: "min_variance", valid: "finite and greater than 0" }` unless it is finite and
    /// positive, `"window"` for `W = 0`.
    pub fn new(min_variance: T) -> Result<Self, FilterError> {
        if W == 0 {
            return Err(FilterError::InvalidParameter {
                name: "window",
                valid: "at least 1 (the window length W)",
            });
        }
        if !(min_variance.is_finite() && min_variance > T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "min_variance",
                valid: "finite and greater than 0",
            });
        }
        Ok(Self {
            window: [SVector::zeros(); W],
            next: 0,
            len: 0,
            min_variance,
        })
    }

    /// The eigenvalue floor.
    pub fn min_variance(&self) -> T {
        self.min_variance
    }

    /// Innovations currently in the window.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no innovation has been seen yet.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Empties the window.
    pub fn reset(&mut self) {
        self.next = 0;
        self.len = 0;
    }

    /// Adds an innovation, dropping the oldest once `W` are held.
    pub fn push(&mut self, innovation: &SVector<T, M>) {
        self.window[self.next] = *innovation;
        self.next = (self.next + 1) % W;
        self.len = (self.len + 1).min(W);
    }

    /// `Ĉ = (1/n) Σ νⱼ νⱼᵀ` over the innovations held (zero when empty).
    pub fn sample_covariance(&self) -> SMatrix<T, M, M> {
        let mut c = SMatrix::<T, M, M>::zeros();
        if self.len == 0 {
            return c;
        }
        for nu in &self.window[..self.len] {
            // Lower triangle only; mirrored below.
            for j in 0..M {
                for i in j..M {
                    c[(i, j)] += nu[i] * nu[j];
                }
            }
        }
        let inv = T::one() / lit::<T>(self.len as f64);
        for j in 0..M {
            for i in j..M {
                c[(i, j)] *= inv;
                c[(j, i)] = c[(i, j)];
            }
        }
        c
    }
}

impl<T: Real, const M: usize, const W: usize> PriorAdapter<T> for WindowedNoise<T, M, W> {}

impl<T: Real, const M: usize, const W: usize> NoiseAdapter<T, M> for WindowedNoise<T, M, W> {
    type Report = WindowedNoiseReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        if !step.is_rejected() {
            self.push(step.innovation());
        }
        report.samples = self.len;
        if self.len < W || step.is_rejected() {
            return;
        }
        let predicted = step.predicted_covariance();
        let raw = self.sample_covariance() - predicted;
        // A variance below the rounding of H P⁻ Hᵀ cannot register in
        // C = H P⁻ Hᵀ + R, and the posterior variance it implies is below the
        // rounding of the covariance update (the square-root form's downdate
        // then fails): keep R above it.
        let resolution = lit::<T>(128.0 * M as f64) * epsilon::<T>() * predicted.trace();
        if let Some(p) = project_spd(&raw, self.min_variance.max(resolution)) {
            report.estimated = true;
            report.min_eigenvalue = p.min_eigenvalue;
            report.floor = p.floor;
            report.raised = p.raised;
            step.set_noise(p.matrix);
        }
    }
}
