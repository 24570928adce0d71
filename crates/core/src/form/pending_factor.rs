//! A covariance factor with a prediction pending its update.

use nalgebra::{SMatrix, SVector};

use super::double_buffer::DoubleBuffer;
use super::FadeStates;
use crate::linalg::add_columns;
use crate::Real;

/// The covariance of the square-root form, as lower Cholesky factors: after
/// a predict that an adapter may still fade at the update, it holds the
/// factor `S` of the propagated part and the factor `S_Q` of the process
/// noise apart; the prior with a fade `λ` is `D S Sᵀ D + S_Q S_Qᵀ`
/// (`D = √λ` on the faded states). A fade at the predict is already in `S`.
///
/// The factor has two buffers, as [`PendingCovariance`] has: a step writes
/// the next factor into the spare buffer, checks it, and only then makes it
/// current.
///
/// [`PendingCovariance`]: super::pending::PendingCovariance
#[derive(Debug, Clone)]
pub(crate) struct PendingFactor<T: Real, const N: usize> {
    /// Factor of the posterior, or of the propagated part while a
    /// prediction is pending (the current buffer), and the spare buffer.
    buffers: DoubleBuffer<T, N>,
    /// Factor of the pending process noise; zero when nothing is pending.
    sq: SMatrix<T, N, N>,
    pending: bool,
    /// The states a fade scales.
    states: FadeStates<N>,
}

impl<T: Real, const N: usize> PendingFactor<T, N> {
    /// The factor `s` of a posterior; nothing pending.
    pub fn new(s: SMatrix<T, N, N>) -> Self {
        Self {
            buffers: DoubleBuffer::new(s),
            sq: SMatrix::zeros(),
            pending: false,
            states: FadeStates::all(),
        }
    }

    /// What the factor of the covariance is made of, borrowed.
    pub fn view(&self) -> FactorView<'_, T, N> {
        FactorView {
            s: self.buffers.current(),
            sq: &self.sq,
            pending: self.pending,
            states: &self.states,
        }
    }

    /// The borrowed view and the spare buffer at once: a step reads the one
    /// and writes the next factor into the other.
    pub fn view_and_spare(&mut self) -> (FactorView<'_, T, N>, &mut SMatrix<T, N, N>) {
        let (s, spare) = self.buffers.current_and_spare();
        let view = FactorView {
            s,
            sq: &self.sq,
            pending: self.pending,
            states: &self.states,
        };
        (view, spare)
    }

    /// The states a fade scales.
    pub fn fade_states(&self) -> FadeStates<N> {
        self.states
    }

    /// The spare buffer, to write the next factor into.
    pub fn spare(&mut self) -> &mut SMatrix<T, N, N> {
        self.buffers.spare()
    }

    /// Selects the states a fade scales.
    pub fn set_fade_states(&mut self, states: FadeStates<N>) {
        self.states = states;
    }

    /// Replaces the factor by `s`, a posterior's; nothing is pending.
    pub fn commit(&mut self, s: SMatrix<T, N, N>) {
        *self.buffers.spare() = s;
        self.commit_spare();
    }

    /// Makes the spare buffer, which holds a posterior's factor, current;
    /// nothing is pending.
    pub fn commit_spare(&mut self) {
        self.buffers.swap();
        // `sq` is only read while a prediction is pending, and is zero
        // otherwise: cleared only if it was set (not `N × N` stores a step).
        if self.pending {
            self.sq = SMatrix::zeros();
        }
        self.pending = false;
    }

    /// Records a prediction whose propagated part's factor is in the spare
    /// buffer, with `sq` the factor of its process noise.
    pub fn predicted_spare(&mut self, sq: &SMatrix<T, N, N>) {
        self.buffers.swap();
        self.sq = *sq;
        self.pending = true;
    }

    /// `(G_P G_Pᵀ, G_Q G_Qᵀ)` with `G_P = h S` and `G_Q = h S_Q`: the
    /// propagated part and the process noise of `h P⁻ hᵀ` apart; `None`
    /// when nothing is pending.
    pub fn split<const M: usize>(
        &self,
        h: &SMatrix<T, M, N>,
    ) -> Option<(SMatrix<T, M, M>, SMatrix<T, M, M>)> {
        if !self.pending {
            return None;
        }
        let gp = h * self.buffers.current();
        let gq = h * self.sq;
        Some((gp * gp.transpose(), gq * gq.transpose()))
    }
}

/// Equal when they represent the same covariance: `sq` matters only while
/// a prediction is pending, and the spare buffer never.
impl<T: Real, const N: usize> PartialEq for PendingFactor<T, N> {
    fn eq(&self, other: &Self) -> bool {
        self.buffers.current() == other.buffers.current()
            && self.pending == other.pending
            && self.states == other.states
            && (!self.pending || self.sq == other.sq)
    }
}

/// What the factor of a [`PendingFactor`] is made of, borrowed apart from
/// its spare buffer.
#[derive(Clone, Copy)]
pub(crate) struct FactorView<'a, T: Real, const N: usize> {
    /// The current buffer.
    s: &'a SMatrix<T, N, N>,
    sq: &'a SMatrix<T, N, N>,
    pending: bool,
    states: &'a FadeStates<N>,
}

impl<T: Real, const N: usize> FactorView<'_, T, N> {
    /// Factor of `D S Sᵀ D + S_Q S_Qᵀ` (`D = √λ` on the faded states) for
    /// a fade `λ`.
    pub fn merged(&self, lambda: T) -> SMatrix<T, N, N> {
        if !self.pending {
            return if lambda == T::one() {
                *self.s
            } else {
                self.states.scale_rows(self.s, lambda)
            };
        }
        let mut s = self.states.scale_rows(self.s, lambda);
        let mut cols: [SVector<T, N>; N] = core::array::from_fn(|i| self.sq.column(i).into_owned());
        add_columns(&mut s, &mut cols);
        s
    }

    /// The factor of the covariance: `S` itself, borrowed (no copy), unless
    /// a prediction is pending; then the merged factor, kept in `merged`.
    pub fn current<'b>(&'b self, merged: &'b mut Option<SMatrix<T, N, N>>) -> &'b SMatrix<T, N, N> {
        if self.pending {
            merged.insert(self.merged(T::one()))
        } else {
            self.s
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Matrix2;

    use super::*;

    #[test]
    fn a_pending_factor_merges_the_process_noise_and_commits_through_the_spare_buffer() {
        let s0 = Matrix2::new(2.0, 0.0, 1.0, 3.0);
        let mut factor = PendingFactor::new(s0);
        let mut merged = None;
        assert_eq!(factor.view().current(&mut merged), &s0);
        assert!(merged.is_none(), "nothing pending: borrowed, not merged");
        // Written but not committed (a step that failed its checks): the
        // factor is unchanged.
        *factor.spare() = Matrix2::from_element(f64::NAN);
        assert_eq!(factor, PendingFactor::new(s0));
        // A prediction: the propagated factor in the spare buffer, `S_Q` apart.
        let sq = Matrix2::new(0.5, 0.0, 0.0, 0.25);
        let (view, spare) = factor.view_and_spare();
        *spare = view.merged(1.0) * 2.0;
        factor.predicted_spare(&sq);
        // The merged factor's product is `S Sᵀ + S_Q S_Qᵀ`.
        let p = (s0 * 2.0) * (s0 * 2.0).transpose() + sq * sq.transpose();
        let l = factor.view().merged(1.0);
        approx::assert_relative_eq!(l * l.transpose(), p, epsilon = 1e-12);
        assert_eq!(factor.view().current(&mut merged), &l);
        // A fade of 4 doubles the propagated factor's part.
        let p4 = (s0 * 4.0) * (s0 * 4.0).transpose() + sq * sq.transpose();
        let l4 = factor.view().merged(4.0);
        approx::assert_relative_eq!(l4 * l4.transpose(), p4, epsilon = 1e-12);
        // The split of `h P⁻ hᵀ` for `h = [1 1]`.
        let h = nalgebra::RowVector2::new(1.0, 1.0);
        let (propagated, noise) = factor.split(&h).unwrap();
        approx::assert_relative_eq!(propagated[0], (h * (s0 * 2.0)).norm_squared());
        approx::assert_relative_eq!(noise[0], 0.5 * 0.5 + 0.25 * 0.25);
        // Committed: nothing pending, `S_Q` cleared, no split.
        factor.commit(l);
        assert_eq!(factor.view().merged(1.0), l);
        assert!(factor.split(&h).is_none());
        assert_eq!(factor, PendingFactor::new(l));
    }
}
