use nalgebra::{SMatrix, SVector};

use crate::linalg::{cholesky, mirror_lower, solve_lower};
use crate::Real;

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
#[derive(Debug, Clone)]
pub struct GainStep<T: Real, const M: usize> {
    raw_innovation: SVector<T, M>,
    innovation: SVector<T, M>,
    nominal_predicted: SMatrix<T, M, M>,
    split: Option<(SMatrix<T, M, M>, SMatrix<T, M, M>)>,
    nominal_noise: SMatrix<T, M, M>,
    noise: SMatrix<T, M, M>,
    fade: T,
    innovation_scale: T,
    noise_changed: bool,
    rejected: bool,
    covariance: SMatrix<T, M, M>,
    factor: Option<SMatrix<T, M, M>>,
}

impl<T: Real, const M: usize> GainStep<T, M> {
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
    pub fn with_factor(
        innovation: SVector<T, M>,
        predicted: SMatrix<T, M, M>,
        split: Option<(SMatrix<T, M, M>, SMatrix<T, M, M>)>,
        noise: SMatrix<T, M, M>,
        factor: SMatrix<T, M, M>,
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
            factor: Some(factor),
        }
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
        self.split.as_ref().map(|(a, b)| (a, b))
    }

    /// `H P⁻ Hᵀ` with the current fade (without `R`).
    pub fn predicted_covariance(&self) -> SMatrix<T, M, M> {
        if self.fade == T::one() {
            return self.nominal_predicted;
        }
        match &self.split {
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
        self.factor.as_ref()
    }

    /// `νᵀ C⁻¹ ν` for the current innovation and covariance (the NIS); `None`
    /// if `C` is not positive definite.
    pub fn mahalanobis(&self) -> Option<T> {
        self.mahalanobis_of(&self.innovation)
    }

    /// `vᵀ C⁻¹ v` for any `v` with the current covariance.
    pub fn mahalanobis_of(&self, v: &SVector<T, M>) -> Option<T> {
        let l = self.factor.as_ref()?;
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
        self.noise_changed = true;
        self.refresh();
    }

    /// Multiplies the innovation by `s` (outlier compression).
    pub fn scale_innovation(&mut self, s: T) {
        self.innovation *= s;
        self.innovation_scale *= s;
    }

    /// Replaces the innovation (for adapters that change components
    /// differently).
    pub fn set_innovation(&mut self, innovation: SVector<T, M>) {
        self.innovation = innovation;
    }

    /// Rejects the measurement: the filter keeps its prior and reports the
    /// rejection.
    pub fn reject(&mut self) {
        self.rejected = true;
    }

    fn refresh(&mut self) {
        self.covariance = self.predicted_covariance() + self.noise;
        self.factor = cholesky(&self.covariance).ok();
    }
}
