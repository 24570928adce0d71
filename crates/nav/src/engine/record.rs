//! What the engine's forward pass leaves for a smoother: per covariance
//! epoch, the transition, the prior and posterior covariances and the
//! error state fed back.

use kestrel_core::smoother::RtsEpoch;
use kestrel_core::Real;
use nalgebra::{SMatrix, SVector};

use crate::earth::Ellipsoid;
use crate::error_model::ForcingMean;
use crate::state::NavState;

/// One covariance epoch of the closed-loop error-state filter: the
/// covariance propagation at the IMU sample at `time` and the updates at
/// that sample.
///
/// The error state is zero before every propagation (it is reset after
/// each feedback), so the prior error state is zero and the posterior is
/// the sum of the error states fed back at this epoch, relative to the
/// solution the mechanisation reached at `time` before any feedback. In
/// those coordinates the closed-loop record is an ordinary RTS record
/// ([`rts`](Self::rts)): the smoothed error state `xˢ` of the epoch
/// corrects the solution before feedback, and `xˢ − feedback` the solution
/// after it (to first order, the feedback being additive in the error
/// state).
///
/// ```
/// use kestrel_nav::engine::ForwardEpoch;
/// use kestrel_nav::nalgebra::{SMatrix, SVector};
/// let e = ForwardEpoch::<f64, 15>::initial(0.0, SMatrix::identity());
/// assert_eq!(e.rts().prior_state, SVector::<f64, 15>::zeros());
/// assert_eq!(e.feedback, SVector::<f64, 15>::zeros());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForwardEpoch<T: Real, const N: usize> {
    /// Time of the IMU sample, s.
    pub time: f64,
    /// `Φ` from the previous epoch (identity at the first).
    pub transition: SMatrix<T, N, N>,
    /// `P⁻` after the propagation.
    pub prior_covariance: SMatrix<T, N, N>,
    /// The error states fed back at this epoch, summed.
    pub feedback: SVector<T, N>,
    /// `P⁺` after the epoch's updates (`P⁻` without one).
    pub posterior_covariance: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> ForwardEpoch<T, N> {
    /// The first epoch: covariance `p` at `time`, nothing fed back.
    pub fn initial(time: f64, p: SMatrix<T, N, N>) -> Self {
        Self::propagated(time, SMatrix::identity(), p)
    }

    /// An epoch after a propagation with `transition`, before any update.
    pub fn propagated(time: f64, transition: SMatrix<T, N, N>, p: SMatrix<T, N, N>) -> Self {
        Self {
            time,
            transition,
            prior_covariance: p,
            feedback: SVector::zeros(),
            posterior_covariance: p,
        }
    }

    /// The epoch as an RTS record entry: prior state zero, posterior state
    /// the feedback.
    pub fn rts(&self) -> RtsEpoch<T, N> {
        let mut e = RtsEpoch::predicted(self.transition, SVector::zeros(), self.prior_covariance);
        e.set_posterior(self.feedback, self.posterior_covariance);
        e
    }
}

/// `Φ` of the system's process model over the interval `forcing`
/// summarises, evaluated at the error state `x`.
pub(crate) type TransitionOf<S, T, const N: usize> =
    fn(&S, &Ellipsoid, &NavState, &ForcingMean, &SVector<T, N>, T) -> SMatrix<T, N, N>;

/// The engine's recording: the epoch still open and the last one closed.
#[derive(Clone, Debug)]
pub(crate) struct Recording<S, T: Real, const N: usize> {
    pub transition: TransitionOf<S, T, N>,
    pub open: ForwardEpoch<T, N>,
    pub closed: Option<ForwardEpoch<T, N>>,
    /// Epochs closed while the previous one was still untaken.
    pub overrun: usize,
}

impl<S, T: Real, const N: usize> Recording<S, T, N> {
    /// Opens `next`, closing the open epoch.
    pub fn open(&mut self, next: ForwardEpoch<T, N>) {
        let done = core::mem::replace(&mut self.open, next);
        if self.closed.replace(done).is_some() {
            self.overrun += 1;
        }
    }
}
