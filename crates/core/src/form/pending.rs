//! A covariance with a prediction pending its update.

use nalgebra::SMatrix;

use super::double_buffer::DoubleBuffer;
use super::FadeStates;
use crate::linalg::sandwich;
use crate::Real;

/// The covariance of the covariance and unscented forms: after a predict it
/// holds the propagated part `Φ P Φᵀ`, the process noise `Q` and a fade `λ`
/// apart, so an adapter can still fade the propagated part at the update;
/// the prior is `λ Φ P Φᵀ + Q`.
///
/// The covariance has two buffers: a form writes the next one into the
/// spare buffer, checks it, and only then makes it current, so a rejected
/// step leaves the covariance as it was without a copy of `N × N` values
/// either way.
#[derive(Clone)]
pub(crate) struct PendingCovariance<T: Real, const N: usize> {
    /// The posterior, or the propagated part while a prediction is pending
    /// (the current buffer), and the spare buffer.
    buffers: DoubleBuffer<T, N>,
    /// The pending process noise.
    q: SMatrix<T, N, N>,
    /// The pending fade of `p` from the after-predict hook.
    fade: T,
    pending: bool,
    /// The states a fade scales.
    states: FadeStates<N>,
}

impl<T: Real, const N: usize> core::fmt::Debug for PendingCovariance<T, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PendingCovariance")
            .field("p", self.p())
            .field("q", &self.q)
            .field("fade", &self.fade)
            .field("pending", &self.pending)
            .field("states", &self.states)
            .finish()
    }
}

impl<T: Real, const N: usize> PendingCovariance<T, N> {
    /// A posterior covariance `p` (taken as symmetric).
    pub fn new(p: SMatrix<T, N, N>) -> Self {
        Self {
            buffers: DoubleBuffer::new(p),
            q: SMatrix::zeros(),
            fade: T::one(),
            pending: false,
            states: FadeStates::all(),
        }
    }

    /// The current buffer.
    fn p(&self) -> &SMatrix<T, N, N> {
        self.buffers.current()
    }

    /// The current buffer (read) and the spare one (to write), for a
    /// result computed from the current covariance.
    pub fn current_and_spare(&mut self) -> (&SMatrix<T, N, N>, &mut SMatrix<T, N, N>) {
        self.buffers.current_and_spare()
    }

    /// The spare buffer, to write the next covariance into.
    pub fn spare(&mut self) -> &mut SMatrix<T, N, N> {
        self.buffers.spare()
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
        self.view().prior(extra)
    }

    /// Whether a prediction is pending (the current buffer holds the
    /// propagated part, not the posterior).
    pub fn is_pending(&self) -> bool {
        self.pending
    }

    /// The fade applied to the propagated part with an extra fade `extra`.
    pub fn total_fade(&self, extra: T) -> T {
        self.view().total_fade(extra)
    }

    /// Replaces the covariance by the posterior `p`; nothing is pending.
    /// (`q` is only read while a prediction is pending, so it is left as is
    /// rather than cleared: this runs on every update.)
    pub fn commit(&mut self, p: SMatrix<T, N, N>) {
        *self.spare() = p;
        self.commit_spare();
    }

    /// Makes the spare buffer, which holds the posterior, current; nothing
    /// is pending.
    pub fn commit_spare(&mut self) {
        self.buffers.swap();
        self.fade = T::one();
        self.pending = false;
    }

    /// Records a prediction whose propagated part is in the spare buffer,
    /// with process noise `q` (`None`: the same as the last prediction's)
    /// and fade `fade`.
    pub fn predicted_spare(&mut self, q: Option<&SMatrix<T, N, N>>, fade: T) {
        self.buffers.swap();
        if let Some(q) = q {
            self.q = *q;
        }
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
        self.view().split(h, predicted)
    }

    /// What [`prior`](Self::prior), [`split`](Self::split) and
    /// [`total_fade`](Self::total_fade) read, borrowed.
    fn view(&self) -> PendingView<'_, T, N> {
        PendingView {
            p: self.p(),
            q: &self.q,
            fade: self.fade,
            pending: self.pending,
            states: &self.states,
        }
    }

    /// The borrowed view and the spare buffer at once, so that an update
    /// can keep a lazily computed split (which reads the view) alive while
    /// it writes the posterior into the spare buffer.
    pub fn view_and_spare(&mut self) -> (PendingView<'_, T, N>, &mut SMatrix<T, N, N>) {
        let (p, spare) = self.buffers.current_and_spare();
        let view = PendingView {
            p,
            q: &self.q,
            fade: self.fade,
            pending: self.pending,
            states: &self.states,
        };
        (view, spare)
    }
}

/// What the prior, the fading split and the total fade of a
/// [`PendingCovariance`] are computed from, borrowed apart from its spare
/// buffer.
#[derive(Clone, Copy)]
pub(crate) struct PendingView<'a, T: Real, const N: usize> {
    /// The current buffer.
    p: &'a SMatrix<T, N, N>,
    q: &'a SMatrix<T, N, N>,
    fade: T,
    pending: bool,
    states: &'a FadeStates<N>,
}

impl<T: Real, const N: usize> PendingView<'_, T, N> {
    /// See [`PendingCovariance::prior`]. Always inlined: on the step's path
    /// `extra` is the constant 1 and the fade's branches fold away; left
    /// to itself the compiler keeps it out of line in builds where the
    /// adapter path calls it too.
    #[inline(always)]
    pub fn prior(&self, extra: T) -> SMatrix<T, N, N> {
        if self.pending {
            let lambda = self.fade * extra;
            if lambda == T::one() {
                // Element by element into the result (nalgebra's `+`
                // returns through a temporary and a copy).
                let (p, q) = (self.p, self.q);
                SMatrix::from_fn(|i, j| p[(i, j)] + q[(i, j)])
            } else {
                self.states.scale_symmetric(self.p, lambda) + *self.q
            }
        } else if extra == T::one() {
            *self.p
        } else {
            self.states.scale_symmetric(self.p, extra)
        }
    }

    /// See [`PendingCovariance::total_fade`].
    pub fn total_fade(&self, extra: T) -> T {
        if self.pending {
            self.fade * extra
        } else {
            extra
        }
    }

    /// See [`PendingCovariance::split`].
    pub fn split<const M: usize>(
        &self,
        h: Option<&SMatrix<T, M, N>>,
        predicted: &SMatrix<T, M, M>,
    ) -> (SMatrix<T, M, M>, SMatrix<T, M, M>) {
        match h {
            Some(h) if self.pending && self.states.is_all() => {
                (sandwich(h, self.p) * self.fade, sandwich(h, self.q))
            }
            Some(h) if self.pending => (
                sandwich(h, &self.states.scale_symmetric(self.p, self.fade)),
                sandwich(h, self.q),
            ),
            _ => (*predicted, SMatrix::zeros()),
        }
    }
}

/// Equal when they represent the same covariance state: `q` and the fade
/// matter only while a prediction is pending.
impl<T: Real, const N: usize> PartialEq for PendingCovariance<T, N> {
    fn eq(&self, other: &Self) -> bool {
        self.p() == other.p()
            && self.pending == other.pending
            && self.states == other.states
            && (!self.pending || (self.q == other.q && self.fade == other.fade))
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Matrix2;

    use super::*;

    #[test]
    fn the_spare_buffer_becomes_current_only_when_committed() {
        let p0 = Matrix2::new(2.0, 0.5, 0.5, 1.0);
        let mut cov = PendingCovariance::new(p0);
        // Written but not committed (a step that failed its checks): the
        // covariance is unchanged.
        *cov.spare() = Matrix2::from_element(f64::NAN);
        assert_eq!(cov.prior(1.0), p0);
        assert_eq!(cov, PendingCovariance::new(p0));
        // A prediction from the spare buffer, with a new Q, then one that
        // keeps it.
        let q = Matrix2::new(0.1, 0.0, 0.0, 0.2);
        let (current, spare) = cov.current_and_spare();
        *spare = current * 2.0;
        cov.predicted_spare(Some(&q), 1.0);
        assert!(cov.is_pending());
        assert_eq!(cov.prior(1.0), p0 * 2.0 + q);
        let (current, spare) = cov.current_and_spare();
        *spare = current * 3.0;
        cov.predicted_spare(None, 1.0);
        assert_eq!(cov.prior(1.0), p0 * 6.0 + q);
        assert_eq!(cov.noise(), &q);
        // Committed through the spare buffer and by value.
        *cov.spare() = p0;
        cov.commit_spare();
        assert!(!cov.is_pending());
        assert_eq!(cov.prior(1.0), p0);
        cov.commit(p0 * 4.0);
        assert_eq!(cov.prior(1.0), p0 * 4.0);
    }
}
