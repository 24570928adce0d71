use nalgebra::{SMatrix, SVector};

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
/// in full, then the lower half of `(A P) Aᵀ`) and mirroring it, so the
/// result is exactly symmetric.
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
    let ap = a * p;
    sandwich_transposed(&ap, a)
}

/// The symmetric product `B Aᵀ` where `B = A P` (or any product known to be
/// symmetric, such as `H (P Hᵀ)`), computing the lower triangle only.
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
    let mut out = SMatrix::<T, R, R>::zeros();
    {
        let o = out.as_mut_slice();
        let bs = b.as_slice();
        // out[i, j] = Σ_k B[i, k] A[j, k]; column j, rows i ≥ j.
        for j in 0..R {
            let oj = &mut o[j * R + j..j * R + R];
            for k in 0..C {
                let f = a[(j, k)];
                let bk = &bs[k * R + j..k * R + R];
                for (oi, bi) in oj.iter_mut().zip(bk) {
                    *oi += *bi * f;
                }
            }
        }
    }
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
    let mut out = *p;
    {
        let o = out.as_mut_slice();
        let ks = k.as_slice();
        let es = e.as_slice();
        let bs = b.as_slice();
        for j in 0..N {
            let oj = &mut o[j * N + j..j * N + N];
            for m in 0..M {
                let kj = ks[m * N + j];
                let bj = bs[m * N + j];
                let ecol = &es[m * N + j..m * N + N];
                let kcol = &ks[m * N + j..m * N + N];
                for ((oi, ei), ki) in oj.iter_mut().zip(ecol).zip(kcol) {
                    *oi += *ei * kj - *ki * bj;
                }
            }
        }
    }
    mirror_lower(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix3, Matrix3x2, Matrix2x3, Matrix2};

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
}
