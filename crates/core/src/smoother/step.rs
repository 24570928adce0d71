//! One step of the backward pass.

use nalgebra::SMatrix;

use super::{RtsEpoch, Smoothed};
use crate::error::ensure_finite;
use crate::linalg::{cholesky, mirror_lower, sandwich, solve_lower, solve_lower_transpose};
use crate::{FilterError, Quantity, Real, StateSpace};

/// Smooths `epoch` given the next epoch of the record and that epoch's
/// smoothed estimate (see the [module](super) for the recursion).
///
/// The covariances are read as symmetric matrices; the result's covariance
/// is exactly symmetric. With [`Euclidean`](crate::Euclidean) arithmetic
/// `⊞`/`⊟` are `+`/`−`; a [`StateSpace`] carries wrapped angles.
///
/// # Errors
/// [`FilterError::NotPositiveDefinite`] naming
/// [`Quantity::PropagatedCovariance`] when `next.prior_covariance` cannot
/// be factored, [`FilterError::NonFinite`] naming
/// [`Quantity::SmoothedState`] / [`Quantity::SmoothedCovariance`] when a
/// result is not finite (a non-finite input).
///
/// ```
/// use kestrel_core::smoother::{rts_step, RtsEpoch, Smoothed};
/// use kestrel_core::{Euclidean, nalgebra::{Matrix1, Vector1}};
/// // x⁺ = 0, P⁺ = 1; Φ = 1, Q = 1 so P⁻ = 2; the next epoch smooths to 1 with variance 0.5.
/// let this = RtsEpoch::<f64, 1>::initial(Vector1::new(0.0), Matrix1::new(1.0));
/// let next = RtsEpoch::predicted(Matrix1::new(1.0), Vector1::new(0.0), Matrix1::new(2.0));
/// let later = Smoothed { state: Vector1::new(1.0), covariance: Matrix1::new(0.5) };
/// let s = rts_step(&Euclidean, &this, &next, &later)?;
/// // C = 1/2: xˢ = 0 + ½ (1 − 0); Pˢ = 1 + ¼ (0.5 − 2).
/// assert!((s.state[0] - 0.5).abs() < 1e-15);
/// assert!((s.covariance[0] - 0.625).abs() < 1e-15);
/// # Ok::<(), kestrel_core::FilterError>(())
/// ```
pub fn rts_step<T: Real, const N: usize, S: StateSpace<T, N>>(
    space: &S,
    epoch: &RtsEpoch<T, N>,
    next: &RtsEpoch<T, N>,
    smoothed_next: &Smoothed<T, N>,
) -> Result<Smoothed<T, N>, FilterError> {
    let phi = &next.transition;
    let p = &epoch.posterior_covariance;
    // G = Φ P⁺ (so that Gᵀ = P⁺ Φᵀ for the symmetric P⁺).
    let g = phi * p;
    let l = cholesky(&next.prior_covariance).map_err(|e| FilterError::NotPositiveDefinite {
        what: Quantity::PropagatedCovariance,
        index: e.index,
    })?;
    // Cᵀ = (P⁻)⁻¹ Φ P⁺ by two triangular solves, no inverse formed.
    let mut ct = g;
    solve_lower(&l, &mut ct);
    solve_lower_transpose(&l, &mut ct);
    let c = ct.transpose();
    let a = SMatrix::<T, N, N>::identity() - c * phi;
    // Q̃ + Pˢ_{k+1} = P⁻ − Φ P⁺ Φᵀ + Pˢ_{k+1}, symmetric in exact arithmetic.
    let mut inner = next.prior_covariance - g * phi.transpose() + smoothed_next.covariance;
    mirror_lower(&mut inner);
    let covariance = sandwich(&a, p) + sandwich(&c, &inner);
    let correction = c * space.difference(&smoothed_next.state, &next.prior_state);
    let state = space.add(&epoch.posterior_state, &correction);
    ensure_finite(&state, Quantity::SmoothedState)?;
    ensure_finite(&covariance, Quantity::SmoothedCovariance)?;
    Ok(Smoothed { state, covariance })
}
