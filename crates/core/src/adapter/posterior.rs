use core::cell::OnceCell;

use nalgebra::{SMatrix, SVector};

use crate::linalg::{
    add_scaled, mirror_lower, mul_vector, solve_lower, solve_lower_transpose, Ldl,
};
use crate::Real;

/// The measurement-space view of a completed update, given to
/// [`NoiseAdapter::after_update`](super::NoiseAdapter::after_update).
///
/// With `H_p = H P⁻ Hᵀ` and `C = H_p + R` as used for the gain, the
/// quantities adaptive noise estimators need follow without the state
/// dimension: the post-fit residual `(I − H K) ν = R C⁻¹ ν` and the
/// posterior measurement covariance `H P⁺ Hᵀ = H_p − H_p C⁻¹ H_p`.
/// (Exact for linear models; the unscented forms use their statistical
/// linearisation.) What needs `L⁻¹` for the lower Cholesky factor `L` of
/// `C` (the whitened innovation, the posterior covariance) is computed when
/// an adapter first asks, and `L⁻¹ ν` once, if the update did not already
/// have it.
///
/// ```
/// use kestrel_core::adapter::Posterior;
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// // H P⁻ Hᵀ = 3, R = 1 → C = 4 with factor 2; ν = 2.
/// let (nu, hp, r, l) = (Vector1::new(2.0), Matrix1::new(3.0), Matrix1::new(1.0), Matrix1::new(2.0));
/// let post = Posterior::new(&nu, &hp, &r, &l);
/// assert_eq!(post.post_fit_residual()[0], 0.5);          // R C⁻¹ ν
/// assert_eq!(post.posterior_covariance()[0], 0.75);      // 3 − 9/4
/// ```
#[derive(Debug, Clone)]
pub struct Posterior<'a, T: Real, const M: usize> {
    innovation: &'a SVector<T, M>,
    predicted: &'a SMatrix<T, M, M>,
    noise: &'a SMatrix<T, M, M>,
    factor: Factor<'a, T, M>,
    /// `L⁻¹ ν`, formed when first read unless the update had it.
    whitened: OnceCell<SVector<T, M>>,
}

/// How `C` is factored: its lower Cholesky factor `L`, or the form's
/// `L₁ D L₁ᵀ` (unit `L₁`), for which `L = L₁ √D` is never formed: the
/// posterior covariance and residual take `D⁻¹` as weights (no square
/// roots, no divisions), and `L⁻¹ ν` is `√D⁻¹ L₁⁻¹ ν`.
#[derive(Debug, Clone, Copy)]
enum Factor<'a, T: Real, const M: usize> {
    Cholesky(&'a SMatrix<T, M, M>),
    Ldl(&'a Ldl<T, M>),
}

impl<'a, T: Real, const M: usize> Posterior<'a, T, M> {
    /// Assembles the view from the innovation used, `H P⁻ Hᵀ`, `R` and the
    /// lower Cholesky factor of `C = H P⁻ Hᵀ + R`.
    pub fn new(
        innovation: &'a SVector<T, M>,
        predicted: &'a SMatrix<T, M, M>,
        noise: &'a SMatrix<T, M, M>,
        factor: &'a SMatrix<T, M, M>,
    ) -> Self {
        Self {
            innovation,
            predicted,
            noise,
            factor: Factor::Cholesky(factor),
            whitened: OnceCell::new(),
        }
    }

    /// [`new`](Self::new) with the whitened innovation `L⁻¹ ν` the form has
    /// already computed (for the NIS).
    #[inline(always)]
    pub(crate) fn with_whitened(
        innovation: &'a SVector<T, M>,
        whitened: &SVector<T, M>,
        predicted: &'a SMatrix<T, M, M>,
        noise: &'a SMatrix<T, M, M>,
        factor: &'a SMatrix<T, M, M>,
    ) -> Self {
        Self {
            innovation,
            predicted,
            noise,
            factor: Factor::Cholesky(factor),
            whitened: OnceCell::from(*whitened),
        }
    }

    /// The view on the form's `L D Lᵀ` of `C`: nothing is computed until an
    /// adapter reads it.
    #[inline(always)]
    pub(crate) fn on_ldl(
        innovation: &'a SVector<T, M>,
        predicted: &'a SMatrix<T, M, M>,
        noise: &'a SMatrix<T, M, M>,
        ldl: &'a Ldl<T, M>,
    ) -> Self {
        Self {
            innovation,
            predicted,
            noise,
            factor: Factor::Ldl(ldl),
            whitened: OnceCell::new(),
        }
    }

    /// `v ← L⁻¹ v` for the lower Cholesky factor `L` of `C` (on the form's
    /// `L₁ D L₁ᵀ`, `L⁻¹ = √D⁻¹ L₁⁻¹`).
    fn whiten(&self, v: &mut SVector<T, M>) {
        match &self.factor {
            Factor::Cholesky(l) => solve_lower(l, v),
            Factor::Ldl(ldl) => {
                ldl.solve_unit_lower_in_place(v);
                for (x, inv_d) in v.iter_mut().zip(ldl.inverse_pivots()) {
                    *x *= inv_d.sqrt();
                }
            }
        }
    }

    /// The innovation the update used (after any adapter scaling).
    pub fn innovation(&self) -> &SVector<T, M> {
        self.innovation
    }

    /// `H P⁻ Hᵀ` as used (with any fade).
    pub fn predicted_covariance(&self) -> &SMatrix<T, M, M> {
        self.predicted
    }

    /// `R` as used.
    pub fn noise(&self) -> &SMatrix<T, M, M> {
        self.noise
    }

    /// `C = H P⁻ Hᵀ + R` as used.
    pub fn innovation_covariance(&self) -> SMatrix<T, M, M> {
        self.predicted + self.noise
    }

    /// `C⁻¹ v`.
    pub fn solve(&self, v: &SVector<T, M>) -> SVector<T, M> {
        let mut w = *v;
        match &self.factor {
            Factor::Cholesky(l) => {
                solve_lower(l, &mut w);
                solve_lower_transpose(l, &mut w);
            }
            Factor::Ldl(ldl) => ldl.solve_in_place(&mut w),
        }
        w
    }

    /// The whitened innovation `L⁻¹ ν` for `C = L Lᵀ`; its squared norm is
    /// the NIS of the innovation used.
    ///
    /// ```
    /// use kestrel_core::adapter::Posterior;
    /// use kestrel_core::nalgebra::{Matrix1, Vector1};
    /// // C = 3 + 1 = 4 with factor 2; ν = 2: L⁻¹ ν = 1, NIS = 1.
    /// let (nu, hp, r, l) = (Vector1::new(2.0), Matrix1::new(3.0), Matrix1::new(1.0), Matrix1::new(2.0));
    /// let post = Posterior::new(&nu, &hp, &r, &l);
    /// assert_eq!(post.whitened_innovation()[0], 1.0);
    /// ```
    pub fn whitened_innovation(&self) -> &SVector<T, M> {
        self.whitened.get_or_init(|| {
            let mut whitened = *self.innovation;
            self.whiten(&mut whitened);
            whitened
        })
    }

    /// The post-fit residual `z − H x⁺ = (I − H K) ν = R C⁻¹ ν`.
    pub fn post_fit_residual(&self) -> SVector<T, M> {
        let w = match &self.factor {
            Factor::Cholesky(l) => {
                let mut w = *self.whitened_innovation();
                solve_lower_transpose(l, &mut w);
                w
            }
            Factor::Ldl(_) => self.solve(self.innovation),
        };
        mul_vector(self.noise, &w)
    }

    /// `H P⁺ Hᵀ = H_p − H_p C⁻¹ H_p`, computed as `H_p − GᵀG` with
    /// `G = L⁻¹ H_p` so it stays symmetric.
    pub fn posterior_covariance(&self) -> SMatrix<T, M, M> {
        self.covariance_and_gt().0
    }

    /// [`post_fit_residual`](Self::post_fit_residual) and
    /// [`posterior_covariance`](Self::posterior_covariance) together, for
    /// less than the two cost apart: with `G = L⁻¹ H_p`, the residual is
    /// `R C⁻¹ ν = ν − H_p C⁻¹ ν = ν − Gᵀ (L⁻¹ ν)`, a product with the `G`
    /// the covariance needs anyway instead of two more triangular solves.
    /// Equal to the two to rounding. Like the covariance, the residual is
    /// then a difference that cancels when `R ≪ H_p` (its relative error
    /// grows as `ε √(H_p / R)`).
    ///
    /// ```
    /// use kestrel_core::adapter::Posterior;
    /// use kestrel_core::nalgebra::{Matrix1, Vector1};
    /// // H P⁻ Hᵀ = 3, R = 1 → C = 4 with factor 2; ν = 2.
    /// let (nu, hp, r, l) = (Vector1::new(2.0), Matrix1::new(3.0), Matrix1::new(1.0), Matrix1::new(2.0));
    /// let (e, p) = Posterior::new(&nu, &hp, &r, &l).post_fit_residual_and_covariance();
    /// assert_eq!((e[0], p[0]), (0.5, 0.75));
    /// ```
    pub fn post_fit_residual_and_covariance(&self) -> (SVector<T, M>, SMatrix<T, M, M>) {
        let (covariance, gt) = self.covariance_and_gt();
        // `Gᵀ (L⁻¹ ν)`; on `L₁ D L₁ᵀ`, `Gᵀ D⁻¹ (L₁⁻¹ ν)` with `G = L₁⁻¹ H_p`.
        let projected = match self.factor {
            Factor::Cholesky(_) => mul_vector(&gt, self.whitened_innovation()),
            Factor::Ldl(ldl) => {
                let mut y = *self.innovation;
                ldl.solve_unit_lower_in_place(&mut y);
                let inv_d = ldl.inverse_pivots();
                mul_vector(&gt, &SVector::from_fn(|k, _| y[k] * inv_d[k]))
            }
        };
        (self.innovation - projected, covariance)
    }

    /// `H_p − GᵀG` and `Gᵀ`, for `G = L⁻¹ H_p`; on the form's `L₁ D L₁ᵀ`,
    /// `H_p − Gᵀ D⁻¹ G` and `Gᵀ` for `G = L₁⁻¹ H_p`.
    fn covariance_and_gt(&self) -> (SMatrix<T, M, M>, SMatrix<T, M, M>) {
        let (gt, weights) = match self.factor {
            Factor::Cholesky(l) => {
                let mut g = *self.predicted;
                solve_lower(l, &mut g);
                (g.transpose(), [T::one(); M])
            }
            // `Gᵀ = H_p L₁⁻ᵀ` for the symmetric `H_p`, solved as it is
            // used: no transpose.
            Factor::Ldl(ldl) => {
                let mut gt = *self.predicted;
                ldl.solve_unit_lower_transpose_right_in_place(&mut gt);
                (gt, *ldl.inverse_pivots())
            }
        };
        // Gᵀ W G as Σₖ wₖ (row k of G)ᵀ (row k of G), a column at a time,
        // then mirrored: exactly symmetric.
        let mut gram = SMatrix::zeros();
        for j in 0..M {
            let mut acc = [T::zero(); M];
            for (k, row) in gt.data.0.iter().enumerate() {
                add_scaled(&mut acc, row, gt[(j, k)] * weights[k]);
            }
            gram.data.0[j] = acc;
        }
        mirror_lower(&mut gram);
        (self.predicted - gram, gt)
    }
}

#[cfg(test)]
mod tests {
    use approx::assert_relative_eq;
    use nalgebra::{Matrix1, Vector1};

    use super::*;
    use crate::linalg::cholesky;

    /// The view on `L D Lᵀ` (weights `D⁻¹`, no square roots) reads what
    /// the view on the Cholesky factor reads, to rounding, at sizes on both
    /// sides of the unrolled solves; the covariance exactly symmetric.
    #[test]
    fn the_view_on_l_d_lt_equals_the_view_on_the_cholesky_factor() {
        fn check<const M: usize>(seed: usize) {
            let a = SMatrix::<f64, M, M>::from_fn(|i, j| {
                ((i * 7 + j * 3 + i * j + seed * 5) as f64 * 0.37).sin()
            });
            let b = SMatrix::<f64, M, M>::from_fn(|i, j| {
                ((i * 2 + j * 11 + seed) as f64 * 0.53).cos() * 0.3
            });
            let hp = a * a.transpose() + SMatrix::identity() * 0.2;
            let r = b * b.transpose() + SMatrix::identity() * 0.05;
            let nu = SVector::<f64, M>::from_fn(|i, _| ((i + seed) as f64 * 1.3).sin() * 2.0);
            let c = hp + r;
            let l = cholesky(&c).unwrap();
            let ldl = Ldl::new(&c).unwrap();
            let by_cholesky = Posterior::new(&nu, &hp, &r, &l);
            let on_ldl = Posterior::on_ldl(&nu, &hp, &r, &ldl);
            let what = (M, seed);
            let rel = 1e-13;
            assert_relative_eq!(
                *on_ldl.whitened_innovation(),
                *by_cholesky.whitened_innovation(),
                epsilon = rel * nu.amax()
            );
            assert_relative_eq!(
                on_ldl.solve(&nu),
                by_cholesky.solve(&nu),
                epsilon = rel * by_cholesky.solve(&nu).amax()
            );
            // Differences: their rounding is relative to what they are the
            // difference of.
            let (e, p) = on_ldl.post_fit_residual_and_covariance();
            let (e_ref, p_ref) = by_cholesky.post_fit_residual_and_covariance();
            assert!(
                (e - e_ref).amax() <= rel * nu.amax(),
                "{what:?}: {e} vs {e_ref}"
            );
            assert!(
                (p - p_ref).amax() <= rel * hp.amax(),
                "{what:?}: {p} vs {p_ref}"
            );
            assert_eq!(p, p.transpose(), "{what:?}");
            assert_eq!(p, on_ldl.posterior_covariance(), "{what:?}");
            let alone = on_ldl.post_fit_residual();
            assert!(
                (alone - e_ref).amax() <= rel * nu.amax(),
                "{what:?}: {alone}"
            );
            // And the quantities themselves: R C⁻¹ ν and H_p − H_p C⁻¹ H_p.
            let inverse = c.try_inverse().unwrap();
            assert_relative_eq!(e, r * inverse * nu, epsilon = 1e-10);
            assert_relative_eq!(p, hp - hp * inverse * hp, epsilon = 1e-10);
        }
        for seed in 0..4 {
            check::<1>(seed);
            check::<2>(seed);
            check::<3>(seed);
            check::<6>(seed);
            check::<12>(seed);
        }
    }

    /// Hand-computed: `H_p = 3`, `R = 1`, `C = 4 = 1 · 4 · 1`, `ν = 2`:
    /// `L₁⁻¹ ν = 2`, whitened `2 √¼ = 1`; `G = 3`, `H P⁺ Hᵀ = 3 − 3 · ¼ · 3
    /// = 0.75`; the residual `2 − 3 · ¼ · 2 = 0.5` (the type's example, on
    /// the Cholesky factor 2).
    #[test]
    fn a_hand_computed_view_on_l_d_lt() {
        let (nu, hp, r) = (Vector1::new(2.0), Matrix1::new(3.0), Matrix1::new(1.0));
        let ldl = Ldl::new(&Matrix1::new(4.0)).unwrap();
        let post = Posterior::on_ldl(&nu, &hp, &r, &ldl);
        assert_eq!(post.whitened_innovation()[0], 1.0);
        assert_eq!(post.solve(&nu)[0], 0.5);
        let (e, p) = post.post_fit_residual_and_covariance();
        assert_eq!((e[0], p[0]), (0.5, 0.75));
        assert_eq!(post.post_fit_residual()[0], 0.5);
    }
}
