//! χ² test with Huber-type inflation of `R` (the ICT-EREKF of paper 002).

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::real::{epsilon, lit, to_f64};
use kestrel_core::{FilterError, Real};

use crate::chi_square::significance_threshold;

/// How the per-component factors `αᵢ` inflate a measurement noise `R` that
/// is not diagonal. Both give `R̄ᵢᵢ = Rᵢᵢ / αᵢ` on a diagonal `R`.
///
/// ```
/// use kestrel_adaptive::{HuberInflation, InflationShape};
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let r = Matrix2::new(1.0, 0.5, 0.5, 1.0);
/// for shape in [InflationShape::Congruence, InflationShape::Diagonal] {
///     let mut huber = HuberInflation::<f64, 2>::as_published().unwrap().with_shape(shape);
///     let mut step = GainStep::new(Vector2::new(10.0, 0.0), Matrix2::identity(), None, r)
///         .unwrap();
///     let mut report = Default::default();
///     huber.before_gain(&mut step, &mut report);
///     let a = report.factors[0];
///     let off = match shape {
///         InflationShape::Congruence => 0.5 / a.sqrt(),
///         InflationShape::Diagonal => 0.5,
///     };
///     assert!((step.noise()[(0, 0)] - 1.0 / a).abs() < 1e-12);
///     assert!((step.noise()[(0, 1)] - off).abs() < 1e-12);
///     assert_eq!(step.noise()[(1, 1)], 1.0);
/// }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InflationShape {
    /// `R̄ = A^{-1/2} R A^{-1/2}` with `A = diag(α)`, i.e.
    /// `R̄ᵢⱼ = Rᵢⱼ / √(αᵢ αⱼ)`: every correlation coefficient is kept and the
    /// result is positive definite whenever `R` is.
    #[default]
    Congruence,
    /// Only the diagonal is divided, `R̄ᵢᵢ = Rᵢᵢ / αᵢ`, the off-diagonal
    /// elements are kept (adds a non-negative diagonal, so it stays positive
    /// definite; correlations shrink).
    Diagonal,
}

/// What [`HuberInflation`] did in one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HuberReport<T: Real, const M: usize> {
    /// The global statistic `T = νᵀ C⁻¹ ν` (0 if `C` was not positive
    /// definite, in which case nothing was done).
    pub statistic: T,
    /// The global threshold `χ²_{1−α}(M)`.
    pub threshold: T,
    /// Whether the global test failed (`statistic > threshold`).
    pub fault: bool,
    /// The component statistics `Tᵢ = νᵢ² / Cᵢᵢ`, computed only on a fault
    /// (zero otherwise).
    pub component_statistics: SVector<T, M>,
    /// The equivalent weights `αᵢ` (1 = untouched; `R̄ᵢᵢ = Rᵢᵢ / αᵢ`).
    pub factors: SVector<T, M>,
    /// How many components were inflated.
    pub inflated: usize,
}

impl<T: Real, const M: usize> Default for HuberReport<T, M> {
    fn default() -> Self {
        Self {
            statistic: T::zero(),
            threshold: T::zero(),
            fault: false,
            component_statistics: SVector::zeros(),
            factors: SVector::repeat(T::one()),
            inflated: 0,
        }
    }
}

/// Innovation χ² test with per-component Huber inflation of `R`: the
/// extended robust Kalman filter with innovation χ² test (ICT-EREKF) of
/// paper 002, eq. 9–15.
///
/// 1. Global test (eq. 9–10): `T = νᵀ C⁻¹ ν`, `C = H P⁻ Hᵀ + R`; if
///    `T ≤ χ²_{1−α}(M)` the update is left exactly as it is (R untouched,
///    bit for bit).
/// 2. Otherwise, per component (eq. 11–13): `Tᵢ = νᵢ² / Cᵢᵢ`, compared
///    with `T' = χ²_{1−α}(1)`; the equivalent weight is
///    `αᵢ = 1` if `Tᵢ ≤ T'`, else `αᵢ = T' / Tᵢ` (Huber's weight on the
///    normalised residual).
/// 3. Equivalent noise (eq. 14–15): `R̄ᵢᵢ = Rᵢᵢ / αᵢ`; for a full `R`, see
///    [`InflationShape`] (default `R̄ = A^{-1/2} R A^{-1/2}`). `R̄` is used
///    in the gain.
///
/// `α` is the significance level, in `[0.01, 0.15]` (the paper uses 0.05).
/// The factors are floored at the machine epsilon of `T`, so an extreme
/// outlier inflates `R` by at most `1/ε` instead of producing infinity.
///
/// **Gross errors.** Because of that floor, a residual beyond about
/// `√(χ²/ε)` standard deviations (≈ 10⁸ σ in `f64`, 6·10³ σ in `f32`) is
/// no longer down-weighted any further, and the correction grows with it: a
/// 10³⁰ m range moves a state by about 10¹⁴ m. Huber inflation alone is for
/// moderate outliers (multipath); for data that can hold gross errors, use
/// it behind a χ² gate, [`GatedHuber`](crate::GatedHuber) /
/// [`gated_huber`](crate::gated_huber).
/// The test uses the innovation and covariance left by any adapter before
/// this one in a tuple.
///
/// ```
/// use kestrel_adaptive::HuberInflation;
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let mut huber = HuberInflation::<f64, 2>::as_published().unwrap();
/// // H P⁻ Hᵀ = I, R = I: C = 2 I; ν = (10, 0) gives T = 50 > χ²₀.₉₅(2).
/// let mut step = GainStep::new(
///     Vector2::new(10.0, 0.0), Matrix2::identity(), None, Matrix2::identity(),
/// ).unwrap();
/// let mut report = Default::default();
/// huber.before_gain(&mut step, &mut report);
/// assert!(report.fault);
/// // T₁ = 100 / 2 = 50, α₁ = 3.8415 / 50; component 2 untouched.
/// let t1 = kestrel_adaptive::chi_square_quantile(0.95, 1).unwrap();
/// assert!((report.factors[0] - t1 / 50.0).abs() < 1e-15);
/// assert_eq!(report.factors[1], 1.0);
/// assert!((step.noise()[(0, 0)] - 50.0 / t1).abs() < 1e-12);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HuberInflation<T: Real, const M: usize> {
    global_threshold: T,
    component_threshold: T,
    shape: InflationShape,
}

impl<T: Real, const M: usize> HuberInflation<T, M> {
    /// Smallest accepted significance level.
    pub const MIN_SIGNIFICANCE: f64 = 0.01;
    /// Largest accepted significance level.
    pub const MAX_SIGNIFICANCE: f64 = 0.15;
    /// The significance level of paper 002.
    pub const PAPER_SIGNIFICANCE: f64 = 0.05;

    /// The test at significance `significance ∈ [0.01, 0.15]`, with the
    /// default [`InflationShape::Congruence`].
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"significance"` outside
    /// `[0.01, 0.15]` (the error states the range), or `"dof"` for `M = 0`.
    pub fn new(significance: T) -> Result<Self, FilterError> {
        let range = Self::MIN_SIGNIFICANCE..=Self::MAX_SIGNIFICANCE;
        if !range.contains(&to_f64(significance)) {
            return Err(FilterError::InvalidParameter {
                name: "significance",
                valid: "0.01 ≤ significance ≤ 0.15 (the range the test is built for)",
            });
        }
        Ok(Self {
            global_threshold: significance_threshold(significance, M)?,
            component_threshold: significance_threshold(significance, 1)?,
            shape: InflationShape::default(),
        })
    }

    /// The published configuration: significance 0.05 (Miao, Zhou, Tian and
    /// Cui, *Extended Robust Kalman Filter Based on Innovation Chi-Square
    /// Test Algorithm and Its Application*, 2014; paper 002 in
    /// `crates/core/REFERENCES.md`).
    ///
    /// # Errors
    /// `InvalidParameter { name: "dof", valid: "at least 1 (the measurement dimension M)" }` for `M = 0`.
    pub fn as_published() -> Result<Self, FilterError> {
        Self::new(lit(Self::PAPER_SIGNIFICANCE))
    }

    /// The same test inflating a full `R` with `shape`.
    pub fn with_shape(mut self, shape: InflationShape) -> Self {
        self.shape = shape;
        self
    }

    /// The global threshold `χ²_{1−α}(M)`.
    pub fn global_threshold(&self) -> T {
        self.global_threshold
    }

    /// The component threshold `T' = χ²_{1−α}(1)`.
    pub fn component_threshold(&self) -> T {
        self.component_threshold
    }

    /// The inflation shape in use.
    pub fn shape(&self) -> InflationShape {
        self.shape
    }

    /// `R̄` from `R` and the factors `α` (all in `(0, 1]`).
    fn inflate(&self, r: &SMatrix<T, M, M>, alpha: &SVector<T, M>) -> SMatrix<T, M, M> {
        let mut out = *r;
        for j in 0..M {
            for i in 0..M {
                out[(i, j)] = match self.shape {
                    InflationShape::Congruence => r[(i, j)] / (alpha[i] * alpha[j]).sqrt(),
                    InflationShape::Diagonal if i == j => r[(i, i)] / alpha[i],
                    InflationShape::Diagonal => r[(i, j)],
                };
            }
        }
        out
    }
}

impl<T: Real, const M: usize> PriorAdapter<T> for HuberInflation<T, M> {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for HuberInflation<T, M> {
    type Report = HuberReport<T, M>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        report.threshold = self.global_threshold;
        let Some(statistic) = step.mahalanobis() else {
            return;
        };
        report.statistic = statistic;
        report.fault = statistic > self.global_threshold;
        if !report.fault {
            return;
        }
        let c = step.innovation_covariance();
        let nu = step.innovation();
        let mut alpha = SVector::<T, M>::repeat(T::one());
        for i in 0..M {
            // C is positive definite here (mahalanobis succeeded): Cᵢᵢ > 0.
            let ti = nu[i] * nu[i] / c[(i, i)];
            report.component_statistics[i] = ti;
            if ti > self.component_threshold {
                alpha[i] = (self.component_threshold / ti).max(epsilon::<T>());
                report.inflated += 1;
            }
        }
        report.factors = alpha;
        if report.inflated > 0 {
            let r = self.inflate(step.noise(), &alpha);
            step.set_noise(r);
        }
    }
}
