//! The process model of a local filter holding the share `β_i`.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

/// A process model whose noise is `Q / β`: the process noise of a local
/// filter that holds the information share `β` (paper 001, `Q_i = β_i⁻¹ Q`).
///
/// Together with the reset `P_i = β_i⁻¹ P_g` this keeps the locals'
/// information summing to the true information, so the fused estimate of
/// linear locals with `Σ β_i = 1` equals the centralised Kalman filter.
/// Propagation and the transition matrix are the wrapped model's.
/// [`FederatedFilter::predict`](super::FederatedFilter::predict) wraps the
/// model for every local; [`FederatedFilter::shared_noise`](super::FederatedFilter::shared_noise)
/// gives the wrapper for predicting one local by hand.
///
/// ```
/// use kestrel_adaptive::federated::SharedNoise;
/// use kestrel_core::{ProcessModel, nalgebra::{Matrix1, Vector1}};
/// use kestrel_models::LinearProcess;
/// let model = LinearProcess::new(Matrix1::new(1.0), Matrix1::new(0.3));
/// let local = SharedNoise::new(&model, 0.25).unwrap();
/// assert_eq!(local.noise(&Vector1::zeros(), 1.0)[0], 1.2);
/// assert!(SharedNoise::new(&model, 0.0).is_err());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct SharedNoise<'m, T: Real, P> {
    model: &'m P,
    share: T,
    inverse_share: T,
}

impl<'m, T: Real, P> SharedNoise<'m, T, P> {
    /// `model` with its noise divided by `share`.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] (`"share"`) unless `0 < share ≤ 1`.
    pub fn new(model: &'m P, share: T) -> Result<Self, FilterError> {
        // Also refuses NaN; a share too small to invert is not finite.
        let inverse_share = share.recip();
        if !(share > T::zero() && share <= T::one() && inverse_share.is_finite()) {
            return Err(FilterError::InvalidParameter {
                name: "share",
                valid: "0 < share ≤ 1, with a finite reciprocal",
            });
        }
        Ok(Self {
            model,
            share,
            inverse_share,
        })
    }

    /// The information share `β`.
    pub fn share(&self) -> T {
        self.share
    }

    /// The wrapped model.
    pub fn model(&self) -> &'m P {
        self.model
    }
}

impl<T: Real, const N: usize, P: ProcessModel<T, N>> ProcessModel<T, N> for SharedNoise<'_, T, P> {
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        self.model.propagate(x, dt)
    }

    fn noise(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        self.model.noise(x, dt) * self.inverse_share
    }
}

impl<T: Real, const N: usize, P: LinearizedProcess<T, N>> LinearizedProcess<T, N>
    for SharedNoise<'_, T, P>
{
    fn transition(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        self.model.transition(x, dt)
    }
}
