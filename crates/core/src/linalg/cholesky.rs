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
    let scale = largest_diagonal_magnitude(a);
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

/// `max |a_ii|` (0 for `N = 0`; a NaN on the diagonal is passed over, as
/// `max` passes it over, and left to the pivot tests), in four running
/// maxima over every fourth diagonal element: one maximum after another is
/// a chain of `N` dependent operations that the factorisation's first
/// pivot waits on. The maximum of a set does not depend on the order it
/// is taken in, so the result is that of the plain fold.
#[inline(always)]
fn largest_diagonal_magnitude<T: Real, const N: usize>(a: &SMatrix<T, N, N>) -> T {
    let mut lanes = [T::zero(); 4];
    for i in 0..N {
        let v = a[(i, i)].abs();
        // `>` is false for NaN: it is passed over, as by `max`.
        if v > lanes[i % 4] {
            lanes[i % 4] = v;
        }
    }
    let (low, high) = (
        if lanes[1] > lanes[0] {
            lanes[1]
        } else {
            lanes[0]
        },
        if lanes[3] > lanes[2] {
            lanes[3]
        } else {
            lanes[2]
        },
    );
    if high > low {
        high
    } else {
        low
    }
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
/// `−l_jk · L[j.., k]` for every finished column `k < j`, in the order of
/// the textbook right-looking update (`a_ij − l_i0 l_j0 − l_i1 l_j1 − …`, the
/// same rounding). `pivot(k, d, a_kk, column_below)` then turns the Schur
/// pivot `d` into the diagonal (`None` = zero column) or an error. In
/// place: `l` holds the matrix on entry and its factor on success.
///
/// The rows are taken in blocks of four counted from the last row (the
/// first `N mod 4` rows form a short head), so each pass over a column is
/// whole four-lane blocks with no scalar remainder; a loop from row `j`
/// on is scalar for most of its rows (in `f32` it takes no vector path
/// below eight rows). The block holding row `j` may begin up
/// to three rows above it, in the strict upper part, which holds the
/// input until it is set to zero at the end of the column and is read by
/// nothing before; the finished columns read there are zero above their
/// diagonal. Rows from `j` on get exactly the arithmetic of a row loop.
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
    let head = N % 4;
    let columns = l.as_mut_slice().as_chunks_mut::<N>().0;
    for j in 0..N {
        let (done, rest) = columns.split_at_mut(j);
        let col = &mut rest[0];
        // The head only while `j` is in it.
        let first = first_block::<N>(j);
        let in_head = j < head;
        // From `UNROLL_FROM` states on, four finished columns per pass:
        // each element still takes its subtractions one at a time in
        // column order (the same rounding), with a quarter of the loop
        // overhead and stores. (Below, the larger code costs more than the
        // short loops save.)
        let mut k = 0;
        while N >= UNROLL_FROM && k + 4 <= j {
            // Scalars, not an array: four 8-byte stores read back as vectors
            // stall store forwarding.
            let (f0, f1, f2, f3) = (done[k][j], done[k + 1][j], done[k + 2][j], done[k + 3][j]);
            let (h0, b0) = blocks(&done[k]);
            let (h1, b1) = blocks(&done[k + 1]);
            let (h2, b2) = blocks(&done[k + 2]);
            let (h3, b3) = blocks(&done[k + 3]);
            let (h, b) = blocks_mut(col);
            if in_head {
                for i in 0..h.len() {
                    h[i] = h[i] - h0[i] * f0 - h1[i] * f1 - h2[i] * f2 - h3[i] * f3;
                }
            }
            for q in first..b.len() {
                // Read whole, then written whole: the compiler cannot tell
                // the column from the finished ones, and would otherwise
                // keep every load behind the previous lane's store.
                let mut v = b[q];
                for l in 0..4 {
                    v[l] = v[l] - b0[q][l] * f0 - b1[q][l] * f1 - b2[q][l] * f2 - b3[q][l] * f3;
                }
                b[q] = v;
            }
            k += 4;
        }
        for c in &done[k..j] {
            let f = c[j];
            let (hc, bc) = blocks(c);
            let (h, b) = blocks_mut(col);
            if in_head {
                for i in 0..h.len() {
                    h[i] -= hc[i] * f;
                }
            }
            for q in first..b.len() {
                let mut v = b[q];
                for l in 0..4 {
                    v[l] -= bc[q][l] * f;
                }
                b[q] = v;
            }
        }
        // `l_ij = u_ij / l_jj` below the diagonal, `l_jj` on it, zero
        // above (all zero for a zero column).
        match pivot(j, col[j], original[j], &col[j + 1..])? {
            Some(root) => {
                let inv = root.recip();
                finish_column(col, j, root, |v| v * inv);
            }
            None => finish_column(col, j, T::zero(), |_| T::zero()),
        }
    }
    Ok(())
}

/// Writes column `j` of the factor in place: `below(u_ij)` under the
/// diagonal, `diagonal` on it, zero above. In the blocks the next columns
/// read it in, each block stored whole: a loop from row `j + 1` stores
/// where the blocks do not begin, and the next column's loads of the
/// blocks then cannot take their data from those stores but wait for them
/// to reach the cache.
#[inline(always)]
fn finish_column<T: Real, const N: usize>(
    col: &mut [T; N],
    j: usize,
    diagonal: T,
    below: impl Fn(T) -> T,
) {
    let element = |i: usize, v: T| {
        if i > j {
            below(v)
        } else if i == j {
            diagonal
        } else {
            T::zero()
        }
    };
    let head = N % 4;
    let first = first_block::<N>(j);
    let (h, b) = blocks_mut(col);
    for (i, v) in h.iter_mut().enumerate() {
        *v = element(i, *v);
    }
    for (q, block) in b.iter_mut().enumerate() {
        let mut v = *block;
        if q < first {
            // Wholly above the diagonal.
            v = [T::zero(); 4];
        } else if q == first && j >= head {
            // Holds the diagonal.
            for (l, x) in v.iter_mut().enumerate() {
                *x = element(head + 4 * q + l, *x);
            }
        } else {
            for x in &mut v {
                *x = below(*x);
            }
        }
        *block = v;
    }
}

/// The index among a column's four-row [`blocks`] of the first block that
/// holds row `j` or a row below it (0 while `j` is in the head).
#[inline(always)]
fn first_block<const N: usize>(j: usize) -> usize {
    j.saturating_sub(N % 4) / 4
}

/// A column as its head of `N mod 4` rows and the four-row blocks after
/// it (see [`factor`]).
#[inline(always)]
fn blocks<T, const N: usize>(column: &[T; N]) -> (&[T], &[[T; 4]]) {
    let (head, rest) = column.split_at(N % 4);
    (head, rest.as_chunks::<4>().0)
}

/// [`blocks`] of a column being written.
#[inline(always)]
fn blocks_mut<T, const N: usize>(column: &mut [T; N]) -> (&mut [T], &mut [[T; 4]]) {
    let (head, rest) = column.split_at_mut(N % 4);
    (head, rest.as_chunks_mut::<4>().0)
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

    /// The four running maxima give the plain fold of `max` over the
    /// diagonal's magnitudes: every size from 0 to 9 (every count of
    /// elements per running maximum), with NaN, infinities and signed
    /// zeros on the diagonal, the largest at every position.
    #[test]
    fn the_largest_diagonal_magnitude_is_the_fold_of_max() {
        fn check<const N: usize>() {
            let fold = |a: &SMatrix<f64, N, N>| {
                let mut m = 0.0_f64;
                for i in 0..N {
                    m = m.max(a[(i, i)].abs());
                }
                m
            };
            let specials = [f64::NAN, -0.0, 0.0, -3.5, f64::INFINITY, 1e-300, -f64::MAX];
            for at in 0..N.max(1) {
                for &special in &specials {
                    let a = SMatrix::<f64, N, N>::from_fn(|i, j| {
                        if i != j {
                            f64::NAN
                        } else if i == at {
                            special
                        } else {
                            ((i * 5 + 1) as f64 * 0.7).sin() * if i % 2 == 0 { 1.0 } else { -2.0 }
                        }
                    });
                    assert_eq!(
                        largest_diagonal_magnitude(&a),
                        fold(&a),
                        "N = {N}, {special} at {at}"
                    );
                }
            }
            // All NaN: passed over, as by `max`.
            let nan = SMatrix::<f64, N, N>::from_element(f64::NAN);
            assert_eq!(largest_diagonal_magnitude(&nan), 0.0);
        }
        check::<0>();
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

    /// The column loop by four-row blocks counted from the last row does,
    /// row for row, the arithmetic of the plain loop from the diagonal
    /// down: the factors are equal bit for bit, at sizes with every head
    /// length, in `f64` and `f32`; the strict upper triangle, read by the
    /// blocks' first rows as scratch, may hold anything (here NaN), and a
    /// zero column in the head or in a block, and a failing pivot, come out
    /// the same.
    #[test]
    fn the_blocked_column_loop_equals_a_row_loop_bit_for_bit() {
        /// Left-looking Cholesky with the plain loops (four columns per
        /// pass from `UNROLL_FROM` on, as the blocked loop takes them).
        fn reference<T: Real, const N: usize>(
            a: &SMatrix<T, N, N>,
            semidefinite: bool,
        ) -> Result<SMatrix<T, N, N>, NotPositiveDefinite> {
            let mut scale = T::zero();
            for i in 0..N {
                scale = scale.max(a[(i, i)].abs());
            }
            let rel = epsilon::<T>() * lit::<T>(N as f64);
            let tol = rel * scale;
            let mut l = *a;
            for j in 0..N {
                let mut k = 0;
                while N >= UNROLL_FROM && k + 4 <= j {
                    let f: [T; 4] = core::array::from_fn(|q| l[(j, k + q)]);
                    for i in j..N {
                        l[(i, j)] = l[(i, j)]
                            - l[(i, k)] * f[0]
                            - l[(i, k + 1)] * f[1]
                            - l[(i, k + 2)] * f[2]
                            - l[(i, k + 3)] * f[3];
                    }
                    k += 4;
                }
                for k in k..j {
                    let f = l[(j, k)];
                    for i in j..N {
                        let v = l[(i, k)] * f;
                        l[(i, j)] -= v;
                    }
                }
                let d = l[(j, j)];
                let root = if !semidefinite {
                    if !regular_pivot(d, a[(j, j)], rel) {
                        return Err(NotPositiveDefinite { index: j });
                    }
                    Some(d.sqrt())
                } else if !d.is_finite() || d < -tol {
                    return Err(NotPositiveDefinite { index: j });
                } else if d > tol || (d > T::zero() && d > rel * a[(j, j)].abs()) {
                    Some(d.sqrt())
                } else {
                    let limit = (tol * scale).sqrt() * lit(4.0);
                    if (j + 1..N).all(|i| l[(i, j)].abs() <= limit) {
                        None
                    } else {
                        return Err(NotPositiveDefinite { index: j });
                    }
                };
                match root {
                    Some(root) => {
                        let inv = root.recip();
                        for i in j + 1..N {
                            l[(i, j)] *= inv;
                        }
                        l[(j, j)] = root;
                    }
                    None => {
                        for i in j..N {
                            l[(i, j)] = T::zero();
                        }
                    }
                }
                for i in 0..j {
                    l[(i, j)] = T::zero();
                }
            }
            Ok(l)
        }
        fn check<T: Real, const N: usize>() {
            let f = |i: usize, j: usize| -> T {
                lit(((i * 7 + j * 3 + N) as f64 * 0.37).sin() + 0.1 * ((i * j) as f64).cos())
            };
            let a = SMatrix::<T, N, N>::from_fn(f);
            let mut p = a * a.transpose() + SMatrix::identity();
            let mut garbage = p;
            for j in 0..N {
                for i in 0..j {
                    garbage[(i, j)] = lit(f64::NAN);
                }
            }
            assert_eq!(cholesky_by(&garbage, false), reference(&p, false));
            assert!(cholesky_by(&p, false).is_ok());
            // A zero state in the head (row 0) and in the last block.
            for zero in [0, N - 1, N / 2] {
                let z =
                    SMatrix::<T, N, N>::from_fn(|i, j| if i == zero { T::zero() } else { f(i, j) });
                let q = z * z.transpose();
                let mut ours = q;
                semidefinite_by(&mut ours, false).unwrap();
                assert_eq!(Ok(ours), reference(&q, true));
                assert_eq!(ours.column(zero).norm(), T::zero());
            }
            // Indefinite at the last pivot: the same error.
            p[(N - 1, N - 1)] = -p[(N - 1, N - 1)];
            assert_eq!(cholesky_by(&p, false), reference(&p, false));
            assert!(cholesky_by(&p, false).is_err());
        }
        check::<f64, 1>();
        check::<f64, 2>();
        check::<f64, 3>();
        check::<f64, 4>();
        check::<f64, 5>();
        check::<f64, 9>();
        check::<f64, 10>();
        check::<f64, 11>();
        check::<f64, 12>();
        check::<f64, 13>();
        check::<f64, 15>();
        check::<f64, 18>();
        check::<f32, 15>();
        check::<f32, 17>();
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
