//! A covariance with a prediction pending its update.

use nalgebra::SMatrix;

use super::FadeStates;
use crate::linalg::sandwich;
use crate::Real;

/// The covariance of the covariance and unscented forms: after a predict it
/// holds the propagated part `Φ P Φᵀ`, the process noise `Q` and a fade `λ`
/// apart, so an adapter can still fade the propagated part at the update;
/// the prior is `λ Φ P Φᵀ + Q`.
#[derive(Debug, Clone)]
pub(crate) struct PendingCovariance<T: Real, const N: usize> {
    /// The posterior, or the propagated part while a prediction is pending.
    p: SMatrix<T, N, N>,
    /// The pending process noise.
    q: SMatrix<T, N, N>,
    /// The pending fade of `p` from the after-predict hook.
    fade: T,
    pending: bool,
    /// The states a fade scales.
    states: FadeStates<N>,
}

impl<T: Real, const N: usize> PendingCovariance<T, N> {
    /// A posterior covariance `p` (taken as symmetric).
    pub fn new(p: SMatrix<T, N, N>) -> Self {
        Self {
            p,
            q: SMatrix::zeros(),
            fade: T::one(),
            pending: false,
            states: FadeStates::all(),
        }
    }

    /// The process noise of the last prediction (zero before the first):
    /// it passed the input contract, so an equal `Q` need not be checked
    /// again.
    pub fn noise(&self) -> &SMatrix<T, N, N> {
        &self.q
    }

    /// The states a fade scales.
    pub fn fade_states(&self) -> FadeStates<N> {
        self.states
    }

    /// Selects the states a fade scales.
    pub fn set_fade_states(&mut self, states: FadeStates<N>) {
        self.states = states;
    }

    /// `D Φ P Φᵀ D + Q` (`λ_total Φ P Φᵀ + Q` when every state fades) for
    /// an extra fade `extra` on top of the pending one.
    pub fn prior(&self, extra: T) -> SMatrix<T, N, N> {
        if self.pending {
            let lambda = self.fade * extra;
            if lambda == T::one() {
                self.p + self.q
            } else {
                self.states.scale_symmetric(&self.p, lambda) + self.q
            }
        } else if extra == T::one() {
            self.p
        } else {
            self.states.scale_symmetric(&self.p, extra)
        }
    }

    /// The fade applied to the propagated part with an extra fade `extra`.
    /// The posterior itself, when no prediction is pending (no copy).
    pub fn committed(&self) -> Option<&SMatrix<T, N, N>> {
        (!self.pending).then_some(&self.p)
    }

    pub fn total_fade(&self, extra: T) -> T {
        if self.pending {
            self.fade * extra
        } else {
            extra
        }
    }

    /// Replaces the covariance by the posterior `p`; nothing is pending.
    /// (`q` is only read while a prediction is pending, so it is left as is
    /// rather than cleared: this runs on every update.)
    pub fn commit(&mut self, p: SMatrix<T, N, N>) {
        self.p = p;
        self.fade = T::one();
        self.pending = false;
    }

    /// Records a prediction: propagated part, process noise and fade.
    pub fn predicted(&mut self, propagated: SMatrix<T, N, N>, q: SMatrix<T, N, N>, fade: T) {
        self.p = propagated;
        self.q = q;
        self.fade = fade;
        self.pending = true;
    }

    /// `(H Φ P Φᵀ Hᵀ · λ, H Q Hᵀ)` for a (possibly statistically linearised)
    /// measurement matrix `h`; without a pending prediction all of
    /// `predicted` is propagated.
    pub fn split<const M: usize>(
        &self,
        h: Option<&SMatrix<T, M, N>>,
        predicted: &SMatrix<T, M, M>,
    ) -> (SMatrix<T, M, M>, SMatrix<T, M, M>) {
        match h {
            Some(h) if self.pending && self.states.is_all() => {
                (sandwich(h, &self.p) * self.fade, sandwich(h, &self.q))
            }
            Some(h) if self.pending => (
                sandwich(h, &self.states.scale_symmetric(&self.p, self.fade)),
                sandwich(h, &self.q),
            ),
            _ => (*predicted, SMatrix::zeros()),
        }
    }
}

/// Equal when they represent the same covariance state: `q` and the fade
/// matter only while a prediction is pending.
impl<T: Real, const N: usize> PartialEq for PendingCovariance<T, N> {
    fn eq(&self, other: &Self) -> bool {
        self.p == other.p
            && self.pending == other.pending
            && self.states == other.states
            && (!self.pending || (self.q == other.q && self.fade == other.fade))
    }
}
