//! A forward-pass record in caller-provided storage.

use super::{rts_step, RtsEpoch, Smoothed, SmootherError};
use crate::form::{CovarianceForm, Form};
use crate::{Ekf, Euclidean, Filter, LinearizedProcess, Real, StateSpace};

/// The epochs of a covariance-form filter's forward pass, written into a
/// slice the caller owns (nothing is allocated), and their RTS smoothing.
///
/// Use: [`start`](Self::start) with the initial filter, then for every
/// epoch [`predict`](Self::predict) through the record (it evaluates `Φ`
/// at the state before the predict, as the filter does, and stores the
/// prior), run the epoch's updates on the filter, and
/// [`observe`](Self::observe) the result. [`smooth`](Self::smooth) runs the
/// backward pass. See the [module](super) for an example.
#[derive(Debug)]
pub struct RtsRecord<'s, T: Real, const N: usize> {
    epochs: &'s mut [RtsEpoch<T, N>],
    len: usize,
}

impl<'s, T: Real, const N: usize> RtsRecord<'s, T, N> {
    /// An empty record writing into `storage` (its capacity).
    pub fn new(storage: &'s mut [RtsEpoch<T, N>]) -> Self {
        Self {
            epochs: storage,
            len: 0,
        }
    }

    /// Epochs recorded.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether nothing is recorded.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Epochs the storage holds.
    pub fn capacity(&self) -> usize {
        self.epochs.len()
    }

    /// The recorded epochs.
    pub fn epochs(&self) -> &[RtsEpoch<T, N>] {
        &self.epochs[..self.len]
    }

    /// Clears the record and stores `filter`'s estimate as the first epoch.
    ///
    /// # Errors
    /// [`SmootherError::Full`] for empty storage.
    pub fn start<F: Form<T, N>, A, S: StateSpace<T, N>>(
        &mut self,
        filter: &Filter<T, N, F, A, S>,
    ) -> Result<(), SmootherError> {
        self.len = 0;
        self.push(RtsEpoch::initial(*filter.state(), filter.covariance()))
    }

    /// Appends an epoch built by the caller (for a forward pass that does
    /// not go through [`predict`](Self::predict)).
    ///
    /// # Errors
    /// [`SmootherError::Full`] when the storage is full.
    pub fn push(&mut self, epoch: RtsEpoch<T, N>) -> Result<(), SmootherError> {
        let capacity = self.epochs.len();
        let slot = self
            .epochs
            .get_mut(self.len)
            .ok_or(SmootherError::Full { capacity })?;
        *slot = epoch;
        self.len += 1;
        Ok(())
    }

    /// Predicts `filter` over `dt` with `model` and records the new epoch:
    /// `Φ = model.transition(x, dt)` at the state before the predict and
    /// the prior after it.
    ///
    /// # Errors
    /// [`SmootherError::NotStarted`] before [`start`](Self::start),
    /// [`SmootherError::Full`] with no room (both before the filter is
    /// touched), or the filter's own [`SmootherError::Filter`] (the filter
    /// and the record unchanged).
    pub fn predict<P, A, S>(
        &mut self,
        filter: &mut Ekf<T, N, A, S>,
        model: &P,
        dt: T,
    ) -> Result<(), SmootherError>
    where
        P: LinearizedProcess<T, N>,
        CovarianceForm<T, N>: crate::form::PredictForm<T, N, P>,
        A: crate::adapter::PriorAdapter<T>,
        S: StateSpace<T, N>,
    {
        if self.is_empty() {
            return Err(SmootherError::NotStarted);
        }
        if self.len == self.epochs.len() {
            return Err(SmootherError::Full {
                capacity: self.epochs.len(),
            });
        }
        let transition = model.transition(filter.state(), dt);
        filter.predict(model, dt)?;
        self.push(RtsEpoch::predicted(
            transition,
            *filter.state(),
            filter.covariance(),
        ))
    }

    /// Stores `filter`'s estimate as the latest epoch's posterior (call after
    /// the epoch's updates; an epoch without updates needs no call).
    ///
    /// # Errors
    /// [`SmootherError::NotStarted`] before [`start`](Self::start).
    pub fn observe<F: Form<T, N>, A, S: StateSpace<T, N>>(
        &mut self,
        filter: &Filter<T, N, F, A, S>,
    ) -> Result<(), SmootherError> {
        let last = self.len.checked_sub(1).ok_or(SmootherError::NotStarted)?;
        self.epochs[last].set_posterior(*filter.state(), filter.covariance());
        Ok(())
    }

    /// The backward pass with ordinary vector arithmetic: `out[k]` receives
    /// the smoothed estimate of epoch `k` (the last epoch's is its
    /// posterior).
    ///
    /// # Errors
    /// [`SmootherError::OutputTooShort`], or [`SmootherError::Backward`]
    /// with the epoch where [`rts_step`] failed (`out` is then partly
    /// written, from the end).
    pub fn smooth(&self, out: &mut [Smoothed<T, N>]) -> Result<(), SmootherError> {
        self.smooth_in(&Euclidean, out)
    }

    /// [`smooth`](Self::smooth) with the state arithmetic `space` (the
    /// filter's [`state_space`](crate::Filter::state_space)).
    ///
    /// # Errors
    /// As [`smooth`](Self::smooth).
    pub fn smooth_in<S: StateSpace<T, N>>(
        &self,
        space: &S,
        out: &mut [Smoothed<T, N>],
    ) -> Result<(), SmootherError> {
        let epochs = self.epochs();
        let Some(last) = epochs.last() else {
            return Ok(());
        };
        if out.len() < epochs.len() {
            return Err(SmootherError::OutputTooShort {
                needed: epochs.len(),
                given: out.len(),
            });
        }
        let n = epochs.len();
        out[n - 1] = Smoothed::last(last);
        for k in (0..n - 1).rev() {
            out[k] = rts_step(space, &epochs[k], &epochs[k + 1], &out[k + 1])
                .map_err(|error| SmootherError::Backward { epoch: k, error })?;
        }
        Ok(())
    }
}
