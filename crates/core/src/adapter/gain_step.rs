use core::cell::{Cell, OnceCell};
use core::fmt;

use nalgebra::{SMatrix, SVector};

use crate::linalg::{
    cholesky, lower_times_transpose, mirror_lower, solve_lower, FactoredCovariance, Ldl,
};
use crate::Real;

/// The two parts of `H P⁻ Hᵀ`: `(H Φ P Φᵀ Hᵀ, H Q Hᵀ)`.
type Parts<T, const M: usize> = (SMatrix<T, M, M>, SMatrix<T, M, M>);

/// Where the split of `H P⁻ Hᵀ` comes from.
#[derive(Clone)]
enum Split<'a, T: Real, const M: usize> {
    /// Not asked for.
    Absent,
    /// Given when the view was built.
    Ready(Parts<T, M>),
    /// Computed by the form the first time an adapter asks (a fading
    /// adapter whose test passes never does), then kept.
    Lazy {
        compute: &'a dyn Fn() -> Parts<T, M>,
        parts: OnceCell<Parts<T, M>>,
    },
}

impl<T: Real, const M: usize> Split<'_, T, M> {
    /// The split given up front, or none.
    fn given(parts: Option<Parts<T, M>>) -> Self {
        match parts {
            Some(parts) => Self::Ready(parts),
            None => Self::Absent,
        }
    }

    fn get(&self) -> Option<&Parts<T, M>> {
        match self {
            Self::Absent => None,
            Self::Ready(parts) => Some(parts),
            Self::Lazy { compute, parts } => Some(parts.get_or_init(compute)),
        }
    }
}

impl<T: Real, const M: usize> fmt::Debug for Split<'_, T, M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Absent => f.write_str("Absent"),
            Self::Ready(parts) => f.debug_tuple("Ready").field(parts).finish(),
            Self::Lazy { parts, .. } => f.debug_tuple("Lazy").field(&parts.get()).finish(),
        }
    }
}

/// The measurement-space view of one update that adapters read and change
/// before the gain is computed.
///
/// The predicted measurement covariance (`H P⁻ Hᵀ`, without `R`) is kept as
/// the sum of a *propagated* part (`H Φ P Φᵀ Hᵀ`) and a *process noise* part
/// (`H Q Hᵀ`) when the adapter asked for the split
/// ([`PriorAdapter::NEEDS_SPLIT`](super::PriorAdapter::NEEDS_SPLIT)); a fade
/// `λ` scales only the propagated part, as in `P⁻ = λ Φ P Φᵀ + Q`.
///
/// Every change keeps [`innovation_covariance`](Self::innovation_covariance)
/// and its factor consistent, so later members of an adapter tuple see the
/// effect of earlier ones. After the adapters, the form recomputes its own
/// quantities exactly from the fade, `R` and innovation left here.
///
/// ```
/// use kestrel_core::adapter::GainStep;
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// let mut step = GainStep::new(
///     Vector1::new(3.0_f64),
///     Matrix1::new(4.0),            // H P⁻ Hᵀ
///     Some((Matrix1::new(3.0), Matrix1::new(1.0))),
///     Matrix1::new(5.0),            // R
/// ).unwrap();
/// assert_eq!(step.innovation_covariance()[0], 9.0);
/// assert_eq!(step.mahalanobis(), Some(1.0));
/// step.fade(2.0);                   // 2·3 + 1 + 5
/// assert_eq!(step.innovation_covariance()[0], 12.0);
/// step.set_noise(Matrix1::new(10.0));
/// assert_eq!(step.innovation_covariance()[0], 17.0);
/// step.scale_innovation(0.5);
/// assert_eq!(step.innovation()[0], 1.5);
/// ```
///
/// The lifetime is that of the form's data the split may be computed from
/// on demand, and of its factorisation of the nominal `C`; adapters write
/// `&mut GainStep<T, M>` and never name it.
#[derive(Debug, Clone)]
pub struct GainStep<'a, T: Real, const M: usize> {
    raw_innovation: SVector<T, M>,
    innovation: SVector<T, M>,
    nominal_predicted: SMatrix<T, M, M>,
    split: Split<'a, T, M>,
    nominal_noise: SMatrix<T, M, M>,
    noise: SMatrix<T, M, M>,
    fade: T,
    innovation_scale: T,
    noise_changed: bool,
    rejected: bool,
    covariance: SMatrix<T, M, M>,
    /// The lower Cholesky factor of `covariance` (`None`: not positive
    /// definite), given by the form or made when first asked for.
    factor: OnceCell<Option<SMatrix<T, M, M>>>,
    /// The form's `L D Lᵀ` of the nominal `C` (its check), while
    /// `covariance` is that `C`: the NIS the report gives comes from it,
    /// and the Cholesky factor, if an adapter asks for it, is its `L √D`
    /// instead of a second factorisation. An adapter that replaces `R`
    /// first (Sage–Husa) never needs the nominal factor at all.
    nominal_ldl: Option<&'a Ldl<T, M>>,
    /// The `L D Lᵀ` of `covariance` once an adapter changed it, made when
    /// first needed: the NIS, the Cholesky factor if asked for, and the
    /// form's gain all come from it (no square roots on the way to the
    /// gain).
    ldl: OnceCell<Option<Ldl<T, M>>>,
    /// The factor `noise` was given by ([`GainStep::set_noise_factor`]).
    noise_factor: Option<SMatrix<T, M, M>>,
    /// `L⁻¹ ν` for the current innovation and factor, once asked for.
    whitened: Cell<Option<SVector<T, M>>>,
    /// `νᵀ C⁻¹ ν` for the current innovation and `C`, once asked for: the
    /// report's NIS, the adapters' tests and the adapted NIS share it.
    nis: Cell<Option<T>>,
}

impl<T: Real, const M: usize> GainStep<'static, T, M> {
    /// Builds the view from the innovation `ν`, the predicted measurement
    /// covariance `H P⁻ Hᵀ`, optionally its split into (propagated, process
    /// noise) parts, and `R`. Returns `None` if `H P⁻ Hᵀ + R` is not positive
    /// definite. Forms call this; adapters receive it.
    pub fn new(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: Option<(SMatrix<T, M, M>, SMatrix<T, M, M>)>,
        noise: SMatrix<T, M, M>,
    ) -> Option<Self> {
        let covariance = predicted + noise;
        let factor = cholesky(&covariance).ok()?;
        Some(Self::with_factor(
            innovation, predicted, split, noise, factor,
        ))
    }

    /// Like [`new`](Self::new) with the Cholesky factor of `H P⁻ Hᵀ + R`
    /// already known (square-root forms have it).
    #[inline(always)]
    pub fn with_factor(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: Option<(SMatrix<T, M, M>, SMatrix<T, M, M>)>,
        noise: SMatrix<T, M, M>,
        factor: SMatrix<T, M, M>,
    ) -> Self {
        let factor = OnceCell::from(Some(factor));
        Self::build(
            innovation,
            predicted,
            Split::given(split),
            noise,
            factor,
            None,
        )
    }
}

impl<'a, T: Real, const M: usize> GainStep<'a, T, M> {
    /// Like [`with_factor`](GainStep::with_factor), given the form's
    /// `L D Lᵀ` of `H P⁻ Hᵀ + R` (the check that it is positive definite)
    /// instead of the Cholesky factor.
    #[inline(always)]
    pub(crate) fn with_ldl(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: Option<Parts<T, M>>,
        noise: SMatrix<T, M, M>,
        ldl: &'a Ldl<T, M>,
    ) -> Self {
        Self::on_ldl(innovation, predicted, Split::given(split), noise, ldl)
    }

    /// Like [`with_ldl`](GainStep::with_ldl), the split computed by `split`
    /// only if an adapter asks for it.
    #[inline(always)]
    pub(crate) fn with_lazy_split(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: &'a dyn Fn() -> Parts<T, M>,
        noise: SMatrix<T, M, M>,
        ldl: &'a Ldl<T, M>,
    ) -> Self {
        let split = Split::Lazy {
            compute: split,
            parts: OnceCell::new(),
        };
        Self::on_ldl(innovation, predicted, split, noise, ldl)
    }

    /// The view on the form's `L D Lᵀ`, nothing factored yet.
    #[inline(always)]
    fn on_ldl(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: Split<'a, T, M>,
        noise: SMatrix<T, M, M>,
        ldl: &'a Ldl<T, M>,
    ) -> Self {
        let factor = OnceCell::new();
        Self::build(innovation, predicted, split, noise, factor, Some(ldl))
    }

    /// The view with nothing adapted yet, built in place (no intermediate
    /// view copied: it is a few KB).
    #[inline(always)]
    fn build(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: Split<'a, T, M>,
        noise: SMatrix<T, M, M>,
        factor: OnceCell<Option<SMatrix<T, M, M>>>,
        nominal_ldl: Option<&'a Ldl<T, M>>,
    ) -> Self {
        Self {
            raw_innovation: innovation,
            innovation,
            nominal_predicted: predicted,
            split,
            nominal_noise: noise,
            noise,
            fade: T::one(),
            innovation_scale: T::one(),
            noise_changed: false,
            rejected: false,
            covariance: predicted + noise,
            factor,
            nominal_ldl,
            ldl: OnceCell::new(),
            noise_factor: None,
            whitened: Cell::new(None),
            nis: Cell::new(None),
        }
    }

    /// The `L D Lᵀ` of the current `C`: the form's while `C` is the
    /// nominal one, else the view's own, made now if no adapter needed it
    /// yet; `None` if `C` is not positive definite, or for a view the form
    /// built on a Cholesky factor that no adapter changed.
    #[inline(always)]
    pub(crate) fn ldl(&self) -> Option<&Ldl<T, M>> {
        match self.nominal_ldl {
            Some(ldl) => Some(ldl),
            None if self.on_given_factor() => None,
            None => self
                .ldl
                .get_or_init(|| Ldl::new(&self.covariance).ok())
                .as_ref(),
        }
    }

    /// The `L D Lᵀ` of `C` as the adapters left it and the NIS of the
    /// innovation used (computed once, shared with the adapters' tests);
    /// `None` when something faded (`fade ≠ 1`: the form then factors `C`
    /// from the faded prior itself) or the adapters left `C` indefinite.
    #[inline(always)]
    pub(crate) fn used_factorisation(&self, fade: T) -> Option<(&Ldl<T, M>, T)> {
        if fade != T::one() {
            return None;
        }
        let ldl = self.ldl()?;
        Some((ldl, self.mahalanobis()?))
    }

    /// The Cholesky factor of `C` if the view holds it already (given by
    /// the form, or formed for an adapter), without forming it.
    #[inline(always)]
    pub(crate) fn formed_factor(&self) -> Option<&SMatrix<T, M, M>> {
        self.factor.get().and_then(Option::as_ref)
    }

    /// Whether the view is still on the Cholesky factor a form built it
    /// with ([`with_factor`](GainStep::with_factor)): no adapter changed
    /// `C` since.
    #[inline(always)]
    fn on_given_factor(&self) -> bool {
        self.ldl.get().is_none() && self.factor.get().is_some_and(Option::is_some)
    }

    /// `H P⁻ Hᵀ + R` as the form gave them, before any adapter.
    #[inline(always)]
    pub(crate) fn nominal_innovation_covariance(&self) -> SMatrix<T, M, M> {
        self.nominal_predicted + self.nominal_noise
    }

    /// The innovation as the adapters have left it so far.
    pub fn innovation(&self) -> &SVector<T, M> {
        &self.innovation
    }

    /// The innovation `z ⊟ h(x⁻)` before any adapter touched it.
    pub fn raw_innovation(&self) -> &SVector<T, M> {
        &self.raw_innovation
    }

    /// The measurement noise covariance in use (`R`, or what an adapter set).
    pub fn noise(&self) -> &SMatrix<T, M, M> {
        &self.noise
    }

    /// The model's own `R`.
    pub fn nominal_noise(&self) -> &SMatrix<T, M, M> {
        &self.nominal_noise
    }

    /// `(H Φ P Φᵀ Hᵀ, H Q Hᵀ)` at fade 1, when the adapter asked for the split.
    pub fn split(&self) -> Option<(&SMatrix<T, M, M>, &SMatrix<T, M, M>)> {
        self.split.get().map(|(a, b)| (a, b))
    }

    /// `H P⁻ Hᵀ` with the current fade (without `R`).
    pub fn predicted_covariance(&self) -> SMatrix<T, M, M> {
        if self.fade == T::one() {
            return self.nominal_predicted;
        }
        match self.split.get() {
            Some((prop, _)) => self.nominal_predicted + prop * (self.fade - T::one()),
            None => self.nominal_predicted * self.fade,
        }
    }

    /// The innovation covariance `C = H P⁻ Hᵀ + R` with the current fade and
    /// noise.
    pub fn innovation_covariance(&self) -> &SMatrix<T, M, M> {
        &self.covariance
    }

    /// Lower Cholesky factor of [`innovation_covariance`](Self::innovation_covariance),
    /// `None` if an adapter made it indefinite.
    pub fn innovation_factor(&self) -> Option<&SMatrix<T, M, M>> {
        self.factor
            .get_or_init(|| self.ldl().map(Ldl::cholesky_factor))
            .as_ref()
    }

    /// `νᵀ C⁻¹ ν` for the current innovation and covariance (the NIS); `None`
    /// if `C` is not positive definite. From the `L D Lᵀ` of `C` (`Σ yₖ² /
    /// dₖ` for `y = L⁻¹ ν`) where the view has one, else from its Cholesky
    /// factor; computed once for the current innovation and `C`, whichever
    /// adapter asks first.
    pub fn mahalanobis(&self) -> Option<T> {
        if let Some(nis) = self.nis.get() {
            return Some(nis);
        }
        let nis = match self.ldl() {
            Some(ldl) => ldl.quadratic_form(&self.innovation),
            None => self.whitened_innovation()?.norm_squared(),
        };
        self.nis.set(Some(nis));
        Some(nis)
    }

    /// The whitened innovation `L⁻¹ ν` for `C = L Lᵀ` (its squared norm is
    /// the NIS); `None` if `C` is not positive definite. Computed once for
    /// the current innovation and `C`, whichever adapter asks first.
    ///
    /// ```
    /// use kestrel_core::adapter::GainStep;
    /// use kestrel_core::nalgebra::{Matrix1, Vector1};
    /// // C = 3 + 1 = 4 = 2², ν = 3: L⁻¹ ν = 1.5.
    /// let mut step =
    ///     GainStep::new(Vector1::new(3.0), Matrix1::new(3.0), None, Matrix1::new(1.0)).unwrap();
    /// assert_eq!(step.whitened_innovation(), Some(Vector1::new(1.5)));
    /// step.scale_innovation(2.0);
    /// assert_eq!(step.whitened_innovation(), Some(Vector1::new(3.0)));
    /// ```
    pub fn whitened_innovation(&self) -> Option<SVector<T, M>> {
        if let Some(w) = self.whitened.get() {
            return Some(w);
        }
        let l = self.innovation_factor()?;
        let mut w = self.innovation;
        solve_lower(l, &mut w);
        self.whitened.set(Some(w));
        Some(w)
    }

    /// `vᵀ C⁻¹ v` for any `v` with the current covariance.
    pub fn mahalanobis_of(&self, v: &SVector<T, M>) -> Option<T> {
        let l = self.innovation_factor()?;
        let mut w = *v;
        solve_lower(l, &mut w);
        Some(w.norm_squared())
    }

    /// The product of the fades applied so far.
    pub fn fade_factor(&self) -> T {
        self.fade
    }

    /// The product of the innovation scale factors applied so far.
    pub fn innovation_scale(&self) -> T {
        self.innovation_scale
    }

    /// Whether an adapter has rejected the measurement.
    pub fn is_rejected(&self) -> bool {
        self.rejected
    }

    /// Whether an adapter has replaced `R`.
    pub fn noise_changed(&self) -> bool {
        self.noise_changed
    }

    /// Scales the propagated covariance by `lambda` (cumulative), i.e.
    /// `P⁻ = λ Φ P Φᵀ + Q`. Non-finite or non-positive values are ignored.
    ///
    /// Without the split (the adapter did not set `NEEDS_SPLIT`) this view can
    /// only approximate `C` by fading all of `H P⁻ Hᵀ`. The covariance and
    /// unscented forms still fade only the propagated part; the square-root
    /// form, whose factor then already holds `Q`, fades all of `P⁻`.
    ///
    /// When the form fades only a block of states
    /// ([`FadeStates`](crate::form::FadeStates)), this view takes
    /// `H D Φ P Φᵀ D Hᵀ = λ H Φ P Φᵀ Hᵀ`, exact when the block covers every
    /// state `H` reads; otherwise `C` here (and a `λ` computed from it) is an
    /// approximation, while the form still applies `D` exactly.
    pub fn fade(&mut self, lambda: T) {
        if !(lambda.is_finite() && lambda > T::zero()) || lambda == T::one() {
            return;
        }
        self.fade *= lambda;
        self.refresh();
    }

    /// Replaces the measurement noise covariance (the lower triangle of `r` is
    /// used and mirrored).
    pub fn set_noise(&mut self, r: SMatrix<T, M, M>) {
        let mut r = r;
        mirror_lower(&mut r);
        self.noise = r;
        self.noise_factor = None;
        self.noise_changed = true;
        self.refresh();
    }

    /// Replaces the measurement noise covariance by `L Lᵀ`, given its lower
    /// triangular factor `L` (the strict upper part of `l` is not read),
    /// and keeps `L`: the form then takes `R` into the Joseph update
    /// through it instead of factoring `R` again. An adapter that has the
    /// factor of its `R` anyway (as [`cholesky`] of the estimate, to check
    /// it) saves a factorisation per update this way; one that keeps `R`
    /// as well hands both over by
    /// [`set_factored_noise`](Self::set_factored_noise), which also spares
    /// the product `L Lᵀ`.
    ///
    /// `L Lᵀ` is positive semi-definite for any `L`; a non-finite `L` gives
    /// a non-finite `R`, which the form rejects as it does one given to
    /// [`set_noise`](Self::set_noise).
    ///
    /// ```
    /// use kestrel_core::adapter::GainStep;
    /// use kestrel_core::nalgebra::{Matrix2, Vector2};
    /// let mut step =
    ///     GainStep::new(Vector2::zeros(), Matrix2::identity(), None, Matrix2::identity()).unwrap();
    /// // L = [2 0; 1 3] (the 9 above the diagonal is not read): R = [4 2; 2 10].
    /// step.set_noise_factor(&Matrix2::new(2.0, 9.0, 1.0, 3.0));
    /// assert_eq!(*step.noise(), Matrix2::new(4.0, 2.0, 2.0, 10.0));
    /// assert_eq!(step.noise_factor(), Some(&Matrix2::new(2.0, 0.0, 1.0, 3.0)));
    /// assert_eq!(step.innovation_covariance()[(1, 1)], 11.0);
    /// ```
    pub fn set_noise_factor(&mut self, l: &SMatrix<T, M, M>) {
        let mut lower = *l;
        lower.fill_upper_triangle(T::zero(), 1);
        self.noise = lower_times_transpose(&lower);
        self.noise_factor = Some(lower);
        self.noise_changed = true;
        self.refresh();
    }

    /// Replaces the measurement noise covariance by `r.matrix()` and keeps
    /// its factor, as [`set_noise_factor`](Self::set_noise_factor) does but
    /// without forming `L Lᵀ`: the pair was made together
    /// ([`FactoredCovariance::new`]), so the form takes `R` into the
    /// innovation covariance as it is and into the Joseph update through
    /// `L`, as it takes the model's `R` and its cached factor.
    ///
    /// ```
    /// use kestrel_core::adapter::GainStep;
    /// use kestrel_core::linalg::FactoredCovariance;
    /// use kestrel_core::nalgebra::{Matrix2, Vector2};
    /// let mut step =
    ///     GainStep::new(Vector2::zeros(), Matrix2::identity(), None, Matrix2::identity()).unwrap();
    /// let r = FactoredCovariance::new(Matrix2::new(4.0, 2.0, 2.0, 10.0)).unwrap();
    /// step.set_factored_noise(&r);
    /// assert_eq!(step.noise(), r.matrix());
    /// assert_eq!(step.noise_factor(), Some(r.factor()));
    /// assert!(step.noise_changed());
    /// assert_eq!(step.innovation_covariance()[(1, 1)], 11.0);
    /// ```
    pub fn set_factored_noise(&mut self, r: &FactoredCovariance<T, M>) {
        self.noise = *r.matrix();
        self.noise_factor = Some(*r.factor());
        self.noise_changed = true;
        self.refresh();
    }

    /// The lower triangular factor of the current `R` when an adapter gave
    /// `R` by it ([`set_noise_factor`](Self::set_noise_factor),
    /// [`set_factored_noise`](Self::set_factored_noise)); `None` for the
    /// model's `R` or one set by [`set_noise`](Self::set_noise).
    pub fn noise_factor(&self) -> Option<&SMatrix<T, M, M>> {
        self.noise_factor.as_ref()
    }

    /// Multiplies the innovation by `s` (outlier compression).
    pub fn scale_innovation(&mut self, s: T) {
        self.whitened.set(None);
        self.nis.set(None);
        self.innovation *= s;
        self.innovation_scale *= s;
    }

    /// Replaces the innovation (for adapters that change components
    /// differently).
    pub fn set_innovation(&mut self, innovation: SVector<T, M>) {
        self.whitened.set(None);
        self.nis.set(None);
        self.innovation = innovation;
    }

    /// Rejects the measurement: the filter keeps its prior and reports the
    /// rejection.
    pub fn reject(&mut self) {
        self.rejected = true;
    }

    fn refresh(&mut self) {
        self.whitened.set(None);
        self.nis.set(None);
        // Unfaded, `predicted_covariance` is the nominal one: added in
        // place rather than through its copy.
        self.covariance = if self.fade == T::one() {
            self.nominal_predicted + self.noise
        } else {
            self.predicted_covariance() + self.noise
        };
        // Factored when first asked for: a fade then a new `R` factor once.
        self.factor = OnceCell::new();
        self.ldl = OnceCell::new();
        self.nominal_ldl = None;
    }
}

#[cfg(test)]
mod whitened_cache_tests {
    use nalgebra::{Matrix2, Vector2};

    use super::*;

    /// The cached NIS equals one computed afresh after every change an
    /// adapter can make (`mahalanobis_of` never reads the cache).
    #[test]
    fn every_change_of_the_innovation_or_covariance_refreshes_the_cache() {
        let predicted = Matrix2::new(3.0, 1.0, 1.0, 2.0);
        let parts = (predicted * 0.75, predicted * 0.25);
        let mut step = GainStep::new(
            Vector2::new(1.5, -0.5),
            predicted,
            Some(parts),
            Matrix2::identity(),
        )
        .unwrap();
        let fresh = |step: &GainStep<f64, 2>| step.mahalanobis_of(step.innovation());
        let mut seen = [(0.0, 0.0); 5];
        type Change = dyn Fn(&mut GainStep<f64, 2>);
        let changes: [&Change; 5] = [
            &|s| s.scale_innovation(0.5),
            &|s| s.set_innovation(Vector2::new(-2.0, 1.0)),
            &|s| s.set_noise(Matrix2::new(2.0, 0.5, 0.5, 1.0)),
            &|s| s.set_noise_factor(&Matrix2::new(0.5, 0.0, 0.25, 2.0)),
            &|s| s.fade(1.5),
        ];
        for (change, seen) in changes.iter().zip(&mut seen) {
            let before = step.mahalanobis().unwrap();
            assert_eq!(Some(before), fresh(&step));
            change(&mut step);
            let after = step.mahalanobis().unwrap();
            assert_eq!(Some(after), fresh(&step));
            *seen = (before, after);
        }
        // Each change moved the NIS, so a stale cache would have shown.
        assert!(seen.iter().all(|(b, a)| b != a), "{seen:?}");
    }
}

#[cfg(test)]
mod lazy_split_tests {
    use core::cell::Cell;

    use nalgebra::{Matrix1, Vector1};

    use super::*;

    #[test]
    fn the_split_is_computed_once_and_only_when_asked() {
        let calls = Cell::new(0);
        let parts = || {
            calls.set(calls.get() + 1);
            (Matrix1::new(3.0), Matrix1::new(1.0))
        };
        let ldl = Ldl::new(&Matrix1::new(9.0)).unwrap(); // 4 + 5
        fn build<'a>(
            parts: &'a dyn Fn() -> Parts<f64, 1>,
            ldl: &'a Ldl<f64, 1>,
        ) -> GainStep<'a, f64, 1> {
            GainStep::with_lazy_split(
                Vector1::new(3.0),
                Matrix1::new(4.0),
                parts,
                Matrix1::new(5.0),
                ldl,
            )
        }
        // Not asked: never computed.
        let step = build(&parts, &ldl);
        assert_eq!(step.mahalanobis(), Some(1.0));
        assert_eq!(step.predicted_covariance()[0], 4.0);
        assert_eq!(calls.get(), 0);
        // A fade needs the propagated part: computed once, and the result is
        // that of the split given up front (the type's own example).
        let mut step = build(&parts, &ldl);
        step.fade(2.0);
        assert_eq!(step.innovation_covariance()[0], 12.0);
        assert_eq!(step.split().map(|(p, q)| (p[0], q[0])), Some((3.0, 1.0)));
        step.set_noise(Matrix1::new(10.0));
        assert_eq!(step.innovation_covariance()[0], 17.0);
        assert_eq!(calls.get(), 1);
    }
}

#[cfg(test)]
mod nominal_ldl_tests {
    use approx::assert_relative_eq;
    use nalgebra::{Matrix3, Vector3};

    use super::*;

    /// `H P⁻ Hᵀ`, `R` and `ν` of a three-component measurement.
    fn parts() -> (Matrix3<f64>, Matrix3<f64>, Vector3<f64>) {
        let a = Matrix3::new(1.0, 0.3, -0.2, 0.1, 2.0, 0.4, -0.5, 0.2, 1.5);
        let r = Matrix3::new(0.5, 0.1, 0.0, 0.1, 0.4, 0.05, 0.0, 0.05, 0.3);
        (a * a.transpose(), r, Vector3::new(1.0, -2.0, 0.5))
    }

    #[test]
    fn a_view_on_the_forms_ldl_equals_one_on_the_cholesky_factor() {
        let (hph, r, nu) = parts();
        let ldl = Ldl::new(&(hph + r)).unwrap();
        let from_ldl = GainStep::with_ldl(nu, hph, None, r, &ldl);
        let reference = GainStep::new(nu, hph, None, r).unwrap();
        // Nothing factored until asked.
        assert!(from_ldl.factor.get().is_none());
        let nis = reference.mahalanobis().unwrap();
        assert_relative_eq!(from_ldl.mahalanobis().unwrap(), nis, epsilon = 1e-13);
        assert!(from_ldl.factor.get().is_none(), "the NIS needs no factor");
        // Asked: L √D, the Cholesky factor to rounding; then the same NIS.
        let l = from_ldl.innovation_factor().unwrap();
        assert_relative_eq!(*l, *reference.innovation_factor().unwrap(), epsilon = 1e-14);
        assert_relative_eq!(from_ldl.mahalanobis().unwrap(), nis, epsilon = 1e-13);
        assert_relative_eq!(
            from_ldl.whitened_innovation().unwrap(),
            reference.whitened_innovation().unwrap(),
            epsilon = 1e-13
        );
    }

    #[test]
    fn a_new_noise_drops_the_nominal_factorisation() {
        let (hph, r, nu) = parts();
        let ldl = Ldl::new(&(hph + r)).unwrap();
        let mut step = GainStep::with_ldl(nu, hph, None, r, &ldl);
        let r2 = r * 4.0;
        step.set_noise(r2);
        // The NIS is that of H P⁻ Hᵀ + 4 R, from its own L D Lᵀ (no
        // Cholesky factor formed), not that of the nominal C.
        let own = Ldl::new(&(hph + r2)).unwrap();
        assert_eq!(step.mahalanobis(), Some(own.quadratic_form(&nu)));
        assert_ne!(step.mahalanobis(), Some(ldl.quadratic_form(&nu)));
        assert!(step.factor.get().is_none(), "the NIS needs no factor");
        // Asked for, the factor is L √D of that L D Lᵀ: the Cholesky factor
        // to rounding, and the NIS through it the same to rounding.
        let expected = crate::linalg::cholesky(&(hph + r2)).unwrap();
        assert_eq!(*step.innovation_factor().unwrap(), own.cholesky_factor());
        assert_relative_eq!(
            *step.innovation_factor().unwrap(),
            expected,
            epsilon = 1e-14
        );
        let mut w = nu;
        crate::linalg::solve_lower(&expected, &mut w);
        assert_relative_eq!(
            step.mahalanobis().unwrap(),
            w.norm_squared(),
            max_relative = 1e-13
        );
        // An indefinite replacement: no factor, no NIS.
        step.set_noise(-r2 * 10.0);
        assert!(step.innovation_factor().is_none());
        assert!(step.mahalanobis().is_none());
    }
}
