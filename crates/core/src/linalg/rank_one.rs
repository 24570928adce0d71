use nalgebra::{SMatrix, SVector};

use super::product::lanes;
use super::NotPositiveDefinite;
use crate::real::{epsilon, finite};
use crate::Real;

/// `S Sᵀ ← S Sᵀ + v vᵀ` for a lower-triangular factor `S`, by Givens
/// rotations. Works from a singular (even zero) factor.
///
/// Fails only on non-finite input; `s` is unchanged on failure.
///
/// ```
/// use kestrel_core::linalg::rank_one_update;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let mut s = Matrix2::new(1.0, 0.0, 0.0, 1.0);
/// rank_one_update(&mut s, &Vector2::new(1.0, 0.0)).unwrap();
/// assert!((s * s.transpose() - Matrix2::new(2.0, 0.0, 0.0, 1.0)).norm() < 1e-15);
/// ```
pub fn rank_one_update<T: Real, const N: usize>(
    s: &mut SMatrix<T, N, N>,
    v: &SVector<T, N>,
) -> Result<(), NotPositiveDefinite> {
    let mut work = *s;
    let mut v = *v;
    update_in_place(&mut work, &mut v).map_err(|index| NotPositiveDefinite { index })?;
    *s = work;
    Ok(())
}

/// `S Sᵀ ← S Sᵀ − v vᵀ` for a lower-triangular factor `S`, by hyperbolic
/// rotations, **checked**: if the result would not be positive definite to
/// working precision (a pivot `r² = S_kk² − v_k²` not above `ε·S_kk²`), the
/// failing pivot is returned and `s` is left unchanged, instead of filling
/// the factor with NaN.
///
/// ```
/// use kestrel_core::linalg::rank_one_downdate;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let mut s = Matrix2::new(2.0, 0.0, 0.0, 1.0);
/// rank_one_downdate(&mut s, &Vector2::new(1.0, 0.0)).unwrap();
/// assert!((s * s.transpose() - Matrix2::new(3.0, 0.0, 0.0, 1.0)).norm() < 1e-15);
/// // Removing more than is there fails and leaves `s` alone.
/// let err = rank_one_downdate(&mut s, &Vector2::new(0.0, 2.0)).unwrap_err();
/// assert_eq!(err.index, 1);
/// assert_eq!(s[(1, 1)], 1.0);
/// ```
pub fn rank_one_downdate<T: Real, const N: usize>(
    s: &mut SMatrix<T, N, N>,
    v: &SVector<T, N>,
) -> Result<(), NotPositiveDefinite> {
    let mut work = *s;
    let mut v = *v;
    downdate_in_place(&mut work, &mut v).map_err(|index| NotPositiveDefinite { index })?;
    *s = work;
    Ok(())
}

/// `S Sᵀ ← S Sᵀ + w v vᵀ`: an update for `w ≥ 0`, a checked downdate for
/// `w < 0`. `s` is unchanged on failure.
///
/// ```
/// use kestrel_core::linalg::weighted_rank_one;
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// let mut s = Matrix1::new(3.0_f64);
/// weighted_rank_one(&mut s, &Vector1::new(2.0), -1.25).unwrap();
/// assert!((s[0] - 2.0).abs() < 1e-15);
/// ```
pub fn weighted_rank_one<T: Real, const N: usize>(
    s: &mut SMatrix<T, N, N>,
    v: &SVector<T, N>,
    w: T,
) -> Result<(), NotPositiveDefinite> {
    let mut work = *s;
    weighted_rank_one_in_place(&mut work, v, w)?;
    *s = work;
    Ok(())
}

/// [`weighted_rank_one`] without the copy that keeps `s` on failure: on
/// error `s` is partly modified and must be discarded.
pub(crate) fn weighted_rank_one_in_place<T: Real, const N: usize>(
    s: &mut SMatrix<T, N, N>,
    v: &SVector<T, N>,
    w: T,
) -> Result<(), NotPositiveDefinite> {
    let mut scaled = *v;
    let f = w.abs().sqrt();
    for x in scaled.as_mut_slice() {
        *x *= f;
    }
    if w >= T::zero() {
        update_in_place(s, &mut scaled)
    } else {
        downdate_in_place(s, &mut scaled)
    }
    .map_err(|index| NotPositiveDefinite { index })
}

/// In-place Givens update; `v` is destroyed. On error (non-finite values)
/// `s` is partly modified and must be discarded.
pub(crate) fn update_in_place<T: Real, const N: usize>(
    s: &mut SMatrix<T, N, N>,
    v: &mut SVector<T, N>,
) -> Result<(), usize> {
    let s = s.as_mut_slice();
    let v = v.as_mut_slice();
    for k in 0..N {
        let b = v[k];
        if b == T::zero() {
            continue;
        }
        let a = s[k * N + k];
        let r = (a * a + b * b).sqrt();
        if !finite(r) {
            return Err(k);
        }
        let c = a / r;
        let sn = b / r;
        s[k * N + k] = r;
        let col = &mut s[k * N + k + 1..k * N + N];
        let rest = &mut v[k + 1..];
        for (t, u) in col.iter_mut().zip(rest.iter_mut()) {
            let (tv, uv) = (*t, *u);
            *t = c * tv + sn * uv;
            *u = c * uv - sn * tv;
        }
    }
    Ok(())
}

/// In-place hyperbolic downdate; `v` is destroyed. On error `s` is partly
/// modified and must be discarded.
pub(crate) fn downdate_in_place<T: Real, const N: usize>(
    s: &mut SMatrix<T, N, N>,
    v: &mut SVector<T, N>,
) -> Result<(), usize> {
    if N == 0 {
        return Ok(());
    }
    let s = s.as_mut_slice().as_chunks_mut::<N>().0;
    let v = &mut v.data.0[0];
    for (k, col) in s.iter_mut().enumerate() {
        if !downdate_pivot(col, v, k) {
            return Err(k);
        }
    }
    Ok(())
}

/// `M` hyperbolic downdates of `s` by the columns of `u`, in an order that
/// lets the chains of square roots and divisions overlap. Pivot `(k, j)`
/// (pivot `k` of column `j`) reads column `k` of `s` as pivot `(k, j − 1)`
/// left it and column `j` of `u` as pivot `(k − 1, j)` left it, nothing
/// else; so the pivots of one anti-diagonal `k + j = d` are independent,
/// and the pivots are done anti-diagonal by anti-diagonal (`N + M − 1`
/// dependent steps instead of `N M`). Every pivot does the same arithmetic
/// on the same values as one downdate after the other, so the result is
/// bit for bit that of [`downdate_in_place`] per column. `u` is destroyed.
/// `Err(())` when some pivot fails; `s` is then partly modified and must
/// be discarded (the caller finds which column and pivot with the
/// one-by-one downdates).
pub(crate) fn downdate_columns_in_place<T: Real, const N: usize, const M: usize>(
    s: &mut SMatrix<T, N, N>,
    u: &mut SMatrix<T, N, M>,
) -> Result<(), ()> {
    if N == 0 {
        return Ok(());
    }
    let s = s.as_mut_slice().as_chunks_mut::<N>().0;
    let u = u.as_mut_slice().as_chunks_mut::<N>().0;
    for d in 0..N + M - 1 {
        // Columns j ≤ d with pivot k = d − j inside the factor (k < N); a
        // constant trip count with the bounds as conditions, so it unrolls.
        for (j, column) in u.iter_mut().enumerate() {
            if j <= d && d - j < N {
                let k = d - j;
                if !downdate_pivot(&mut s[k], column, k) {
                    return Err(());
                }
            }
        }
    }
    Ok(())
}

/// Pivot `k` of a hyperbolic downdate: column `k` of the lower factor
/// (`col`, all `N` rows) and the vector being removed (`v`). `false` when
/// the pivot would not stay positive (or is not finite); nothing is then
/// written.
///
/// The rows below the pivot are taken in whole blocks counted from the
/// last row (see [`rows_in_blocks`]), so no pivot ends in scalar rows. The
/// block holding row `k + 1` may begin above it; there the factor's column
/// is zero (above the diagonal) and so is the vector (set to zero at each
/// row's own pivot, where it is read for the last time), so those rows
/// compute `+0` from `+0` exactly, and the pivot's own row is then set to
/// `r` (and the vector's to zero). The rows below the pivot get the
/// arithmetic of a loop over them alone, so the factor is the same bit for
/// bit; `v` is destroyed.
#[inline(always)]
fn downdate_pivot<T: Real, const N: usize>(col: &mut [T; N], v: &mut [T; N], k: usize) -> bool {
    let b = v[k];
    if b == T::zero() {
        return true;
    }
    let a = col[k];
    // (a − b)(a + b) keeps the difference accurate when |b| ≈ a.
    let r2 = (a - b) * (a + b);
    if !(r2 > epsilon::<T>() * a * a && finite(r2)) {
        return false;
    }
    let r = r2.sqrt();
    // Two divisions per pivot, not three: c = r / a, s = b / a through
    // 1 / a, and 1 / c = a / r.
    let inv_a = a.recip();
    let c = r * inv_a;
    let sn = b * inv_a;
    let inv_c = a / r;
    // Blocks of four rows where a vector register holds four or more
    // (`f32`; `f64` with AVX), else of two (`f64` on SSE2) up to 16 states:
    // whole registers below the pivot, and few rows computed above it.
    // From 18 states the columns are long enough that four rows a block
    // are the cheaper in `f64` too.
    if const { lanes::<T>() >= 4 || N > 16 } {
        rows_in_blocks::<T, N, 4>(col, v, k, (c, sn, inv_c));
    } else {
        rows_in_blocks::<T, N, 2>(col, v, k, (c, sn, inv_c));
    }
    col[k] = r;
    v[k] = T::zero();
    true
}

/// The rows below pivot `k` of [`downdate_pivot`] with the rotation
/// `(c, s, 1/c)`, in blocks of `B` counted from the last row (the first
/// `N mod B` rows a head taken one at a time), each block read and written
/// whole.
#[inline(always)]
fn rows_in_blocks<T: Real, const N: usize, const B: usize>(
    col: &mut [T; N],
    v: &mut [T; N],
    k: usize,
    (c, sn, inv_c): (T, T, T),
) {
    let head = N % B;
    // A constant trip count, the bound as a condition: it unrolls.
    for i in 0..head {
        if i > k {
            let tn = (col[i] - sn * v[i]) * inv_c;
            col[i] = tn;
            v[i] = c * v[i] - sn * tn;
        }
    }
    let (tb, ub) = (
        col[head..].as_chunks_mut::<B>().0,
        v[head..].as_chunks_mut::<B>().0,
    );
    let first = (k + 1).saturating_sub(head) / B;
    for q in first..N / B {
        // Read whole, written whole (as in the Cholesky factorisation).
        let (mut t, mut u) = (tb[q], ub[q]);
        for l in 0..B {
            let tn = (t[l] - sn * u[l]) * inv_c;
            t[l] = tn;
            u[l] = c * u[l] - sn * tn;
        }
        tb[q] = t;
        ub[q] = u;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::cholesky;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix3, Vector3};

    fn spd() -> Matrix3<f64> {
        let a = Matrix3::new(2.0, 0.3, -0.1, 0.5, 1.5, 0.2, -0.4, 0.1, 1.0);
        a * a.transpose() + Matrix3::identity()
    }

    #[test]
    fn update_matches_refactorisation() {
        let p = spd();
        let v = Vector3::new(0.7, -1.2, 0.4);
        let mut s = cholesky(&p).unwrap();
        rank_one_update(&mut s, &v).unwrap();
        assert_relative_eq!(
            s,
            cholesky(&(p + v * v.transpose())).unwrap(),
            epsilon = 1e-13
        );
    }

    #[test]
    fn downdate_matches_refactorisation() {
        let p = spd();
        let v = Vector3::new(0.3, -0.2, 0.25);
        let mut s = cholesky(&p).unwrap();
        rank_one_downdate(&mut s, &v).unwrap();
        assert_relative_eq!(
            s,
            cholesky(&(p - v * v.transpose())).unwrap(),
            epsilon = 1e-13
        );
    }

    #[test]
    fn update_from_zero_builds_a_factor() {
        let mut s = Matrix3::zeros();
        let vs = [
            Vector3::new(1.0, 2.0, 3.0),
            Vector3::new(0.0, 1.0, -1.0),
            Vector3::new(2.0, 0.0, 1.0),
        ];
        let mut p = Matrix3::zeros();
        for v in &vs {
            rank_one_update(&mut s, v).unwrap();
            p += v * v.transpose();
        }
        assert_relative_eq!(s * s.transpose(), p, epsilon = 1e-13);
        assert!((0..3).all(|i| s[(i, i)] >= 0.0));
    }

    #[test]
    fn failed_downdate_leaves_the_factor_alone_and_never_nan() {
        let p = spd();
        let s0 = cholesky(&p).unwrap();
        let mut s = s0;
        let big = Vector3::new(10.0, 0.0, 0.0);
        assert!(rank_one_downdate(&mut s, &big).is_err());
        assert_eq!(s, s0);
        // Downdating exactly to singular is refused too.
        let exact = s0.column(0).into_owned();
        assert_eq!(
            rank_one_downdate(&mut s, &exact),
            Err(NotPositiveDefinite { index: 0 })
        );
    }

    #[test]
    fn weighted_chooses_update_or_downdate() {
        let p = spd();
        let v = Vector3::new(0.1, 0.2, 0.3);
        for w in [2.0, -0.5] {
            let mut s = cholesky(&p).unwrap();
            weighted_rank_one(&mut s, &v, w).unwrap();
            assert_relative_eq!(
                s * s.transpose(),
                p + v * v.transpose() * w,
                epsilon = 1e-13
            );
        }
    }

    /// The across-columns downdate against one downdate per column, for a
    /// factor of `N` states and `M` columns.
    fn across_equals_one_by_one<const N: usize, const M: usize>() {
        let a =
            nalgebra::SMatrix::<f64, N, N>::from_fn(|i, j| ((i * 3 + j * 5) as f64 * 0.7).sin());
        let p = a * a.transpose() + nalgebra::SMatrix::identity() * (2.0 * M as f64);
        let s0 = cholesky(&p).unwrap();
        let u =
            nalgebra::SMatrix::<f64, N, M>::from_fn(|i, j| ((i + 4 * j) as f64 * 0.9).cos() * 0.4);
        let mut one_by_one = s0;
        for j in 0..M {
            let mut col = u.column(j).into_owned();
            downdate_in_place(&mut one_by_one, &mut col).unwrap();
        }
        let mut across = s0;
        let mut work = u;
        downdate_columns_in_place(&mut across, &mut work).unwrap();
        assert_eq!(across, one_by_one, "{N} states, {M} columns");
    }

    /// The textbook downdate, one row after another below each pivot.
    fn by_rows<T: Real, const N: usize>(s: &mut SMatrix<T, N, N>, v: &mut SVector<T, N>) {
        for k in 0..N {
            let (a, b) = (s[(k, k)], v[k]);
            if b == T::zero() {
                continue;
            }
            let r = ((a - b) * (a + b)).sqrt();
            let inv_a = a.recip();
            let (c, sn, inv_c) = (r * inv_a, b * inv_a, a / r);
            s[(k, k)] = r;
            for i in k + 1..N {
                let tn = (s[(i, k)] - sn * v[i]) * inv_c;
                s[(i, k)] = tn;
                v[i] = c * v[i] - sn * tn;
            }
        }
    }

    /// The downdate in blocks (of two or four rows, by type and size, the
    /// first one reaching above the pivot) gives the textbook row loop's
    /// factor bit for bit, and keeps the strict upper triangle exactly
    /// zero, in `f64` and `f32`, on sizes on both sides of each block
    /// length and of 16 states.
    #[test]
    fn the_blocked_downdate_is_the_row_loop_bit_for_bit() {
        fn check<T: Real, const N: usize>() {
            let a = SMatrix::<f64, N, N>::from_fn(|i, j| ((i * 3 + j * 5) as f64 * 0.7).sin());
            let p = a * a.transpose() + SMatrix::identity() * (2.0 + N as f64);
            let s0 = cholesky(&p.map(crate::real::lit::<T>)).unwrap();
            let v0 = SVector::<f64, N>::from_fn(|i, _| ((i * 7) as f64 * 0.9).cos() * 0.6)
                .map(crate::real::lit::<T>);
            let (mut blocked, mut v) = (s0, v0);
            downdate_in_place(&mut blocked, &mut v).unwrap();
            let (mut reference, mut w) = (s0, v0);
            by_rows(&mut reference, &mut w);
            assert_eq!(blocked, reference, "{N} states");
            for j in 0..N {
                for i in 0..j {
                    assert!(blocked[(i, j)] == T::zero(), "{N} states, ({i}, {j})");
                }
            }
            // Several columns at once, by anti-diagonals: the same factor.
            let u = SMatrix::<f64, N, 3>::from_fn(|i, j| ((i + 5 * j) as f64 * 0.8).sin() * 0.3)
                .map(crate::real::lit::<T>);
            let (mut across, mut work) = (s0, u);
            downdate_columns_in_place(&mut across, &mut work).unwrap();
            let mut one_by_one = s0;
            for j in 0..3 {
                let mut col = u.column(j).into_owned();
                by_rows(&mut one_by_one, &mut col);
            }
            assert_eq!(across, one_by_one, "{N} states, three columns");
        }
        check::<f64, 1>();
        check::<f64, 2>();
        check::<f64, 3>();
        check::<f64, 5>();
        check::<f64, 7>();
        check::<f64, 15>();
        check::<f64, 17>();
        check::<f64, 18>();
        check::<f64, 24>();
        check::<f32, 1>();
        check::<f32, 3>();
        check::<f32, 4>();
        check::<f32, 6>();
        check::<f32, 15>();
        check::<f32, 18>();
    }

    #[test]
    fn downdates_across_columns_equal_one_after_the_other_in_every_shape() {
        // More columns than states, as many, fewer, and the edge sizes.
        across_equals_one_by_one::<1, 1>();
        across_equals_one_by_one::<1, 3>();
        across_equals_one_by_one::<3, 1>();
        across_equals_one_by_one::<3, 5>();
        across_equals_one_by_one::<4, 4>();
        across_equals_one_by_one::<9, 2>();
        across_equals_one_by_one::<15, 6>();
    }

    #[test]
    fn downdates_across_columns_equal_one_after_the_other_bit_for_bit() {
        // A 7-state factor, three columns to remove (one with zeros, which
        // both skip), small enough that every downdate succeeds.
        let a =
            nalgebra::SMatrix::<f64, 7, 7>::from_fn(|i, j| ((i * 3 + j * 5) as f64 * 0.7).sin());
        let p = a * a.transpose() + nalgebra::SMatrix::identity() * 4.0;
        let s0 = cholesky(&p).unwrap();
        let mut u =
            nalgebra::SMatrix::<f64, 7, 3>::from_fn(|i, j| ((i + 4 * j) as f64 * 0.9).cos() * 0.5);
        u[(2, 1)] = 0.0;
        u[(0, 2)] = 0.0;
        let mut one_by_one = s0;
        for j in 0..3 {
            let mut col = u.column(j).into_owned();
            downdate_in_place(&mut one_by_one, &mut col).unwrap();
        }
        let mut across = s0;
        let mut work = u;
        downdate_columns_in_place(&mut across, &mut work).unwrap();
        assert_eq!(across, one_by_one);
        assert_relative_eq!(
            across * across.transpose(),
            p - u * u.transpose(),
            epsilon = 1e-12
        );
        // Too much to remove: refused (the caller then names the column).
        let mut s = s0;
        let mut big = u * 10.0;
        assert_eq!(downdate_columns_in_place(&mut s, &mut big), Err(()));
    }
}
