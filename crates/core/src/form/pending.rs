//! A form's covariance with a prediction pending its update: dense `P` or
//! a Cholesky factor of it, in one type.

use core::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use super::double_buffer::DoubleBuffer;
use super::FadeStates;
use crate::contract::{check_covariance, check_noise_cached};
use crate::linalg::{add_columns, mirror_lower, sandwich};
use crate::{FilterError, Quantity, Real};

/// How a form stores its covariance: what the current buffer and the
/// pending noise hold, and how the prior is made from them.
pub(crate) trait Storage<T: Real, const N: usize>: Sized {
    /// The name [`Pending`]'s `Debug` output gives.
    const NAME: &'static str;

    /// Whether the pending noise is cleared when a posterior is committed:
    /// the factor of `Q` is zero while nothing is pending, the dense `Q`
    /// stays as the last one checked (the next prediction compares with it).
    const CLEARS_NOISE: bool;

    /// The prior with an extra fade `extra` on top of any pending one.
    fn prior(view: &PendingView<'_, T, N, Self>, extra: T) -> SMatrix<T, N, N>;

    /// What the current buffer holds for the posterior covariance `p`,
    /// after the input checks.
    fn checked(p: &SMatrix<T, N, N>) -> Result<SMatrix<T, N, N>, FilterError>;

    /// The prior at no extra fade where the current buffer holds it (no
    /// copy, no computation): the factor's while nothing is pending.
    fn borrowed<'b>(view: &PendingView<'b, T, N, Self>) -> Option<&'b SMatrix<T, N, N>>;
}

/// Dense storage (the covariance and unscented forms): the current buffer
/// holds `P`, or the propagated part `Φ P Φᵀ` while a prediction is
/// pending, and the pending noise is `Q`; the prior is `λ Φ P Φᵀ + Q`
/// (`D Φ P Φᵀ D + Q` for a block fade).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Dense;

/// Factor storage (the square-root form): the current buffer holds the
/// lower Cholesky factor `S` of the posterior, or of the propagated part
/// while a prediction is pending, and the pending noise is the factor
/// `S_Q` of `Q`; the prior with a fade `λ` is `D S Sᵀ D + S_Q S_Qᵀ`
/// (`D = √λ` on the faded states). A fade at the predict is already in `S`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Factor;

/// The covariance of the covariance and unscented forms.
pub(crate) type PendingCovariance<T, const N: usize> = Pending<T, N, Dense>;

/// The covariance factor of the square-root form.
pub(crate) type PendingFactor<T, const N: usize> = Pending<T, N, Factor>;

/// A covariance (or its factor) with a prediction pending its update: the
/// propagated part, the process noise and the fade apart, so an adapter
/// can still fade the propagated part at the update.
///
/// It has two buffers: a form writes the next covariance (or factor) into
/// the spare buffer, checks it, and only then makes it current, so a
/// rejected step leaves it as it was without a copy of `N × N` values
/// either way.
#[derive(Clone)]
pub(crate) struct Pending<T: Real, const N: usize, K> {
    /// The posterior, or the propagated part while a prediction is pending
    /// (the current buffer), and the spare buffer.
    buffers: DoubleBuffer<T, N>,
    /// The pending process noise (see [`Storage::CLEARS_NOISE`]).
    noise: SMatrix<T, N, N>,
    /// The fade of the prediction: pending in the dense storage, already
    /// in the factor (kept for the report) in the factor storage; 1 after
    /// an update.
    fade: T,
    pending: bool,
    /// The states a fade scales.
    states: FadeStates<N>,
    kind: PhantomData<K>,
}

impl<T: Real, const N: usize, K: Storage<T, N>> core::fmt::Debug for Pending<T, N, K> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct(K::NAME)
            .field("p", self.buffers.current())
            .field("noise", &self.noise)
            .field("fade", &self.fade)
            .field("pending", &self.pending)
            .field("states", &self.states)
            .finish()
    }
}

impl<T: Real, const N: usize, K: Storage<T, N>> Pending<T, N, K> {
    /// The posterior `p` (taken as symmetric) or its factor; nothing
    /// pending.
    pub fn new(p: SMatrix<T, N, N>) -> Self {
        Self {
            buffers: DoubleBuffer::new(p),
            noise: SMatrix::zeros(),
            fade: T::one(),
            pending: false,
            states: FadeStates::all(),
            kind: PhantomData,
        }
    }
}

impl<T: Real, const N: usize, K: Storage<T, N>> Pending<T, N, K> {
    /// The current buffer (read) and the spare one (to write), for a
    /// result computed from the current value.
    pub fn current_and_spare(&mut self) -> (&SMatrix<T, N, N>, &mut SMatrix<T, N, N>) {
        self.buffers.current_and_spare()
    }

    /// The spare buffer, to write the next value into.
    pub fn spare(&mut self) -> &mut SMatrix<T, N, N> {
        self.buffers.spare()
    }

    /// The states a fade scales.
    pub fn fade_states(&self) -> FadeStates<N> {
        self.states
    }

    /// Selects the states a fade scales.
    pub fn set_fade_states(&mut self, states: FadeStates<N>) {
        self.states = states;
    }

    /// Whether a prediction is pending (the current buffer holds the
    /// propagated part, not the posterior).
    pub fn is_pending(&self) -> bool {
        self.pending
    }

    /// The prior (or its factor) for an extra fade `extra` on top of the
    /// pending one.
    pub fn prior(&self, extra: T) -> SMatrix<T, N, N> {
        K::prior(&self.view(), extra)
    }

    /// Replaces the covariance by the posterior `p` after the input checks
    /// (a covariance the user supplies).
    pub fn set_covariance(&mut self, p: &SMatrix<T, N, N>) -> Result<(), FilterError> {
        let p = K::checked(p)?;
        self.commit(p);
        Ok(())
    }

    /// Replaces the current value by the posterior's `p`; nothing is
    /// pending.
    pub fn commit(&mut self, p: SMatrix<T, N, N>) {
        *self.spare() = p;
        self.commit_spare();
    }

    /// Makes the spare buffer, which holds the posterior, current; nothing
    /// is pending.
    pub fn commit_spare(&mut self) {
        self.buffers.swap();
        // The factor's `S_Q` is cleared only if it was set (not `N × N`
        // stores a step); the dense `Q` is only read while a prediction is
        // pending, and kept as the last one checked.
        if K::CLEARS_NOISE && self.pending {
            self.noise = SMatrix::zeros();
        }
        self.fade = T::one();
        self.pending = false;
    }

    /// Records a prediction whose propagated part is in the spare buffer,
    /// with process noise (or its factor) `noise` (`None`: the same as the
    /// last prediction's) and fade `fade`.
    pub fn predicted_spare(&mut self, noise: Option<&SMatrix<T, N, N>>, fade: T) {
        self.buffers.swap();
        if let Some(noise) = noise {
            self.noise = *noise;
        }
        self.fade = fade;
        self.pending = true;
    }

    /// What the prior, the fading split and the total fade are computed
    /// from, borrowed.
    pub fn view(&self) -> PendingView<'_, T, N, K> {
        PendingView {
            p: self.buffers.current(),
            noise: &self.noise,
            fade: self.fade,
            pending: self.pending,
            states: &self.states,
            kind: PhantomData,
        }
    }

    /// The borrowed view and the spare buffer at once, so that an update
    /// can keep what reads the view (a lazily computed split) alive while
    /// it writes the posterior into the spare buffer.
    pub fn view_and_spare(&mut self) -> (PendingView<'_, T, N, K>, &mut SMatrix<T, N, N>) {
        let (p, spare) = self.buffers.current_and_spare();
        let view = PendingView {
            p,
            noise: &self.noise,
            fade: self.fade,
            pending: self.pending,
            states: &self.states,
            kind: PhantomData,
        };
        (view, spare)
    }
}

impl<T: Real, const N: usize> Pending<T, N, Dense> {
    /// The process noise `q` of a prediction, checked unless it equals the
    /// last one: `Some(q)` mirrored when it differs (and passed), `None`
    /// when it is the same.
    #[inline(always)]
    pub fn checked_noise(
        &self,
        mut q: SMatrix<T, N, N>,
    ) -> Result<Option<SMatrix<T, N, N>>, FilterError> {
        let changed = check_noise_cached(&q, &self.noise, Quantity::ProcessNoise)?;
        if changed {
            mirror_lower(&mut q);
        }
        Ok(changed.then_some(q))
    }
}

impl<T: Real, const N: usize> Pending<T, N, Factor> {
    /// Makes the spare buffer, which holds the propagated factor with the
    /// process noise and the predict's fade `fade` folded in, current:
    /// nothing is pending, `fade` is kept for the report.
    pub fn folded_spare(&mut self, fade: T) {
        self.commit_spare();
        self.fade = fade;
    }
}

/// Equal when they represent the same covariance state: the noise matters
/// only while a prediction is pending, the spare buffer never. (The dense
/// fade is 1 whenever nothing is pending.)
impl<T: Real, const N: usize, K> PartialEq for Pending<T, N, K> {
    fn eq(&self, other: &Self) -> bool {
        self.buffers.current() == other.buffers.current()
            && self.pending == other.pending
            && self.states == other.states
            && self.fade == other.fade
            && (!self.pending || self.noise == other.noise)
    }
}

/// What the prior, the fading split and the total fade of a [`Pending`]
/// are computed from, borrowed apart from its spare buffer.
pub(crate) struct PendingView<'a, T: Real, const N: usize, K> {
    /// The current buffer.
    p: &'a SMatrix<T, N, N>,
    noise: &'a SMatrix<T, N, N>,
    fade: T,
    pending: bool,
    states: &'a FadeStates<N>,
    kind: PhantomData<K>,
}

impl<T: Real, const N: usize, K> Clone for PendingView<'_, T, N, K> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: Real, const N: usize, K> Copy for PendingView<'_, T, N, K> {}

impl<'a, T: Real, const N: usize, K: Storage<T, N>> PendingView<'a, T, N, K> {
    /// See [`Pending::prior`].
    #[inline(always)]
    pub fn prior(&self, extra: T) -> SMatrix<T, N, N> {
        K::prior(self, extra)
    }

    /// The fade applied to the propagated part with an extra fade `extra`.
    /// The dense fade is 1 while nothing is pending, the factor's is the
    /// predict's already folded in.
    pub fn total_fade(&self, extra: T) -> T {
        self.fade * extra
    }

    /// See [`Storage::borrowed`].
    #[inline(always)]
    pub fn borrowed(&self) -> Option<&'a SMatrix<T, N, N>> {
        K::borrowed(self)
    }
}

impl<T: Real, const N: usize> Storage<T, N> for Dense {
    const NAME: &'static str = "PendingCovariance";
    const CLEARS_NOISE: bool = false;

    /// `D Φ P Φᵀ D + Q` (`λ_total Φ P Φᵀ + Q` when every state fades).
    /// Always inlined: on the step's path `extra` is the constant 1 and
    /// the fade's branches fold away, which the compiler does not see
    /// where the adapter path calls it too.
    #[inline(always)]
    fn prior(view: &PendingView<'_, T, N, Self>, extra: T) -> SMatrix<T, N, N> {
        if view.pending {
            let lambda = view.fade * extra;
            if lambda == T::one() {
                // Element by element into the result (nalgebra's `+`
                // returns through a temporary and a copy).
                let (p, q) = (view.p, view.noise);
                SMatrix::from_fn(|i, j| p[(i, j)] + q[(i, j)])
            } else {
                view.states.scale_symmetric(view.p, lambda) + *view.noise
            }
        } else if extra == T::one() {
            *view.p
        } else {
            view.states.scale_symmetric(view.p, extra)
        }
    }

    fn checked(p: &SMatrix<T, N, N>) -> Result<SMatrix<T, N, N>, FilterError> {
        check_covariance(p, Quantity::StateCovariance)?;
        let mut p = *p;
        mirror_lower(&mut p);
        Ok(p)
    }

    /// Never: the dense prior is computed (it adds the pending `Q`).
    #[inline(always)]
    fn borrowed<'b>(_view: &PendingView<'b, T, N, Self>) -> Option<&'b SMatrix<T, N, N>> {
        None
    }
}

impl<T: Real, const N: usize> Storage<T, N> for Factor {
    const NAME: &'static str = "PendingFactor";
    const CLEARS_NOISE: bool = true;

    /// The factor of `D S Sᵀ D + S_Q S_Qᵀ` (`D = √λ` on the faded states)
    /// for a fade `λ = extra`.
    fn prior(view: &PendingView<'_, T, N, Self>, lambda: T) -> SMatrix<T, N, N> {
        if !view.pending {
            return if lambda == T::one() {
                *view.p
            } else {
                view.states.scale_rows(view.p, lambda)
            };
        }
        let mut s = view.states.scale_rows(view.p, lambda);
        let mut cols: [SVector<T, N>; N] =
            core::array::from_fn(|i| view.noise.column(i).into_owned());
        add_columns(&mut s, &mut cols);
        s
    }

    fn checked(p: &SMatrix<T, N, N>) -> Result<SMatrix<T, N, N>, FilterError> {
        check_covariance(p, Quantity::StateCovariance)
    }

    /// `S` itself unless a prediction is pending.
    #[inline(always)]
    fn borrowed<'b>(view: &PendingView<'b, T, N, Self>) -> Option<&'b SMatrix<T, N, N>> {
        (!view.pending).then_some(view.p)
    }
}

impl<T: Real, const N: usize> PendingView<'_, T, N, Dense> {
    /// `(H Φ P Φᵀ Hᵀ · λ, H Q Hᵀ)` for a (possibly statistically
    /// linearised) measurement matrix `h`; without a pending prediction all
    /// of `predicted` is propagated.
    pub fn split<const M: usize>(
        &self,
        h: Option<&SMatrix<T, M, N>>,
        predicted: &SMatrix<T, M, M>,
    ) -> (SMatrix<T, M, M>, SMatrix<T, M, M>) {
        match h {
            Some(h) if self.pending && self.states.is_all() => {
                (sandwich(h, self.p) * self.fade, sandwich(h, self.noise))
            }
            Some(h) if self.pending => (
                sandwich(h, &self.states.scale_symmetric(self.p, self.fade)),
                sandwich(h, self.noise),
            ),
            _ => (*predicted, SMatrix::zeros()),
        }
    }
}

impl<T: Real, const N: usize> PendingView<'_, T, N, Factor> {
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
        let gp = h * self.p;
        let gq = h * self.noise;
        Some((gp * gp.transpose(), gq * gq.transpose()))
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
        // Committed through the spare buffer and by value.
        *cov.spare() = p0;
        cov.commit_spare();
        assert!(!cov.is_pending());
        assert_eq!(cov.prior(1.0), p0);
        cov.commit(p0 * 4.0);
        assert_eq!(cov.prior(1.0), p0 * 4.0);
    }

    #[test]
    fn a_pending_factor_merges_the_process_noise_and_commits_through_the_spare_buffer() {
        let s0 = Matrix2::new(2.0, 0.0, 1.0, 3.0);
        let mut factor = PendingFactor::new(s0);
        assert_eq!(
            factor.view().borrowed(),
            Some(&s0),
            "nothing pending: borrowed"
        );
        // Written but not committed (a step that failed its checks): the
        // factor is unchanged.
        *factor.spare() = Matrix2::from_element(f64::NAN);
        assert_eq!(factor, PendingFactor::new(s0));
        // A prediction: the propagated factor in the spare buffer, `S_Q` apart.
        let sq = Matrix2::new(0.5, 0.0, 0.0, 0.25);
        let (view, spare) = factor.view_and_spare();
        *spare = view.prior(1.0) * 2.0;
        factor.predicted_spare(Some(&sq), 1.0);
        // The merged factor's product is `S Sᵀ + S_Q S_Qᵀ`.
        let p = (s0 * 2.0) * (s0 * 2.0).transpose() + sq * sq.transpose();
        let l = factor.prior(1.0);
        approx::assert_relative_eq!(l * l.transpose(), p, epsilon = 1e-12);
        assert_eq!(factor.view().borrowed(), None, "pending: merged");
        // A fade of 4 doubles the propagated factor's part.
        let p4 = (s0 * 4.0) * (s0 * 4.0).transpose() + sq * sq.transpose();
        let l4 = factor.prior(4.0);
        approx::assert_relative_eq!(l4 * l4.transpose(), p4, epsilon = 1e-12);
        // The split of `h P⁻ hᵀ` for `h = [1 1]`.
        let h = nalgebra::RowVector2::new(1.0, 1.0);
        let (propagated, noise) = factor.view().split(&h).unwrap();
        approx::assert_relative_eq!(propagated[0], (h * (s0 * 2.0)).norm_squared());
        approx::assert_relative_eq!(noise[0], 0.5 * 0.5 + 0.25 * 0.25);
        // Committed: nothing pending, `S_Q` cleared, no split.
        factor.commit(l);
        assert_eq!(factor.prior(1.0), l);
        assert!(factor.view().split(&h).is_none());
        assert_eq!(factor, PendingFactor::new(l));
        // A fade folded in at the predict is kept for the report until
        // the next update.
        factor.folded_spare(1.5);
        assert_eq!(factor.view().total_fade(2.0), 3.0);
        factor.commit_spare();
        assert_eq!(factor.view().total_fade(2.0), 2.0);
    }
}
