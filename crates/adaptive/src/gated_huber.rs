//! Huber inflation behind a χ² gate: the robust update that also survives
//! gross errors.

use kestrel_core::real::to_f64;
use kestrel_core::{FilterError, Real};

use crate::{ChiSquareGate, HuberInflation};

/// A [`ChiSquareGate`] followed by [`HuberInflation`], run as a tuple:
/// innovations beyond the gate are rejected outright, those between the
/// Huber threshold and the gate are down-weighted, the rest are used as
/// they are.
///
/// Why both: Huber inflation bounds the influence of a moderate outlier,
/// but its weights are floored at `ε` (so `R` stays finite), which means
/// that beyond about `√(χ²/ε)` standard deviations (≈ 10⁸ σ in `f64`,
/// 6·10³ σ in `f32`) the correction grows again in proportion to the
/// residual: a single 10³⁰ m range moves the state by about 10¹⁴ m. A gate
/// in front removes such gross errors.
///
/// ```
/// use kestrel_adaptive::gated_huber;
/// let (gate, huber) = gated_huber::<f64, 2>(0.05, 1e-6).unwrap();
/// assert!(gate.threshold() > huber.global_threshold());
/// assert!(gated_huber::<f64, 2>(0.05, 0.1).is_err());
/// ```
pub type GatedHuber<T, const M: usize> = (ChiSquareGate<T, M>, HuberInflation<T, M>);

/// Huber inflation at `huber_significance` (in `[0.01, 0.15]`) behind a
/// χ² gate at `gate_significance` (typically 10⁻⁶ … 10⁻³).
///
/// # Errors
/// The errors of [`HuberInflation::new`] and [`ChiSquareGate::new`], and
/// [`FilterError::InvalidParameter`] `"gate_significance"` unless it is
/// below `huber_significance` (a gate inside the Huber threshold would
/// reject what Huber is meant to down-weight).
pub fn gated_huber<T: Real, const M: usize>(
    huber_significance: T,
    gate_significance: T,
) -> Result<GatedHuber<T, M>, FilterError> {
    let huber = HuberInflation::new(huber_significance)?;
    let gate = ChiSquareGate::new(gate_significance)?;
    // Both are in (0, 1) here (the constructors above checked them).
    if to_f64(gate_significance) >= to_f64(huber_significance) {
        return Err(FilterError::InvalidParameter {
            name: "gate_significance",
            valid: "below huber_significance",
        });
    }
    Ok((gate, huber))
}
