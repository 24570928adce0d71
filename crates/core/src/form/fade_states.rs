//! Which states a fade scales (selective fading, "multiple fading
//! factors").

use core::ops::Range;

use nalgebra::{SMatrix, SVector};

use crate::Real;

/// The states a fade `λ` applies to: `P⁻ = D Φ P Φᵀ D + Q` with
/// `D = diag(√λ on the selected states, 1 elsewhere)`. The default selects
/// every state, which is the scalar fade `P⁻ = λ Φ P Φᵀ + Q`.
///
/// Why: a scalar fade multiplies every direction of the covariance,
/// including those the measurements do not observe (in an INS error state:
/// heading, sensor biases). Their variance then grows by the product of all
/// fades and nothing brings it back. Fading only the states the
/// measurements read discounts old information where it is tested and
/// leaves the rest alone.
///
/// `D P D` stays positive semi-definite (and a lower-triangular factor `S`
/// becomes `D S`, still lower-triangular), but `D P D − P` is not, in
/// general, when the selected and unselected states are correlated: a
/// block fade can shrink no variance, yet it does not dominate `P`.
///
/// The adapters' measurement-space view ([`GainStep`](crate::adapter::GainStep))
/// assumes `H D P D Hᵀ = λ H P Hᵀ`, which is exact when the selected states
/// cover every state `H` reads (every column of `H` outside the selection is
/// zero). Otherwise the fade factor an adapter computes from that view is an
/// approximation; the form still applies the fade exactly (`D Φ P Φᵀ D`) when
/// it recomputes the gain.
///
/// ```
/// use kestrel_core::form::{CovarianceForm, FadeStates, Form};
/// use kestrel_core::nalgebra::Matrix3;
/// let block = FadeStates::<3>::range(1..3);
/// assert!(!block.contains(0) && block.contains(1) && block.contains(2));
/// assert!(FadeStates::<3>::default().is_all());
/// let mut form = CovarianceForm::new(&Matrix3::<f64>::identity()).unwrap();
/// form.set_fade_states(block);
/// assert_eq!(form.fade_states(), block);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FadeStates<const N: usize> {
    mask: [bool; N],
    all: bool,
}

impl<const N: usize> Default for FadeStates<N> {
    fn default() -> Self {
        Self::all()
    }
}

impl<const N: usize> FadeStates<N> {
    /// Every state (the scalar fade).
    ///
    /// ```
    /// assert!(kestrel_core::form::FadeStates::<4>::all().is_all());
    /// ```
    pub const fn all() -> Self {
        Self {
            mask: [true; N],
            all: true,
        }
    }

    /// The states with index in `range` (indices `≥ N` are ignored).
    ///
    /// ```
    /// let s = kestrel_core::form::FadeStates::<18>::range(3..9);
    /// assert_eq!(s.count(), 6);
    /// ```
    pub fn range(range: Range<usize>) -> Self {
        Self::from_mask(core::array::from_fn(|i| range.contains(&i)))
    }

    /// The states `i` with `mask[i]`.
    ///
    /// ```
    /// let s = kestrel_core::form::FadeStates::from_mask([true, false, true]);
    /// assert!(s.contains(2) && !s.contains(1));
    /// ```
    pub fn from_mask(mask: [bool; N]) -> Self {
        Self {
            mask,
            all: mask.iter().all(|&m| m),
        }
    }

    /// Whether state `i` is faded (`false` for `i ≥ N`).
    ///
    /// ```
    /// assert!(!kestrel_core::form::FadeStates::<2>::all().contains(2));
    /// ```
    pub fn contains(&self, i: usize) -> bool {
        self.mask.get(i).copied().unwrap_or(false)
    }

    /// Whether every state is faded.
    ///
    /// ```
    /// assert!(!kestrel_core::form::FadeStates::<2>::range(0..1).is_all());
    /// ```
    pub fn is_all(&self) -> bool {
        self.all
    }

    /// The number of faded states.
    ///
    /// ```
    /// assert_eq!(kestrel_core::form::FadeStates::<5>::range(1..3).count(), 2);
    /// ```
    pub fn count(&self) -> usize {
        self.mask.iter().filter(|&&m| m).count()
    }

    /// The selection as a mask.
    ///
    /// ```
    /// assert_eq!(kestrel_core::form::FadeStates::<2>::range(1..2).mask(), &[false, true]);
    /// ```
    pub fn mask(&self) -> &[bool; N] {
        &self.mask
    }

    /// `D P D`; with every state selected exactly `λ P`, as before block
    /// fades existed. Entries with both indices selected get `λ` itself
    /// rather than `√λ·√λ`.
    pub(crate) fn scale_symmetric<T: Real>(
        &self,
        p: &SMatrix<T, N, N>,
        lambda: T,
    ) -> SMatrix<T, N, N> {
        // Unfaded (the common case): no pass over `p` at all.
        if lambda == T::one() {
            return *p;
        }
        if self.all {
            return *p * lambda;
        }
        let root = lambda.sqrt();
        SMatrix::from_fn(|i, j| match (self.mask[i], self.mask[j]) {
            (true, true) => p[(i, j)] * lambda,
            (false, false) => p[(i, j)],
            _ => p[(i, j)] * root,
        })
    }

    /// `D S` (rows of the selected states times `√λ`); with every state
    /// selected exactly `√λ S`.
    pub(crate) fn scale_rows<T: Real, const C: usize>(
        &self,
        s: &SMatrix<T, N, C>,
        lambda: T,
    ) -> SMatrix<T, N, C> {
        if self.all {
            return *s * lambda.sqrt();
        }
        let mut s = *s;
        if lambda != T::one() {
            let root = lambda.sqrt();
            for (i, _) in self.mask.iter().enumerate().filter(|&(_, &m)| m) {
                s.row_mut(i).scale_mut(root);
            }
        }
        s
    }

    /// `v ← D v` (only for a block selection; callers handle `all` by a
    /// scalar weight).
    pub(crate) fn scale_vector<T: Real>(&self, v: &mut SVector<T, N>, root: T) {
        for (i, _) in self.mask.iter().enumerate().filter(|&(_, &m)| m) {
            v[i] *= root;
        }
    }
}
