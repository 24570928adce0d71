use core::cell::OnceCell;

use nalgebra::{SMatrix, SVector};

use crate::linalg::{
    add_products, mirror_lower, mul_vector, solve_lower, solve_lower_transpose, Ldl,
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
/// linearisation.) What needs the lower Cholesky factor `L` of `C` or
/// `L⁻¹ ν` computes them when first asked, once, if the update did not
/// already have them.
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
    whitening: Whitening<'a, T, M>,
}

/// The lower Cholesky factor `L` of `C` and `L⁻¹ ν`, each formed when an
/// adapter first reads it unless the update already had it. Most adapters
/// never read them, and in the epochs they leave as they were the update
/// then forms neither.
#[derive(Debug, Clone)]
struct Whitening<'a, T: Real, const M: usize> {
    factor: Factor<'a, T, M>,
    whitened: OnceCell<SVector<T, M>>,
}

/// `L` as the update had it, or `L √D` of the form's `L D Lᵀ` of `C`.
#[derive(Debug, Clone)]
enum Factor<'a, T: Real, const M: usize> {
    Given(&'a SMatrix<T, M, M>),
    Deferred(&'a Ldl<T, M>, OnceCell<SMatrix<T, M, M>>),
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
            whitening: Whitening {
                factor: Factor::Given(factor),
                whitened: OnceCell::new(),
            },
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
            whitening: Whitening {
                factor: Factor::Given(factor),
                whitened: OnceCell::from(*whitened),
            },
        }
    }

    /// The view on `C`'s lower Cholesky factor `factor`, or, without it, on
    /// the form's `L D Lᵀ` of `C`; `L √D` and `L⁻¹ ν` are formed only when
    /// an adapter first reads them, by the same arithmetic as the adapter
    /// way (so the same bits).
    #[inline(always)]
    pub(crate) fn deferred(
        innovation: &'a SVector<T, M>,
        predicted: &'a SMatrix<T, M, M>,
        noise: &'a SMatrix<T, M, M>,
        (factor, ldl): (Option<&'a SMatrix<T, M, M>>, &'a Ldl<T, M>),
    ) -> Self {
        let factor = match factor {
            Some(factor) => Factor::Given(factor),
            None => Factor::Deferred(ldl, OnceCell::new()),
        };
        Self {
            innovation,
            predicted,
            noise,
            whitening: Whitening {
                factor,
                whitened: OnceCell::new(),
            },
        }
    }

    /// `L`, the lower Cholesky factor of `C`.
    fn factor(&self) -> &SMatrix<T, M, M> {
        match &self.whitening.factor {
            Factor::Given(factor) => factor,
            Factor::Deferred(ldl, formed) => formed.get_or_init(|| ldl.cholesky_factor()),
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
        solve_lower(self.factor(), &mut w);
        solve_lower_transpose(self.factor(), &mut w);
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
        self.whitening.whitened.get_or_init(|| {
            let mut whitened = *self.innovation;
            solve_lower(self.factor(), &mut whitened);
            whitened
        })
    }

    /// The post-fit residual `z − H x⁺ = (I − H K) ν = R C⁻¹ ν`.
    pub fn post_fit_residual(&self) -> SVector<T, M> {
        let mut w = *self.whitened_innovation();
        solve_lower_transpose(self.factor(), &mut w);
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
        (
            self.innovation - mul_vector(&gt, self.whitened_innovation()),
            covariance,
        )
    }

    /// `H_p − GᵀG` and `Gᵀ`, for `G = L⁻¹ H_p`.
    fn covariance_and_gt(&self) -> (SMatrix<T, M, M>, SMatrix<T, M, M>) {
        let mut g = *self.predicted;
        solve_lower(self.factor(), &mut g);
        // Gᵀ G as Σₖ (row k of G)ᵀ (row k of G) on the product kernel, one
        // triangle, mirrored: exactly symmetric.
        let gt = g.transpose();
        let mut gram = SMatrix::zeros();
        add_products(&mut gram, None, [&gt], [&gt], true);
        mirror_lower(&mut gram);
        (self.predicted - gram, gt)
    }
}
