use nalgebra::{SMatrix, SVector};

use super::product::{add_products, add_scaled, mul_lower};
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

/// `L Lᵀ` for a lower-triangular `L` (zeros above the diagonal): column `j`
/// as `Σ_{k ≤ j} L_jk L[.., k]`, whole columns at a time, without the
/// products with the zeros past `k = j`. Elements `(i, j)` and `(j, i)` take
/// the same products in the same order (`L_ik = 0` for `k > i`), so the
/// result is exactly symmetric.
#[inline]
pub(crate) fn lower_times_transpose<T: Real, const M: usize>(
    l: &SMatrix<T, M, M>,
) -> SMatrix<T, M, M> {
    let columns = &l.data.0;
    let mut r = SMatrix::<T, M, M>::zeros();
    for (j, out) in r.data.0.iter_mut().enumerate() {
        for column in columns.iter().take(j + 1) {
            add_scaled(out, column, column[j]);
        }
    }
    r
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
    let mut out = SMatrix::zeros();
    sandwich_into(a, p, &mut out);
    out
}

/// [`sandwich`] written into `out`.
#[inline]
pub(crate) fn sandwich_into<T: Real, const R: usize, const C: usize>(
    a: &SMatrix<T, R, C>,
    p: &SMatrix<T, C, C>,
    out: &mut SMatrix<T, R, R>,
) {
    // A P = A Pᵀ for the symmetric P.
    let mut ap = SMatrix::zeros();
    add_products(&mut ap, None, [a], [p], false);
    add_products(out, None, [&ap], [a], true);
    mirror_lower(out);
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

/// The Joseph-form covariance update with the measurement noise kept apart
/// from `C`, given a lower factor `L` of `R = L Lᵀ`:
///
/// `(I − K H) P (I − K H)ᵀ + K R Kᵀ = P − K Bᵀ − B Kᵀ + K A Kᵀ + (K L)(K L)ᵀ`
///
/// with `B = P Hᵀ` (or `P_xz`) and `A = H P Hᵀ` (or the unscented `P_zz`);
/// the same value as [`joseph_expanded`] with `C = A + R`, lower triangle
/// only, mirrored.
///
/// Why apart: [`joseph_expanded`] forms `K C`, rounding by `ε ‖K‖ ‖C‖`,
/// and `K` is large along the small eigenvectors of a badly conditioned `C`
/// (an `R` with a large eigenvalue next to a small one, such as a windowed
/// estimate after an outlier). That rounding, `ε ‖K‖² ‖C‖` in the result,
/// can exceed the posterior's small eigenvalues and make it indefinite (in
/// `f32` first). Here `R` enters only through the Gram product
/// `(K L)(K L)ᵀ`, positive semi-definite as computed: the result is the
/// Joseph form for `L Lᵀ`, which is `R` up to the rounding `R` has anyway,
/// and the products left are bounded by `P`.
///
/// ```
/// use kestrel_core::linalg::{cholesky, joseph_expanded, joseph_factored_noise};
/// use kestrel_core::nalgebra::{Matrix1, Matrix2, Matrix1x2};
/// let p = Matrix2::new(4.0, 1.0, 1.0, 2.0);
/// let h = Matrix1x2::new(1.0, 0.0);
/// let r = Matrix1::new(1.0);
/// let b = p * h.transpose();
/// let a = h * b;
/// let k = b / (a[0] + r[0]);
/// let l = cholesky(&r).unwrap();
/// let got = joseph_factored_noise(&p, &k, &b, &a, &l);
/// assert!((got - joseph_expanded(&p, &k, &b, &(a + r))).norm() < 1e-14);
/// // P⁺ = P − B Bᵀ / 5 = [[0.8, 0.2], [0.2, 1.8]].
/// assert!((got - Matrix2::new(0.8, 0.2, 0.2, 1.8)).norm() < 1e-14);
/// ```
#[inline]
pub fn joseph_factored_noise<T: Real, const N: usize, const M: usize>(
    p: &SMatrix<T, N, N>,
    k: &SMatrix<T, N, M>,
    b: &SMatrix<T, N, M>,
    a: &SMatrix<T, M, M>,
    l: &SMatrix<T, M, M>,
) -> SMatrix<T, N, N> {
    let mut out = SMatrix::zeros();
    joseph_factored_noise_negated(&mut out, p, &-k, b, a, l);
    out
}

/// [`joseph_factored_noise`] written into `out` and given `K̄ = −K` (the
/// forms compute `K̄` in the pass that transposes the gain anyway). With
/// `Ē = B + K̄ A = −E` (`A` is symmetric, so `K̄ A` is the product `K̄ Aᵀ`
/// the kernel forms, on top of `B`), `P⁺ = P + Ē K̄ᵀ + K̄ Bᵀ + (K̄ L)(K̄ L)ᵀ`:
/// the terms of `joseph_factored_noise` with exact sign changes, and no
/// elementwise pass to negate `K` or subtract `B`.
#[inline]
pub(crate) fn joseph_factored_noise_negated<T: Real, const N: usize, const M: usize>(
    out: &mut SMatrix<T, N, N>,
    p: &SMatrix<T, N, N>,
    nk: &SMatrix<T, N, M>,
    b: &SMatrix<T, N, M>,
    a: &SMatrix<T, M, M>,
    l: &SMatrix<T, M, M>,
) {
    let mut ne = SMatrix::zeros();
    add_products(&mut ne, Some(b), [nk], [a], false);
    let nkl = mul_lower(nk, l);
    add_products(out, Some(p), [&ne, nk, &nkl], [nk, b, &nkl], true);
    mirror_lower(out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix2, Matrix2x3, Matrix3, Matrix3x2};

    #[test]
    fn lower_times_transpose_is_l_lt_and_exactly_symmetric() {
        let mut l =
            nalgebra::SMatrix::<f64, 5, 5>::from_fn(|i, j| ((i * 7 + j * 3) as f64 * 0.37).sin());
        l.fill_upper_triangle(0.0, 1);
        let r = lower_times_transpose(&l);
        assert_relative_eq!(r, l * l.transpose(), epsilon = 1e-14);
        assert_eq!(r, r.transpose());
        // Hand-computed: L = [2 0; 1 3] gives [4 2; 2 10].
        let r2 = lower_times_transpose(&Matrix2::new(2.0, 0.0, 1.0, 3.0));
        assert_eq!(r2, Matrix2::new(4.0, 2.0, 2.0, 10.0));
    }

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
        // 15 states: 4 × 4 register tiles and 3-wide tiles at the edges.
        let a = SMatrix::<f64, 15, 15>::from_fn(|i, j| ((i * 5 + j * 3) as f64 * 0.41).sin());
        let p = a * a.transpose() + SMatrix::identity();
        let h = SMatrix::<f64, 3, 15>::from_fn(|i, j| ((i * 2 + j) as f64 * 0.7).cos());
        let r = Matrix3::new(0.5, 0.1, 0.0, 0.1, 0.4, 0.05, 0.0, 0.05, 0.3);
        let s = sandwich(&a, &p);
        // To 1e-13 of the largest element: entries near zero come from
        // cancelling sums of terms as large as the others.
        assert_relative_eq!(s, a * p * a.transpose(), epsilon = 1e-13 * s.amax());
        assert_eq!(s, s.transpose());
        let b = p * h.transpose();
        let c = h * b + r;
        let k = b * c.try_inverse().unwrap() * 0.9;
        let i_kh = SMatrix::<f64, 15, 15>::identity() - k * h;
        let textbook = i_kh * p * i_kh.transpose() + k * r * k.transpose();
        let got = joseph_expanded(&p, &k, &b, &c);
        assert_relative_eq!(got, textbook, epsilon = 1e-12);
        assert_eq!(got, got.transpose());
        let l = crate::linalg::cholesky(&r).unwrap();
        let got = joseph_factored_noise(&p, &k, &b, &(h * b), &l);
        assert_relative_eq!(got, textbook, epsilon = 1e-12);
        assert_eq!(got, got.transpose());
    }
}

#[cfg(test)]
mod factored_noise_tests {
    use super::*;
    use crate::linalg::{cholesky, cholesky_semidefinite, solve_lower, solve_lower_transpose};
    use nalgebra::{Matrix2, Matrix2x4, Matrix4, Matrix4x2};

    /// An `f32` prior and a nearly rank-one `R` (eigenvalues ≈ 1.1·10⁴ and
    /// 0.04: a windowed estimate after an outlier), observed in the first
    /// two of four states; the posterior's smallest eigenvalue is ≈ 10⁻³.
    #[test]
    fn factored_noise_keeps_a_badly_conditioned_update_positive_definite() {
        #[rustfmt::skip]
        let p = Matrix4::<f32>::from_column_slice(&[
            1.4457688, -1.4161458, 0.7285837, -0.70843124,
            -1.4161458, 1.4019858, -0.70843124, 0.7066812,
            0.7285837, -0.70843124, 0.3739758, -0.35439488,
            -0.70843124, 0.7066812, -0.35439488, 0.36301905,
        ]);
        let r = Matrix2::<f32>::new(7180.731, -5325.0537, -5325.0537, 3948.9946);
        let h = Matrix2x4::<f32>::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0);
        let hp = h * p;
        let b = hp.transpose();
        let a = sandwich_transposed(&hp, &h);
        let c = a + r;
        let lc = cholesky(&c).unwrap();
        let mut kt = hp;
        solve_lower(&lc, &mut kt);
        solve_lower_transpose(&lc, &mut kt);
        let k: Matrix4x2<f32> = kt.transpose();
        let l = cholesky_semidefinite(&r).unwrap();

        // (I − K H) P (I − K H)ᵀ + K R Kᵀ for this very gain, in f64, with
        // R and with the factored R̃ = L Lᵀ (R up to the factor's rounding).
        let (p64, h64, k64) = (p.cast::<f64>(), h.cast::<f64>(), k.cast::<f64>());
        let i_kh = Matrix4::<f64>::identity() - k64 * h64;
        let kept = i_kh * p64 * i_kh.transpose();
        let reference = kept + k64 * r.cast::<f64>() * k64.transpose();
        let l64 = l.cast::<f64>();
        let factored = kept + k64 * l64 * l64.transpose() * k64.transpose();
        let smallest = reference.symmetric_eigenvalues().min();
        assert!(smallest > 1e-3 && smallest < 1.2e-3, "{smallest}");

        let got = joseph_factored_noise(&p, &k, &b, &a, &l);
        assert_eq!(got, got.transpose());
        // Rounding at the level of P, not of K C Kᵀ: 16 ε max|P| ≈ 2.8·10⁻⁶.
        let bound = 16.0 * f64::from(f32::EPSILON) * p64.abs().max();
        let err = (got.cast::<f64>() - factored).abs().max();
        assert!(err < bound, "{err:e}");
        assert!(cholesky(&got).is_ok());
        let got_smallest = got.cast::<f64>().symmetric_eigenvalues().min();
        assert!(
            (got_smallest - smallest).abs() < 0.01 * smallest,
            "{got_smallest}"
        );
        // Through C the same update rounds by ε ‖K‖² ‖C‖: more than the
        // smallest eigenvalue, so nothing keeps it positive definite.
        let expanded = joseph_expanded(&p, &k, &b, &c);
        let err_expanded = (expanded.cast::<f64>() - reference).abs().max();
        assert!(err_expanded > smallest, "{err_expanded:e}");
    }
}
