use nalgebra::{SMatrix, SVector};

use crate::Real;

/// `S Sᵀ ← S Sᵀ + Σ cᵢ cᵢᵀ`: folds the columns `cols` into the lower
/// factor `S` by Householder reflections of the compound `[S | c₁ … c_K]`
/// from the right (a QR factorisation of its transpose that exploits the
/// triangle). The result has a non-negative diagonal; `cols` is used as
/// scratch (destroyed).
///
/// Adding only positive semi-definite terms, it cannot fail; `S` may start
/// singular or zero. Cost ≈ `2 K N²` multiply-adds.
///
/// ```
/// use kestrel_core::linalg::add_columns;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let mut s = Matrix2::zeros();
/// let mut cols = [Vector2::new(1.0, 1.0), Vector2::new(1.0, -1.0)];
/// add_columns(&mut s, &mut cols);
/// assert!((s * s.transpose() - Matrix2::new(2.0, 0.0, 0.0, 2.0)).norm() < 1e-14);
/// ```
pub fn add_columns<T: Real, const N: usize>(s: &mut SMatrix<T, N, N>, cols: &mut [SVector<T, N>]) {
    let two = T::one() + T::one();
    let ss = s.as_mut_slice();
    let mut w = [T::zero(); N];
    for k in 0..N {
        let alpha = ss[k * N + k];
        let mut sigma2 = T::zero();
        for c in cols.iter() {
            sigma2 += c[k] * c[k];
        }
        if sigma2 == T::zero() {
            if alpha < T::zero() {
                for v in &mut ss[k * N + k..k * N + N] {
                    *v = -*v;
                }
            }
            continue;
        }
        let norm = (alpha * alpha + sigma2).sqrt();
        // Reflect (α, c_k) onto (β, 0) with β = −sign(α)·norm; v₀ = α − β
        // has no cancellation.
        let beta = if alpha >= T::zero() { -norm } else { norm };
        let v0 = alpha - beta;
        let tau = two / (v0 * v0 + sigma2);
        // w = v₀ S[k+1.., k] + Σ cᵢ[k] cᵢ[k+1..]
        let wk = &mut w[k + 1..N];
        for (wi, si) in wk.iter_mut().zip(&ss[k * N + k + 1..k * N + N]) {
            *wi = *si * v0;
        }
        for c in cols.iter() {
            let f = c[k];
            if f != T::zero() {
                for (wi, ci) in wk.iter_mut().zip(&c.as_slice()[k + 1..N]) {
                    *wi += *ci * f;
                }
            }
        }
        for wi in wk.iter_mut() {
            *wi *= tau;
        }
        for (si, wi) in ss[k * N + k + 1..k * N + N].iter_mut().zip(wk.iter()) {
            *si -= *wi * v0;
        }
        for c in cols.iter_mut() {
            let f = c[k];
            if f != T::zero() {
                let cs = c.as_mut_slice();
                for (ci, wi) in cs[k + 1..N].iter_mut().zip(wk.iter()) {
                    *ci -= *wi * f;
                }
                cs[k] = T::zero();
            }
        }
        // Make the diagonal positive: flipping a column of S is an
        // orthogonal transformation from the right.
        ss[k * N + k] = beta;
        if beta < T::zero() {
            for v in &mut ss[k * N + k..k * N + N] {
                *v = -*v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::cholesky;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix4, Vector4};

    #[test]
    fn equals_the_cholesky_factor_of_the_sum() {
        let l = Matrix4::new(
            2.0, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, -0.3, 0.2, 1.5, 0.0, 0.1, -0.4, 0.3, 0.8,
        );
        let cols0 = [
            Vector4::new(1.0, 2.0, -1.0, 0.5),
            Vector4::new(-0.5, 0.3, 0.2, 1.0),
            Vector4::new(0.0, 0.0, 3.0, -2.0),
            Vector4::new(0.7, -0.7, 0.1, 0.0),
            Vector4::new(0.0, 1.0, 0.0, 0.0),
        ];
        let mut p = l * l.transpose();
        for c in &cols0 {
            p += c * c.transpose();
        }
        let mut s = l;
        let mut cols = cols0;
        add_columns(&mut s, &mut cols);
        // The Cholesky factor with positive diagonal is unique.
        assert_relative_eq!(s, cholesky(&p).unwrap(), epsilon = 1e-12);
    }
}
