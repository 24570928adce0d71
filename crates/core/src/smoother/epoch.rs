//! What the backward pass needs of one epoch, and what it gives back.

use nalgebra::{SMatrix, SVector};

use crate::Real;

/// One epoch of a forward pass, as the RTS backward pass needs it.
///
/// `transition` is `Φ` from the previous epoch into this one (the identity
/// at the first epoch, which has no predict); the prior is the estimate
/// after the predict, the posterior after the epoch's updates (equal to the
/// prior when there were none).
///
/// ```
/// use kestrel_core::smoother::RtsEpoch;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let e = RtsEpoch::initial(Vector2::new(1.0, 2.0), Matrix2::identity());
/// assert_eq!(e.transition, Matrix2::identity());
/// assert_eq!(e.prior_state, e.posterior_state);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RtsEpoch<T: Real, const N: usize> {
    /// `Φ` from the previous epoch into this one.
    pub transition: SMatrix<T, N, N>,
    /// `x⁻`: the state after the predict into this epoch.
    pub prior_state: SVector<T, N>,
    /// `P⁻`: the covariance after the predict (including any fading).
    pub prior_covariance: SMatrix<T, N, N>,
    /// `x⁺`: the state after this epoch's updates.
    pub posterior_state: SVector<T, N>,
    /// `P⁺`: the covariance after this epoch's updates.
    pub posterior_covariance: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> RtsEpoch<T, N> {
    /// The first epoch: the initial estimate, no transition into it.
    pub fn initial(x: SVector<T, N>, p: SMatrix<T, N, N>) -> Self {
        Self::predicted(SMatrix::identity(), x, p)
    }

    /// An epoch reached by a predict with transition `transition`, before any
    /// update (its posterior is its prior until
    /// [`set_posterior`](Self::set_posterior)).
    ///
    /// ```
    /// use kestrel_core::smoother::RtsEpoch;
    /// use kestrel_core::nalgebra::{Matrix1, Vector1};
    /// let mut e = RtsEpoch::predicted(Matrix1::new(0.5), Vector1::new(1.0), Matrix1::new(2.0));
    /// e.set_posterior(Vector1::new(1.5), Matrix1::new(1.0));
    /// assert_eq!((e.prior_state[0], e.posterior_state[0]), (1.0, 1.5));
    /// ```
    pub fn predicted(transition: SMatrix<T, N, N>, x: SVector<T, N>, p: SMatrix<T, N, N>) -> Self {
        Self {
            transition,
            prior_state: x,
            prior_covariance: p,
            posterior_state: x,
            posterior_covariance: p,
        }
    }

    /// Sets the estimate after this epoch's updates.
    pub fn set_posterior(&mut self, x: SVector<T, N>, p: SMatrix<T, N, N>) {
        self.posterior_state = x;
        self.posterior_covariance = p;
    }
}

impl<T: Real, const N: usize> Default for RtsEpoch<T, N> {
    /// A zero state with zero covariance (storage to be overwritten).
    fn default() -> Self {
        Self::initial(SVector::zeros(), SMatrix::zeros())
    }
}

/// A smoothed estimate: the state and covariance given every epoch of the
/// record.
///
/// ```
/// use kestrel_core::smoother::Smoothed;
/// let s = Smoothed::<f64, 2>::default();
/// assert_eq!(s.state.len(), 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smoothed<T: Real, const N: usize> {
    /// `xˢ`.
    pub state: SVector<T, N>,
    /// `Pˢ` (exactly symmetric).
    pub covariance: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> Smoothed<T, N> {
    /// The smoothed estimate of the last epoch: its posterior.
    pub fn last(epoch: &RtsEpoch<T, N>) -> Self {
        Self {
            state: epoch.posterior_state,
            covariance: epoch.posterior_covariance,
        }
    }
}

impl<T: Real, const N: usize> Default for Smoothed<T, N> {
    /// A zero state with zero covariance (storage to be overwritten).
    fn default() -> Self {
        Self {
            state: SVector::zeros(),
            covariance: SMatrix::zeros(),
        }
    }
}
