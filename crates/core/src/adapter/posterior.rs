use nalgebra::{SMatrix, SVector};

use crate::linalg::{mirror_lower, mul_vector, solve_lower, solve_lower_transpose};
use crate::Real;

/// The measurement-space view of a completed update, given to
/// [`NoiseAdapter::after_update`](super::NoiseAdapter::after_update).
///
/// With `H_p = H P⁻ Hᵀ` and `C = H_p + R` as used for the gain, the
/// quantities adaptive noise estimators need follow without the state
/// dimension: the post-fit residual `(I − H K) ν = R C⁻¹ ν` and the
/// posterior measurement covariance `H P⁺ Hᵀ = H_p − H_p C⁻¹ H_p`.
/// (Exact for linear models; the unscented forms use their statistical
/// linearisation.)
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
#[derive(Debug, Clone, Copy)]
pub struct Posterior<'a, T: Real, const M: usize> {
    innovation: &'a SVector<T, M>,
    predicted: &'a SMatrix<T, M, M>,
    noise: &'a SMatrix<T, M, M>,
    factor: &'a SMatrix<T, M, M>,
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
            factor,
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
        solve_lower(self.factor, &mut w);
        solve_lower_transpose(self.factor, &mut w);
        w
    }

    /// The post-fit residual `z − H x⁺ = (I − H K) ν = R C⁻¹ ν`.
    pub fn post_fit_residual(&self) -> SVector<T, M> {
        mul_vector(self.noise, &self.solve(self.innovation))
    }

    /// `H P⁺ Hᵀ = H_p − H_p C⁻¹ H_p`, computed as `H_p − GᵀG` with
    /// `G = L⁻¹ H_p` so it stays symmetric.
    pub fn posterior_covariance(&self) -> SMatrix<T, M, M> {
        let mut g = *self.predicted;
        solve_lower(self.factor, &mut g);
        // The lower triangle, element (i, j) as the dot product of columns
        // i and j of G, then mirrored: half the products of `GᵀG`, and
        // constant trip counts (bounds as conditions) so it unrolls.
        let columns = &g.data.0;
        let mut out = *self.predicted;
        for j in 0..M {
            for i in 0..M {
                if i >= j {
                    let mut dot = T::zero();
                    for (a, b) in columns[i].iter().zip(&columns[j]) {
                        dot += *a * *b;
                    }
                    out[(i, j)] -= dot;
                }
            }
        }
        mirror_lower(&mut out);
        out
    }
}
