use nalgebra::{SMatrix, SVector};

use super::product::add_products;
use crate::Real;

/// Copies the lower triangle of `p` onto its upper triangle, making `p`
/// exactly symmetric.
///
/// ```
/// use kestrel_core::linalg::mirror_lower;
/// use kestrel_core::nalgebra::Matrix2;
/// let mut p = Matrix2::new(1.0, 9.0, 2.0, 3.0);
/// mirror_lower(&mut p);
/// assert_eq!(p, Matrix2::new(1.0, 2.0, 2.0, 3.0));
/// ```
#[inline]
pub fn mirror_lower<T: Real, const N: usize>(p: &mut SMatrix<T, N, N>) {
    let s = p.as_mut_slice();
    for j in 1..N {
        for i in 0..j {
            s[j * N + i] = s[i * N + j];
        }
    }
}

/// `A P Aᵀ` for a symmetric `P`, computing one triangle (the product `A P`
/// in full, reading `P` as `Pᵀ`, then the lower half of `(A P) Aᵀ`) and
/// mirroring it, so the result is exactly symmetric.
///
/// ```
/// use kestrel_core::linalg::sandwich;
/// use kestrel_core::nalgebra::{Matrix2, Matrix1x2};
/// let p = Matrix2::new(2.0, 1.0, 1.0, 3.0);
/// let h = Matrix1x2::new(1.0, 1.0);
/// assert_eq!(sandwich(&h, &p)[0], 7.0);
/// ```
#[inline]
pub fn sandwich<T: Real, const R: usize, const C: usize>(
    a: &SMatrix<T, R, C>,
    p: &SMatrix<T, C, C>,
) -> SMatrix<T, R, R> {
    // A P = A Pᵀ for the symmetric P.
    let mut ap = SMatrix::zeros();
    add_products(&mut ap, None, [a], [p], false);
    sandwich_transposed(&ap, a)
}

/// The symmetric product `B Aᵀ` where `B = A P` (or any product known to be
/// symmetric, such as `H (P Hᵀ)`), computing the lower triangle only (in
/// register tiles, up to the tiles that straddle the diagonal) and mirroring it.
///
/// ```
/// use kestrel_core::linalg::sandwich_transposed;
/// use kestrel_core::nalgebra::{Matrix2, Matrix1x2};
/// let p = Matrix2::new(2.0, 1.0, 1.0, 3.0);
/// let h = Matrix1x2::new(1.0, 1.0);
/// assert_eq!(sandwich_transposed(&(h * p), &h)[0], 7.0);
/// ```
#[inline]
pub fn sandwich_transposed<T: Real, const R: usize, const C: usize>(
    b: &SMatrix<T, R, C>,
    a: &SMatrix<T, R, C>,
) -> SMatrix<T, R, R> {
    // out[i, j] = Σ_k B[i, k] A[j, k], lower triangle.
    let mut out = SMatrix::<T, R, R>::zeros();
    add_products(&mut out, None, [b], [a], true);
    mirror_lower(&mut out);
    out
}

/// Adds `w d dᵀ` to the lower triangle of `p` (the upper triangle is not
/// touched: call [`mirror_lower`] when done accumulating).
///
/// ```
/// use kestrel_core::linalg::{add_weighted_outer_lower, mirror_lower};
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let mut p = Matrix2::zeros();
/// add_weighted_outer_lower(&mut p, 2.0, &Vector2::new(1.0, 3.0));
/// mirror_lower(&mut p);
/// assert_eq!(p, Matrix2::new(2.0, 6.0, 6.0, 18.0));
/// ```
#[inline]
pub fn add_weighted_outer_lower<T: Real, const N: usize>(
    p: &mut SMatrix<T, N, N>,
    w: T,
    d: &SVector<T, N>,
) {
    let s = p.as_mut_slice();
    let ds = d.as_slice();
    for j in 0..N {
        let f = w * ds[j];
        for (pi, di) in s[j * N + j..j * N + N].iter_mut().zip(&ds[j..]) {
            *pi += *di * f;
        }
    }
}

/// The Joseph-form covariance update, expanded so it costs `O(N²M)`:
///
/// `(I − K H) P (I − K H)ᵀ + K R Kᵀ = P − K Bᵀ − B Kᵀ + K C Kᵀ`
///
/// with `B = P Hᵀ` (or the cross covariance `P_xz` of an unscented form) and
/// `C = H P Hᵀ + R`. The identity holds for any gain `K`, so, like the
/// Joseph form, the result is insensitive to first order to errors in `K`.
/// Computed as `P + E Kᵀ − K Bᵀ` with `E = K C − B` (≈ 0 for the optimal
/// gain), lower triangle only, then mirrored: exactly symmetric.
///
/// ```
/// use kestrel_core::linalg::joseph_expanded;
/// use kestrel_core::nalgebra::{Matrix1, Matrix2, Matrix2x1, Matrix1x2};
/// let p = Matrix2::new(4.0, 1.0, 1.0, 2.0);
/// let h = Matrix1x2::new(1.0, 0.0);
/// let r = Matrix1::new(1.0);
/// let b = p * h.transpose();
/// let c = h * b + r;
/// let k = b / c[0];
/// let joseph = (Matrix2::identity() - k * h) * p * (Matrix2::identity() - k * h).transpose()
///     + k * r * k.transpose();
/// assert!((joseph_expanded(&p, &k, &b, &c) - joseph).norm() < 1e-14);
/// ```
#[inline]
pub fn joseph_expanded<T: Real, const N: usize, const M: usize>(
    p: &SMatrix<T, N, N>,
    k: &SMatrix<T, N, M>,
    b: &SMatrix<T, N, M>,
    c: &SMatrix<T, M, M>,
) -> SMatrix<T, N, N> {
    let e = k * c - b;
    let mut out = SMatrix::zeros();
    add_products(&mut out, Some(p), [&e, &-k], [k, b], true);
    mirror_lower(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix2, Matrix2x3, Matrix3, Matrix3x2};

    #[test]
    fn sandwich_matches_naive() {
        let a = Matrix2x3::new(1.0, 2.0, -1.0, 0.5, 0.0, 3.0);
        let l = Matrix3::new(1.0, 0.0, 0.0, 0.3, 2.0, 0.0, -0.2, 0.1, 0.7);
        let p = l * l.transpose();
        let s = sandwich(&a, &p);
        assert_relative_eq!(s, a * p * a.transpose(), epsilon = 1e-13);
        assert_eq!(s, s.transpose());
    }

    #[test]
    fn joseph_matches_textbook_for_a_suboptimal_gain() {
        let l = Matrix3::new(1.0, 0.0, 0.0, 0.3, 2.0, 0.0, -0.2, 0.1, 0.7);
        let p = l * l.transpose();
        let h = Matrix2x3::new(1.0, 0.0, 1.0, 0.0, 1.0, -1.0);
        let r = Matrix2::new(0.5, 0.1, 0.1, 0.3);
        let b = p * h.transpose();
        let c = h * b + r;
        let k = Matrix3x2::new(0.3, 0.1, -0.2, 0.4, 0.05, 0.2);
        let i_kh = Matrix3::identity() - k * h;
        let textbook = i_kh * p * i_kh.transpose() + k * r * k.transpose();
        let got = joseph_expanded(&p, &k, &b, &c);
        assert_relative_eq!(got, textbook, epsilon = 1e-13);
        assert_eq!(got, got.transpose());
    }

    #[test]
    fn products_match_naive_on_tiled_sizes() {
        // 11 states: register tiles with an overlapping last tile.
        let a = SMatrix::<f64, 11, 11>::from_fn(|i, j| ((i * 5 + j * 3) as f64 * 0.41).sin());
        let p = a * a.transpose() + SMatrix::identity();
        let h = SMatrix::<f64, 3, 11>::from_fn(|i, j| ((i * 2 + j) as f64 * 0.7).cos());
        let r = Matrix3::new(0.5, 0.1, 0.0, 0.1, 0.4, 0.05, 0.0, 0.05, 0.3);
        let s = sandwich(&a, &p);
        assert_relative_eq!(s, a * p * a.transpose(), max_relative = 1e-13);
        assert_eq!(s, s.transpose());
        let b = p * h.transpose();
        let c = h * b + r;
        let k = b * c.try_inverse().unwrap() * 0.9;
        let i_kh = SMatrix::<f64, 11, 11>::identity() - k * h;
        let textbook = i_kh * p * i_kh.transpose() + k * r * k.transpose();
        let got = joseph_expanded(&p, &k, &b, &c);
        assert_relative_eq!(got, textbook, epsilon = 1e-12);
        assert_eq!(got, got.transpose());
    }
}
