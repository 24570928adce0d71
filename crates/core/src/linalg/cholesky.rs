use core::fmt;

use nalgebra::SMatrix;

use crate::real::{epsilon, lit};
use crate::Real;

/// A Cholesky factorisation met a pivot that is not positive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NotPositiveDefinite {
    /// Row / column of the failing pivot.
    pub index: usize,
}

impl fmt::Display for NotPositiveDefinite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "matrix is not positive definite at pivot {}", self.index)
    }
}

impl core::error::Error for NotPositiveDefinite {}

/// Lower Cholesky factor `L` of a symmetric positive-definite matrix
/// (`A = L Lᵀ`), reading only the lower triangle of `a`.
///
/// A pivot that is not finite, or not larger than `N·ε` times the original
/// diagonal element (the matrix is singular to working precision), is
/// reported with its index instead of producing NaN.
///
/// ```
/// use kestrel_core::linalg::cholesky;
/// use kestrel_core::nalgebra::Matrix2;
/// let l = cholesky(&Matrix2::new(4.0, 2.0, 2.0, 5.0)).unwrap();
/// assert_eq!(l, Matrix2::new(2.0, 0.0, 1.0, 2.0));
/// assert_eq!(cholesky(&Matrix2::new(1.0, 2.0, 2.0, 1.0)).unwrap_err().index, 1);
/// ```
pub fn cholesky<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
) -> Result<SMatrix<T, N, N>, NotPositiveDefinite> {
    cholesky_by(a, N < UNROLL_FROM)
}

/// [`cholesky`] by the unrolled (`small`) or the column-loop elimination.
#[inline(always)]
fn cholesky_by<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
    small: bool,
) -> Result<SMatrix<T, N, N>, NotPositiveDefinite> {
    let rel = epsilon::<T>() * lit::<T>(N as f64);
    let mut l = *a;
    factor(&mut l, small, |k, d, original, _column| {
        if regular_pivot(d, original, rel) {
            Ok(Some(d.sqrt()))
        } else {
            Err(NotPositiveDefinite { index: k })
        }
    })?;
    Ok(l)
}

/// Lower Cholesky factor of a symmetric positive **semi**-definite matrix,
/// such as a process noise covariance with noise-free states.
///
/// A pivot within `N·ε·max|diag|` of zero gives a zero column, provided the
/// rest of that column is zero to the same precision (as it must be for a
/// semi-definite matrix); otherwise the matrix is indefinite and the pivot
/// index is returned. A pivot above `N·ε` times its own original diagonal
/// element is kept however small against the largest one, so a badly
/// scaled positive-definite matrix (variances 10⁻⁸ next to 10²) keeps its
/// small variances: the rounding of a pivot is relative to its own
/// diagonal.
///
/// ```
/// use kestrel_core::linalg::cholesky_semidefinite;
/// use kestrel_core::nalgebra::Matrix2;
/// let l = cholesky_semidefinite(&Matrix2::new(4.0, 0.0, 0.0, 0.0)).unwrap();
/// assert_eq!(l, Matrix2::new(2.0, 0.0, 0.0, 0.0));
/// assert!(cholesky_semidefinite(&Matrix2::new(0.0, 1.0, 1.0, 0.0)).is_err());
/// ```
pub fn cholesky_semidefinite<T: Real, const N: usize>(
    a: &SMatrix<T, N, N>,
) -> Result<SMatrix<T, N, N>, NotPositiveDefinite> {
    let mut l = *a;
    cholesky_semidefinite_in_place(&mut l)?;
    Ok(l)
}

/// [`cholesky_semidefinite`] overwriting `a` with its factor (no copy of
/// `N × N` values in or out); on error `a` holds a partial factor.
#[inline]
pub(crate) fn cholesky_semidefinite_in_place<T: Real, const N: usize>(
    a: &mut SMatrix<T, N, N>,
) -> Result<(), NotPositiveDefinite> {
    semidefinite_by(a, N < UNROLL_FROM)
}

/// [`cholesky_semidefinite_in_place`] by the unrolled (`small`) or the
/// column-loop elimination.
#[inline(always)]
fn semidefinite_by<T: Real, const N: usize>(
    a: &mut SMatrix<T, N, N>,
    small: bool,
) -> Result<(), NotPositiveDefinite> {
    let mut scale = T::zero();
    for i in 0..N {
        scale = scale.max(a[(i, i)].abs());
    }
    let rel = epsilon::<T>() * lit::<T>(N as f64);
    let tol = rel * scale;
    factor(a, small, |k, d, original, column: &[T]| {
        if !d.is_finite() || d < -tol {
            return Err(NotPositiveDefinite { index: k });
        }
        if d > tol || (d > T::zero() && d > rel * original.abs()) {
            return Ok(Some(d.sqrt()));
        }
        // A zero pivot of a semi-definite matrix has a zero column below it
        // (Cauchy–Schwarz); anything larger than rounding means indefinite.
        let limit = (tol * scale).sqrt() * lit(4.0);
        if column.iter().all(|v| v.abs() <= limit) {
            Ok(None)
        } else {
            Err(NotPositiveDefinite { index: k })
        }
    })
}

/// The size from which [`factor`] takes four columns per pass; below it,
/// the unrolled elimination ([`factor_small`], also used by
/// [`Ldl`](super::Ldl)).
pub(super) const UNROLL_FROM: usize = 10;

/// The test of a positive definite factorisation's pivot `d`: finite,
/// positive, and above `rel` (`N·ε`) times its matrix's original diagonal
/// element `original` (below it the matrix is singular to working
/// precision). NaN fails.
#[inline(always)]
pub(super) fn regular_pivot<T: Real>(d: T, original: T, rel: T) -> bool {
    d.is_finite() && d > rel * original.abs() && d > T::zero()
}

/// Left-looking column Cholesky: column `j` of the working copy receives
/// `−l_jk · L[j.., k]` for every finished column `k < j`, each as one
/// contiguous, bounds-check-free loop that vectorises, in the order of the
/// textbook right-looking update (`a_ij − l_i0 l_j0 − l_i1 l_j1 − …`, the same
/// rounding). `pivot(k, d, a_kk, column_below)` then turns the Schur pivot
/// `d` into the diagonal (`None` = zero column) or an error. In place: `l`
/// holds the matrix on entry and its factor on success.
#[inline(always)]
fn factor<T: Real, const N: usize>(
    l: &mut SMatrix<T, N, N>,
    small: bool,
    mut pivot: impl FnMut(usize, T, T, &[T]) -> Result<Option<T>, NotPositiveDefinite>,
) -> Result<(), NotPositiveDefinite> {
    if small {
        return factor_small(l, pivot);
    }
    let original: [T; N] = core::array::from_fn(|j| l[(j, j)]);
    let s = l.as_mut_slice();
    for j in 0..N {
        let (done, rest) = s.split_at_mut(j * N);
        let col = &mut rest[j..N];
        // From `UNROLL_FROM` states on, four finished columns per pass over
        // `col`: each element still takes its subtractions one at a time in
        // column order (the same rounding), with a quarter of the loop
        // overhead and stores. (Below, the larger code costs more than the
        // short loops save: measured at 2 and 6.)
        let column = |k: usize| &done[k * N + j..k * N + N];
        let mut k = 0;
        while N >= UNROLL_FROM && k + 4 <= j {
            // Scalars, not an array: four 8-byte stores read back as vectors
            // stall store forwarding.
            let (f0, f1, f2, f3) = (
                done[k * N + j],
                done[(k + 1) * N + j],
                done[(k + 2) * N + j],
                done[(k + 3) * N + j],
            );
            let len = col.len();
            let (c0, c1, c2, c3) = (
                &column(k)[..len],
                &column(k + 1)[..len],
                &column(k + 2)[..len],
                &column(k + 3)[..len],
            );
            for i in 0..len {
                col[i] = col[i] - c0[i] * f0 - c1[i] * f1 - c2[i] * f2 - c3[i] * f3;
            }
            k += 4;
        }
        for k in k..j {
            let ljk = done[k * N + j];
            for (v, &lik) in col.iter_mut().zip(column(k)) {
                *v -= lik * ljk;
            }
        }
        let (diag, below) = col.split_at_mut(1);
        match pivot(j, diag[0], original[j], below)? {
            Some(root) => {
                let inv = root.recip();
                diag[0] = root;
                for v in below {
                    *v *= inv;
                }
            }
            None => {
                diag[0] = T::zero();
                for v in below {
                    *v = T::zero();
                }
            }
        }
        // The strict upper part of the column still holds the input.
        for v in &mut rest[..j] {
            *v = T::zero();
        }
    }
    Ok(())
}

/// [`factor`] below `UNROLL_FROM`, with every loop at a trip count known
/// at compile time (bounds as conditions), so it unrolls into straight-line
/// code, and with the square roots off the chain from one column to the
/// next: the columns are eliminated unscaled, `u_ij = a_ij − Σ_k u_ik
/// (u_jk / d_k)` with pivots `d_j = u_jj` (the square-root-free `L D Lᵀ`
/// recurrence, one division per pivot on the chain), and scaled to
/// `l_ij = u_ij / √d_j` at the end. Mathematically `u_ik = l_ik √d_k`, so
/// the pivots, their tests and the factor are those of [`factor`] to
/// rounding; at small sizes the square root and division per pivot of the
/// textbook order are most of the factorisation's latency.
#[inline(always)]
fn factor_small<T: Real, const N: usize>(
    l: &mut SMatrix<T, N, N>,
    pivot: impl FnMut(usize, T, T, &[T]) -> Result<Option<T>, NotPositiveDefinite>,
) -> Result<(), NotPositiveDefinite> {
    let original: [T; N] = core::array::from_fn(|j| l[(j, j)]);
    let s = l.as_mut_slice();
    let (_, roots) = eliminate_unrolled(s, &original, pivot)?;
    for j in 0..N {
        let scale = if roots[j] > T::zero() {
            roots[j].recip()
        } else {
            T::zero()
        };
        for i in 0..N {
            if i < j {
                s[j * N + i] = T::zero();
            } else if i == j {
                s[j * N + i] = roots[j];
            } else {
                s[j * N + i] *= scale;
            }
        }
    }
    Ok(())
}

/// The unscaled elimination of [`factor_small`], shared with the unrolled
/// [`Ldl`](super::Ldl): on the column-major `N × N` slice `s`, column `j`
/// below the diagonal becomes `u_ij = a_ij − Σ_k u_ik (u_jk / d_k)` and its
/// diagonal the pivot `d_j`, each loop at a constant trip count so it
/// unrolls. `pivot(j, d_j, a_jj, u_·j below)` accepts a pivot (`Some`, with
/// its square root or any value the caller keeps) or makes its column zero
/// (`None`). Returns `1/d_j` (zero for a zero column) and what `pivot` gave.
#[inline(always)]
pub(super) fn eliminate_unrolled<T: Real, const N: usize>(
    s: &mut [T],
    original: &[T; N],
    mut pivot: impl FnMut(usize, T, T, &[T]) -> Result<Option<T>, NotPositiveDefinite>,
) -> Result<([T; N], [T; N]), NotPositiveDefinite> {
    let mut inv_d = [T::zero(); N];
    let mut kept = [T::zero(); N];
    for j in 0..N {
        for k in 0..N {
            if k < j {
                let t = s[k * N + j] * inv_d[k];
                for i in 0..N {
                    if i >= j {
                        s[j * N + i] -= s[k * N + i] * t;
                    }
                }
            }
        }
        let d = s[j * N + j];
        match pivot(j, d, original[j], &s[j * N + j + 1..j * N + N])? {
            Some(value) => {
                inv_d[j] = d.recip();
                kept[j] = value;
            }
            // A zero column: it takes no further part (`1/d = 0`).
            None => {
                for i in 0..N {
                    if i > j {
                        s[j * N + i] = T::zero();
                    }
                }
            }
        }
    }
    Ok((inv_d, kept))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix3, Matrix4, SMatrix};

    #[test]
    fn factors_a_hand_computed_3x3() {
        // A = L Lᵀ with L = [[2,0,0],[1,3,0],[-1,2,4]].
        let l = Matrix3::new(2.0, 0.0, 0.0, 1.0, 3.0, 0.0, -1.0, 2.0, 4.0);
        let a = l * l.transpose();
        assert_relative_eq!(cholesky(&a).unwrap(), l, epsilon = 1e-14);
    }

    #[test]
    fn reads_only_the_lower_triangle() {
        let mut a = Matrix3::new(4.0, 0.0, 0.0, 2.0, 10.0, 0.0, -2.0, 5.0, 21.0);
        let l = cholesky(&a).unwrap();
        a.fill_upper_triangle_with_lower_triangle();
        assert_relative_eq!(l * l.transpose(), a, epsilon = 1e-13);
    }

    #[test]
    fn reports_the_failing_pivot() {
        let a = Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0);
        assert_eq!(cholesky(&a), Err(NotPositiveDefinite { index: 2 }));
        let nan = Matrix3::new(1.0, 0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 1.0);
        assert_eq!(cholesky(&nan), Err(NotPositiveDefinite { index: 1 }));
    }

    #[test]
    fn singular_to_working_precision_is_rejected() {
        // Rank one: [1 1; 1 1] has a zero second pivot.
        let a = nalgebra::Matrix2::new(1.0, 1.0, 1.0, 1.0);
        assert_eq!(cholesky(&a), Err(NotPositiveDefinite { index: 1 }));
    }

    #[test]
    fn sizes_taking_four_columns_per_pass_match_nalgebra() {
        // 11 and 15 states: the four-column passes plus a remainder.
        fn check<const N: usize>() {
            let a = SMatrix::<f64, N, N>::from_fn(|i, j| ((i * 7 + j * 3) as f64 * 0.37).sin());
            let p = a * a.transpose() + SMatrix::identity();
            let ours = cholesky(&p).unwrap();
            let theirs = p.cholesky().unwrap().l();
            assert_relative_eq!(ours, theirs, epsilon = 1e-12);
            assert_eq!(
                ours.upper_triangle(),
                SMatrix::from_diagonal(&ours.diagonal())
            );
        }
        check::<11>();
        check::<15>();
        // Semi-definite with a zero state in the middle of a 12-state.
        let a = SMatrix::<f64, 12, 12>::from_fn(|i, j| {
            if i == 5 || j == 5 {
                0.0
            } else {
                ((i * 5 + j * 11) as f64 * 0.29).cos()
            }
        });
        let p = a * a.transpose();
        let l = cholesky_semidefinite(&p).unwrap();
        assert_eq!(l.column(5).norm(), 0.0);
        assert_relative_eq!(l * l.transpose(), p, epsilon = 1e-12);
    }

    /// The unrolled elimination used below `UNROLL_FROM` equals the column
    /// loop to rounding, fails at the same pivot, and gives the same zero
    /// columns, at every size it serves.
    #[test]
    fn the_unrolled_elimination_equals_the_column_loop() {
        fn check<const N: usize>() {
            for seed in 0..20 {
                // Pseudo-random entries in [−½, ½) (a sine of a linear index
                // would give a matrix of rank two).
                let f = |i: usize, j: usize| {
                    // SplitMix64 of the element's index.
                    let mut x =
                        ((seed * 97 + i * 13 + j) as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
                    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
                    x ^= x >> 31;
                    (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
                };
                let a = SMatrix::<f64, N, N>::from_fn(f);
                // Well and badly scaled positive definite.
                let scale =
                    SMatrix::<f64, N, N>::from_diagonal(&nalgebra::SVector::from_fn(|i, _| {
                        10f64.powi((i * seed) as i32 % 7 - 3)
                    }));
                // chol(S M S) = S chol(M) for a positive diagonal S: compared
                // as S⁻¹ L, whose entries are of order one.
                let unscale = scale.try_inverse().unwrap();
                for (p, back) in [
                    (a * a.transpose() + SMatrix::identity(), SMatrix::identity()),
                    (
                        scale * (a * a.transpose() + SMatrix::identity() * 1e-3) * scale,
                        unscale,
                    ),
                ] {
                    let (small, general) = (cholesky_by(&p, true), cholesky_by(&p, false));
                    let (small, general) = (small.unwrap(), general.unwrap());
                    assert_relative_eq!(back * small, back * general, epsilon = 1e-12);
                    assert_eq!(
                        small.upper_triangle(),
                        SMatrix::from_diagonal(&small.diagonal())
                    );
                }
                // Indefinite: the same failing pivot.
                let mut bad = a * a.transpose() + SMatrix::identity();
                let k = seed % N;
                bad[(k, k)] = -1.0;
                assert_eq!(cholesky_by(&bad, true), cholesky_by(&bad, false));
                assert!(cholesky_by(&bad, true).is_err());
                // Semi-definite with a zero state: the same zero column.
                let z = SMatrix::<f64, N, N>::from_fn(|i, j| if i == k { 0.0 } else { f(i, j) });
                let p = z * z.transpose();
                let (mut small, mut general) = (p, p);
                let (rs, rg) = (
                    semidefinite_by(&mut small, true),
                    semidefinite_by(&mut general, false),
                );
                assert_eq!(rs, rg);
                assert!(rs.is_ok());
                assert_eq!(small.column(k).norm(), 0.0);
                assert_eq!(general.column(k).norm(), 0.0);
                assert_relative_eq!(small, general, epsilon = 1e-12);
            }
        }
        check::<1>();
        check::<2>();
        check::<3>();
        check::<4>();
        check::<5>();
        check::<6>();
        check::<7>();
        check::<8>();
        check::<9>();
    }

    #[test]
    fn semidefinite_accepts_zero_columns_in_the_middle() {
        let mut a = Matrix4::zeros();
        a[(0, 0)] = 4.0;
        a[(2, 2)] = 9.0;
        a[(3, 3)] = 1.0;
        a[(3, 0)] = 1.0;
        a[(0, 3)] = 1.0;
        let l = cholesky_semidefinite(&a).unwrap();
        assert_relative_eq!(l * l.transpose(), a, epsilon = 1e-14);
        assert_eq!(l[(1, 1)], 0.0);
    }

    #[test]
    fn semidefinite_rejects_negative_pivots() {
        let a = Matrix3::new(1.0, 0.0, 0.0, 0.0, -1e-3, 0.0, 0.0, 0.0, 1.0);
        assert_eq!(
            cholesky_semidefinite(&a),
            Err(NotPositiveDefinite { index: 1 })
        );
    }

    /// A positive-definite matrix whose variances span 10 orders of
    /// magnitude (an INS error state: position 10² m², gyro bias 10⁻⁸
    /// rad²/s²) keeps its small pivot in `f32`, where `N·ε·max|diag|` is
    /// 3.6·10⁻⁵: the factor is exact (diagonal) and nothing is zeroed.
    #[test]
    fn semidefinite_keeps_small_pivots_of_a_badly_scaled_matrix() {
        let a = Matrix3::new(100.0f32, 0.0, 0.0, 0.0, 1e-8, 0.0, 0.0, 0.0, 0.25);
        let l = cholesky_semidefinite(&a).unwrap();
        assert_eq!(l[(0, 0)], 10.0);
        assert_eq!(l[(1, 1)], 1e-8f32.sqrt());
        assert_eq!(l[(2, 2)], 0.5);
        // A rank-deficient matrix still gets its zero column: the pivot of
        // the second row is 1 − 1 = 0 exactly.
        let b = Matrix3::new(1.0f32, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1e-8);
        let l = cholesky_semidefinite(&b).unwrap();
        assert_eq!(l[(1, 1)], 0.0);
        assert_eq!(l[(2, 2)], 1e-8f32.sqrt());
    }
}
