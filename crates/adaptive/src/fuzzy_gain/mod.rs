//! The fuzzy odometer-gain adapter of paper 003.

mod inputs;
mod rules;

pub use inputs::{match_factor, OdometerInputs};
pub use rules::{odometer_engine, OdometerEngine, ODOMETER_RULES, ODOMETER_UNUSABLE};

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

use crate::fuzzy::{Engine, Inference};

/// What the fuzzy gain decided in one update.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GainDecision {
    /// No inputs were set for this epoch: the update was left alone.
    #[default]
    NoInputs,
    /// The gain `α₁` was applied to the innovation.
    Applied,
    /// The odometer was judged unusable (a veto or an unusable output set
    /// at least as strong as every usable one, or no rule fired): the update
    /// was rejected.
    Unusable,
}

/// What [`FuzzyGain`] did in one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FuzzyGainReport<T: Real, const O: usize, const R: usize> {
    /// The decision.
    pub decision: GainDecision,
    /// The odometer gain `α₁` applied (1 unless the decision is `Applied`).
    pub alpha: T,
    /// The match factor `dm₁` given.
    pub match_factor: T,
    /// The heading rate `|ΔH|` given, deg/s.
    pub heading_rate: T,
    /// The innovation mean `r` (σ units) after this epoch.
    pub innovation_mean: T,
    /// The rule and output-set strengths.
    pub inference: Inference<T, O, R>,
    /// The strongest usable output set.
    pub usable: T,
    /// The strongest unusable outcome (veto or unusable output set).
    pub unusable: T,
    /// Whether this adapter rejected the measurement.
    pub rejected: bool,
}

impl<T: Real, const O: usize, const R: usize> Default for FuzzyGainReport<T, O, R> {
    fn default() -> Self {
        Self {
            decision: GainDecision::NoInputs,
            alpha: T::one(),
            match_factor: T::zero(),
            heading_rate: T::zero(),
            innovation_mean: T::zero(),
            inference: Inference::default(),
            usable: T::zero(),
            unusable: T::zero(),
            rejected: false,
        }
    }
}

/// Fuzzy adaptive odometer gain (paper 003, eq. 5 and section 3.3) for a
/// velocity-matching update `z = v_SINS − α₁ v_ODⁿ` of dimension `M`.
///
/// The caller forms the measurement with `α₁ = 1` (`z = v_SINS − v_ODⁿ`,
/// the odometer velocity in the navigation frame) and, before each update,
/// supplies the epoch's [`OdometerInputs`] with
/// [`set_inputs`](Self::set_inputs) (they are used once). The adapter then:
///
/// 1. updates the innovation mean `r` (in units of the innovation's
///    predicted standard deviation): with `sₖ = √(νₖᵀ Cₖ⁻¹ νₖ / M)`, the
///    RMS of the whitened innovation as this adapter receives it,
///    `rₖ = β sₖ + (1 − β) rₖ₋₁` (`r₁ = s₁`), `β ∈ (0, 1]` the smoothing
///    (1 = this epoch only). It is updated every epoch, with or without
///    inputs, from the innovation before any gain correction, so a fault
///    the correction hides still shows;
/// 2. fires the engine on `[dm₁, |ΔH|, r]`;
/// 3. rejects the update if the strongest unusable outcome (a
///    [`Consequent::Veto`](crate::fuzzy::Consequent::Veto) rule — side-slip,
///    outage — or an output set flagged unusable — `α₁` tiny or large) is
///    at least as strong as the strongest usable output set, or if nothing
///    fires;
/// 4. otherwise defuzzifies the usable sets into `α₁` and re-forms the
///    innovation of `z = v_SINS − α₁ v_ODⁿ`:
///    `ν' = ν + (1 − α₁) v_ODⁿ`.
///
/// The engine is any [`Engine`] over those three inputs;
/// [`odometer`](Self::odometer) uses [`odometer_engine`].
///
/// ```
/// use kestrel_adaptive::{FuzzyGain, GainDecision, OdometerInputs};
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// let mut gain = FuzzyGain::<f64, 1>::odometer().unwrap();
/// // v_SINS = 10, v_OD = 11: dm₁ = 0.909…, ν = −0.5 with C = 1.
/// gain.set_inputs(OdometerInputs::new(10.0 / 11.0, 0.0, Vector1::new(11.0)));
/// let mut step = GainStep::new(Vector1::new(-0.5), Matrix1::new(0.5), None, Matrix1::new(0.5))
///     .unwrap();
/// let mut report = Default::default();
/// gain.before_gain(&mut step, &mut report);
/// assert_eq!(report.decision, GainDecision::Applied);
/// assert!(report.alpha < 1.0 && report.alpha > 0.85);
/// let corrected = -0.5 + (1.0 - report.alpha) * 11.0;
/// assert!((step.innovation()[0] - corrected).abs() < 1e-12);
/// ```
///
/// Sources: see the [references](kestrel_core::references).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FuzzyGain<
    T: Real,
    const M: usize,
    const S: usize = 5,
    const O: usize = 5,
    const R: usize = 14,
> {
    engine: Engine<T, 3, S, O, R>,
    unusable: [bool; O],
    smoothing: T,
    innovation_mean: Option<T>,
    inputs: Option<OdometerInputs<T, M>>,
}

impl<T: Real, const M: usize> FuzzyGain<T, M> {
    /// The default smoothing `β` of the innovation mean.
    pub const DEFAULT_SMOOTHING: f64 = 0.5;

    /// The adapter with [`odometer_engine`], [`ODOMETER_UNUSABLE`] and
    /// smoothing 0.5.
    ///
    /// # Errors
    /// None for the built-in values.
    pub fn odometer() -> Result<Self, FilterError> {
        Self::new(
            odometer_engine()?,
            ODOMETER_UNUSABLE,
            lit(Self::DEFAULT_SMOOTHING),
        )
    }
}

impl<T: Real, const M: usize, const S: usize, const O: usize, const R: usize>
    FuzzyGain<T, M, S, O, R>
{
    /// The adapter with engine `engine` over `[dm₁, |ΔH|, r]`, the output
    /// sets `unusable` marks as "odometer unusable", and smoothing
    /// `β ∈ (0, 1]` of the innovation mean.
    ///
    /// # Errors
    /// `InvalidParameter { name: "smoothing", valid: "0 < smoothing ≤ 1" }` outside `(0, 1]`.
    pub fn new(
        engine: Engine<T, 3, S, O, R>,
        unusable: [bool; O],
        smoothing: T,
    ) -> Result<Self, FilterError> {
        if !(smoothing > T::zero() && smoothing <= T::one()) {
            return Err(FilterError::InvalidParameter {
                name: "smoothing",
                valid: "0 < smoothing ≤ 1",
            });
        }
        Ok(Self {
            engine,
            unusable,
            smoothing,
            innovation_mean: None,
            inputs: None,
        })
    }

    /// Supplies this epoch's inputs; the next update uses and clears them.
    pub fn set_inputs(&mut self, inputs: OdometerInputs<T, M>) {
        self.inputs = Some(inputs);
    }

    /// The engine.
    pub fn engine(&self) -> &Engine<T, 3, S, O, R> {
        &self.engine
    }

    /// The innovation mean `r` so far (`None` before the first update).
    pub fn innovation_mean(&self) -> Option<T> {
        self.innovation_mean
    }

    /// Forgets the innovation mean and any pending inputs.
    pub fn reset(&mut self) {
        self.innovation_mean = None;
        self.inputs = None;
    }

    fn update_mean(&mut self, step: &GainStep<T, M>) -> T {
        if let Some(nis) = step.mahalanobis() {
            let s = (nis / lit::<T>(M as f64)).sqrt();
            let r = match self.innovation_mean {
                Some(prev) => self.smoothing * s + (T::one() - self.smoothing) * prev,
                None => s,
            };
            self.innovation_mean = Some(r);
        }
        self.innovation_mean.unwrap_or_else(T::zero)
    }
}

impl<T: Real, const M: usize, const S: usize, const O: usize, const R: usize> PriorAdapter<T>
    for FuzzyGain<T, M, S, O, R>
{
}

impl<T: Real, const M: usize, const S: usize, const O: usize, const R: usize> NoiseAdapter<T, M>
    for FuzzyGain<T, M, S, O, R>
{
    type Report = FuzzyGainReport<T, O, R>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        let r = self.update_mean(step);
        report.innovation_mean = r;
        let Some(inputs) = self.inputs.take() else {
            return;
        };
        if !inputs.is_finite() {
            // Nothing trustworthy to correct with: treat as unusable.
            report.decision = GainDecision::Unusable;
            report.rejected = true;
            step.reject();
            return;
        }
        report.match_factor = inputs.match_factor;
        report.heading_rate = inputs.heading_rate.abs();
        let inference = self
            .engine
            .infer(&[inputs.match_factor, inputs.heading_rate.abs(), r]);
        report.inference = inference;

        let mut usable_sets = inference.sets;
        let mut unusable = inference.veto;
        let mut usable = T::zero();
        for (w, &flag) in usable_sets.iter_mut().zip(&self.unusable) {
            if flag {
                unusable = unusable.max(*w);
                *w = T::zero();
            } else {
                usable = usable.max(*w);
            }
        }
        report.usable = usable;
        report.unusable = unusable;
        let alpha = if usable > unusable {
            self.engine.defuzzify(&usable_sets)
        } else {
            None
        };
        match alpha.filter(|a| a.is_finite()) {
            Some(alpha) => {
                report.decision = GainDecision::Applied;
                report.alpha = alpha;
                let corrected = step.innovation() + inputs.odometer_velocity * (T::one() - alpha);
                step.set_innovation(corrected);
            }
            None => {
                report.decision = GainDecision::Unusable;
                report.rejected = true;
                step.reject();
            }
        }
    }
}
