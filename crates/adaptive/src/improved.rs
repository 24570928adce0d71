//! The improved adaptive filter of paper 000 and its "Sage-Husa + fading"
//! baseline, as compositions of the crate's adapters.

use kestrel_core::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

use crate::{DivergenceFading, OutlierCompression, SageHusa, SageHusaReport};

/// A [`SageHusa`] estimator around other adapters (`tests`): the estimate
/// `R̂` is put in place first, so the other adapters test and fade against
/// it, and `R̂` is updated only in epochs the other adapters did not fade.
///
/// Per update:
/// 1. `R ← R̂` (the Sage-Husa estimate so far);
/// 2. the `tests` adapters run (compression, divergence test and fading);
/// 3. the gain is applied with the innovation and covariance they left;
/// 4. unless they faded (and [`SageHusa::with_skip_when_faded`] is on, the
///    default), `R̂` is updated from the post-fit residual of the innovation
///    used.
///
/// A plain tuple `(tests…, SageHusa)` cannot do step 1: its earlier members
/// would see the model's `R`, not `R̂`.
///
/// See [`ImprovedAdaptive`] and [`SageHusaFading`]; any adapter can take
/// their place, here strong tracking:
///
/// ```
/// use kestrel_adaptive::{SageHusa, SageHusaComposition, StrongTracking};
/// use kestrel_core::Ekf;
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// use kestrel_models::{LinearMeasurement, LinearProcess};
///
/// let adapter = SageHusaComposition::new(
///     StrongTracking::new(0.95, 3.0).unwrap(),
///     SageHusa::new(0.97).unwrap(),
/// );
/// let process = LinearProcess::new(Matrix1::new(1.0), Matrix1::new(0.01));
/// let sensor = LinearMeasurement::new(Matrix1::new(1.0), Matrix1::new(1.0));
/// let mut kf = Ekf::new(Vector1::new(0.0), Matrix1::new(1.0)).unwrap().with_adapter(adapter);
/// kf.predict(&process, 1.0).unwrap();
/// // A large innovation: strong tracking fades, so R̂ is left alone.
/// let report = kf.update(&sensor, &Vector1::new(20.0)).unwrap();
/// assert!(report.adapters.tests.fade > 1.0);
/// assert!(report.adapters.sage_husa.skipped_for_fade);
/// assert_eq!(kf.adapter().sage_husa.estimate()[0], 1.0);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SageHusaComposition<A, T: Real, const M: usize> {
    /// The adapters run between putting `R̂` in place and the gain.
    pub tests: A,
    /// The `R` estimator.
    pub sage_husa: SageHusa<T, M>,
}

/// What a [`SageHusaComposition`] did at one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompositionReport<R, T> {
    /// The reports of the `tests` adapters.
    pub tests: R,
    /// The report of the `R` estimator.
    pub sage_husa: SageHusaReport<T>,
}

impl<R: Default, T: Real> Default for CompositionReport<R, T> {
    fn default() -> Self {
        Self {
            tests: R::default(),
            sage_husa: SageHusaReport::default(),
        }
    }
}

/// The improved adaptive filter of paper 000 (section 2, figure 1): per
/// update, `R ← R̂`; χ² outlier compression of the innovation (eq. 13–14);
/// the divergence test on the compressed innovation and, if it fails,
/// fading (eq. 10–12); the gain; and, in epochs without fading, the
/// Sage-Husa update of `R̂` (eq. 9) from the compressed innovation.
///
/// ```
/// use kestrel_adaptive::ImprovedAdaptive;
/// use kestrel_core::Ekf;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// use kestrel_models::{LinearMeasurement, LinearProcess};
///
/// let process = LinearProcess::new(Matrix2::identity(), Matrix2::identity() * 0.01);
/// let sensor = LinearMeasurement::new(Matrix2::identity(), Matrix2::identity());
/// let mut kf = Ekf::new(Vector2::zeros(), Matrix2::identity())
///     .unwrap()
///     .with_adapter(ImprovedAdaptive::<f64, 2>::as_published().unwrap());
/// kf.predict(&process, 1.0).unwrap();
/// // An outlier is compressed; R̂ learns only in epochs without fading.
/// let report = kf.update(&sensor, &Vector2::new(50.0, 0.0)).unwrap();
/// let (compression, fading) = report.adapters.tests;
/// assert!(compression.compressed && compression.factor < 0.1);
/// assert_eq!(report.adapters.sage_husa.estimated, !fading.diverged);
/// ```
pub type ImprovedAdaptive<T, const M: usize> =
    SageHusaComposition<(OutlierCompression<T, M>, DivergenceFading<T>), T, M>;

/// The "Sage-Husa + fading" filter paper 000 compares against (its
/// reference 9): [`ImprovedAdaptive`] without outlier compression.
///
/// ```
/// use kestrel_adaptive::SageHusaFading;
/// let baseline = SageHusaFading::<f64, 6>::as_published().unwrap();
/// assert_eq!(baseline.tests.reserve(), 3.0);
/// assert_eq!(baseline.sage_husa.forgetting(), 0.95);
/// ```
pub type SageHusaFading<T, const M: usize> = SageHusaComposition<DivergenceFading<T>, T, M>;

impl<A, T: Real, const M: usize> SageHusaComposition<A, T, M> {
    /// `sage_husa` estimating `R̂` around `tests`.
    pub fn new(tests: A, sage_husa: SageHusa<T, M>) -> Self {
        Self { tests, sage_husa }
    }
}

impl<T: Real, const M: usize> ImprovedAdaptive<T, M> {
    /// The improved adaptive filter with forgetting factor `b`, significance
    /// `alpha` of the outlier test, reserve coefficient `reserve` (`γ`) and
    /// fade clamp `max_fade` (`λ_max`), each in the range its adapter
    /// documents.
    ///
    /// # Errors
    /// The first invalid parameter, as reported by [`SageHusa::new`],
    /// [`OutlierCompression::new`] or [`DivergenceFading::new`].
    pub fn with_params(b: T, alpha: T, reserve: T, max_fade: T) -> Result<Self, FilterError> {
        Ok(Self::new(
            (
                OutlierCompression::new(alpha)?,
                DivergenceFading::new(reserve, max_fade)?,
            ),
            SageHusa::new(b)?,
        ))
    }

    /// The published parameters `b = 0.95`, `α = 0.05` (Yuan, Yan, Pang and
    /// Zhang, *The Application of Improved Adaptive Kalman Filter to
    /// GPS/SINS*, J. Air Force Eng. Univ. 16(5), 2015; paper 000 in
    /// `crates/core/REFERENCES.md`) and, where the paper leaves the choice
    /// open, `γ = 3` and `λ_max = 100`.
    ///
    /// `γ` must stay below the compression threshold `c = χ²_{0.95}(M)`: a
    /// compressed innovation has `νᵀν ≤ c λ_max(C) ≤ c tr C`, so with
    /// `γ ≥ c` the divergence test could never fail after compression. It
    /// must not be close to 1 either: a consistent filter then fails the test
    /// in a large share of its epochs (37 % at `γ = 1` in two dimensions),
    /// and as faded epochs are not used for `R̂`, `R̂` drifts low and the
    /// fading feeds itself. With `γ = 3` a consistent filter with an
    /// isotropic `C` fades in `P(χ²(M) > 3M)` of its epochs (5 % for
    /// `M = 2`, 0.6 % for the paper's `M = 6`). A `C` dominated by a few
    /// components fades more often: in the GPS/SINS set-up of paper 000,
    /// where three position variances carry almost all of `tr C`, the rate
    /// is about 3 %.
    ///
    /// `λ_max = 100` follows the paper. On a navigation error state, where
    /// fading multiplies the variance of the unobservable directions (e.g.
    /// constant versus Markov gyro drift) by `λ` at every fade, that lets
    /// the covariance run away within seconds; the navigation scenario of
    /// paper 000 therefore uses `λ_max = 1.5` (see `kestrel-nav`'s
    /// `scenario_000`).
    ///
    /// # Errors
    /// `"dof"` if `M = 0`.
    pub fn as_published() -> Result<Self, FilterError> {
        Ok(Self::new(
            (
                OutlierCompression::as_published()?,
                DivergenceFading::new(lit(3.0), lit(100.0))?,
            ),
            SageHusa::as_published()?,
        ))
    }
}

impl<T: Real, const M: usize> SageHusaFading<T, M> {
    /// Sage-Husa with forgetting factor `b` and divergence-tested fading with
    /// reserve coefficient `reserve` and clamp `max_fade`.
    ///
    /// # Errors
    /// As [`SageHusa::new`] and [`DivergenceFading::new`].
    pub fn with_params(b: T, reserve: T, max_fade: T) -> Result<Self, FilterError> {
        Ok(Self::new(
            DivergenceFading::new(reserve, max_fade)?,
            SageHusa::new(b)?,
        ))
    }

    /// The baseline with the parameters of [`ImprovedAdaptive::as_published`]
    /// (`b = 0.95`, `γ = 3`, `λ_max = 100`).
    ///
    /// # Errors
    /// Never for these constants; the `Result` matches the other
    /// constructors.
    pub fn as_published() -> Result<Self, FilterError> {
        Ok(Self::new(
            DivergenceFading::new(lit(3.0), lit(100.0))?,
            SageHusa::as_published()?,
        ))
    }
}

impl<A: PriorAdapter<T>, T: Real, const M: usize> PriorAdapter<T> for SageHusaComposition<A, T, M> {
    const NEEDS_SPLIT: bool = A::NEEDS_SPLIT;

    #[inline(always)]
    fn after_predict(&mut self, prior: &mut PriorStep<T>) {
        self.tests.after_predict(prior);
    }
}

impl<A: NoiseAdapter<T, M>, T: Real, const M: usize> NoiseAdapter<T, M>
    for SageHusaComposition<A, T, M>
{
    type Report = CompositionReport<A::Report, T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        self.sage_husa.apply(step, &mut report.sage_husa);
        self.tests.before_gain(step, &mut report.tests);
        self.sage_husa.note_fade(step);
    }

    fn after_update(&mut self, posterior: &Posterior<'_, T, M>, report: &mut Self::Report) {
        self.tests.after_update(posterior, &mut report.tests);
        self.sage_husa
            .after_update(posterior, &mut report.sage_husa);
    }
}
