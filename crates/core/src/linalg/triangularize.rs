use core::hint::black_box;

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
    let ss = s.as_mut_slice();
    let mut w = [T::zero(); N];
    for k in 0..N {
        let alpha = ss[k * N + k];
        let mut sigma2 = T::zero();
        for c in cols.iter() {
            sigma2 += c[k] * c[k];
        }
        let Some((beta, v0, tau)) = reflector(alpha, sigma2) else {
            flip_if_negative(&mut ss[k * N + k..k * N + N]);
            continue;
        };
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
        ss[k * N + k] = beta;
        flip_if_negative(&mut ss[k * N + k..k * N + N]);
    }
}

/// [`add_columns`] for `2N` columns given by rows: `rows[i]` holds element
/// `i` of every column (the `N` "plus" columns, then the `N` "minus" ones),
/// the layout in which each reflection is `D` dot products and `D` axpys
/// of length `2N` over contiguous memory, which vectorise, instead of
/// `2N` short column loops per row. Equal to [`add_columns`] to rounding
/// (the dot products are summed in four lanes); `rows` is scratch.
///
/// From [`PAIRS_FROM`] states the reflections are applied two at a time
/// (see [`in_pairs`]); below, one at a time, whose loop the compiler
/// unrolls.
pub(crate) fn add_columns_by_rows<T: Real, const D: usize, const N: usize>(
    s: &mut SMatrix<T, D, D>,
    rows: &mut [[[T; N]; 2]; D],
) {
    if D < PAIRS_FROM {
        one_at_a_time(s, rows);
    } else {
        in_pairs(s, rows);
    }
}

/// The state size from which [`add_columns_by_rows`] applies its
/// reflections in pairs, which read each row half as often: below it the
/// loop of one reflection at a time is unrolled whole and the pairs' loop
/// is not, and the unrolled loop is the cheaper.
const PAIRS_FROM: usize = 6;

/// [`add_columns_by_rows`] one reflection at a time.
fn one_at_a_time<T: Real, const D: usize, const N: usize>(
    s: &mut SMatrix<T, D, D>,
    rows: &mut [[[T; N]; 2]; D],
) {
    let ss = s.as_mut_slice();
    // ‖row k‖², computed while row k is updated at step k − 1 (it is the
    // next pivot's input, so computing it then shortens the chain from one
    // reflection to the next).
    let mut sigma2 = first_norm2(rows);
    for k in 0..D {
        let (head, tail) = rows.split_at_mut(k + 1);
        let rk = head[k].as_flattened();
        let alpha = ss[k * D + k];
        let Some((beta, v0, tau)) = reflector(alpha, sigma2) else {
            flip_if_negative(&mut ss[k * D + k..k * D + D]);
            sigma2 = first_norm2(tail);
            continue;
        };
        let below = &mut ss[k * D + k + 1..k * D + D];
        sigma2 = reflect_rows(tail.iter_mut().zip(below.iter_mut()), rk, v0, tau);
        set_diagonal::<T, D>(ss, k, beta);
    }
}

/// [`add_columns_by_rows`] with the reflections applied two at a time,
/// `k` and `k + 1`, in the compact WY form of their product (R. Schreiber
/// and C. Van Loan, "A storage-efficient WY representation for products of
/// Householder transformations", SIAM J. Sci. Stat. Comput. 10(1), 53–57,
/// 1989): row `k + 1` takes reflection `k` alone, which gives reflection
/// `k + 1`; each row `i` below then takes both in one pass of two dot
/// products, `aᵢ = rᵢ·r_k` and `bᵢ = rᵢ·r_{k+1}`, and one pass of two
/// axpys. Reflection `k + 1` needs the row as reflection `k` left it, whose
/// dot product with `r_{k+1}` is `bᵢ − wᵢ (r_k·r_{k+1})`. Each row is read
/// twice per pair of reflections instead of four times, and the rows below
/// go two at a time, sharing the loads of `r_k` and `r_{k+1}`.
fn in_pairs<T: Real, const D: usize, const N: usize>(
    s: &mut SMatrix<T, D, D>,
    rows: &mut [[[T; N]; 2]; D],
) {
    let ss = s.as_mut_slice();
    // ‖row k‖², computed while row k is updated by the reflections before
    // (it is the next pivot's input, so computing it then shortens the
    // chain from one reflection to the next).
    let mut sigma2 = first_norm2(rows);
    let mut k = 0;
    while k < D {
        let (head, tail) = rows.split_at_mut(k + 1);
        let Some((beta, v0, tau)) = reflector(ss[k * D + k], sigma2) else {
            flip_if_negative(&mut ss[k * D + k..k * D + D]);
            sigma2 = first_norm2(tail);
            k += 1;
            continue;
        };
        let [next, rest @ ..] = tail else {
            // Row k is the last.
            set_diagonal::<T, D>(ss, k, beta);
            break;
        };
        let k1 = k + 1;
        // Row k + 1 by reflection k alone: the input of reflection k + 1.
        let w = (ss[k * D + k1] * v0 + dot(next.as_flattened(), head[k].as_flattened())) * tau;
        ss[k * D + k1] -= w * v0;
        if rest.is_empty() {
            // Row k + 1 is the last: reflection k + 1 has nothing below,
            // and the small sizes are spared the pairs' copies.
            sigma2 = axpy_norm2(next.as_flattened_mut(), head[k].as_flattened(), w);
            set_diagonal::<T, D>(ss, k, beta);
            k += 1;
            continue;
        }
        // Copies, so the compiler knows the rows being updated alias
        // neither reflection.
        let rk = head[k];
        let rk = rk.as_flattened();
        let next_sigma2 = axpy_norm2(next.as_flattened_mut(), rk, w);
        let next = *next;
        let next = next.as_flattened();
        // Column k below row k + 1, and column k + 1 below its diagonal.
        let (left, right) = ss.split_at_mut(k1 * D);
        let column_k = &mut left[k * D + k1 + 1..];
        let second = reflector(right[k1], next_sigma2);
        let column_k1 = &mut right[k1 + 1..D];
        let mut below = rest
            .iter_mut()
            .zip(column_k.iter_mut().zip(column_k1.iter_mut()));
        if let Some((_, v01, tau1)) = second {
            let c = dot(rk, next);
            // Both reflections' weights for a row, its two factor entries
            // updated.
            let weights = |sk: &mut T, sk1: &mut T, a: T, b: T| {
                let wk = (*sk * v0 + a) * tau;
                *sk -= wk * v0;
                let w1 = (*sk1 * v01 + (b - wk * c)) * tau1;
                *sk1 -= w1 * v01;
                (wk, w1)
            };
            if let Some((ri, (sk, sk1))) = below.next() {
                let ri = ri.as_flattened_mut();
                let (a, b) = dot2(ri, rk, next);
                let (wk, w1) = weights(sk, sk1, a, b);
                sigma2 = axpy2(ri, rk, wk, next, w1, true);
            }
            // The other rows two at a time, sharing each load of r_k and
            // r_{k+1}.
            loop {
                match (below.next(), below.next()) {
                    (Some((r0, (s0, t0))), Some((r1, (s1, t1)))) => {
                        let (r0, r1) = (r0.as_flattened_mut(), r1.as_flattened_mut());
                        let [a0, b0, a1, b1] = dot2x2(r0, r1, rk, next);
                        let w0 = weights(s0, t0, a0, b0);
                        let w1 = weights(s1, t1, a1, b1);
                        axpy2x2(r0, r1, rk, next, w0, w1);
                    }
                    (Some((ri, (sk, sk1))), None) => {
                        let ri = ri.as_flattened_mut();
                        let (a, b) = dot2(ri, rk, next);
                        let (wk, w1) = weights(sk, sk1, a, b);
                        axpy2(ri, rk, wk, next, w1, false);
                        break;
                    }
                    _ => break,
                }
            }
        } else {
            // Row k + 1 has nothing left to fold: the rows below take
            // reflection k alone.
            sigma2 = reflect_rows(below.map(|(ri, (sk, _))| (ri, sk)), rk, v0, tau);
        }
        set_diagonal::<T, D>(ss, k, beta);
        match second {
            Some((beta1, _, _)) => set_diagonal::<T, D>(ss, k1, beta1),
            None => flip_if_negative(&mut ss[k1 * D + k1..k1 * D + D]),
        }
        k += 2;
    }
}

/// ‖rows[0]‖², zero if there is no row.
#[inline(always)]
fn first_norm2<T: Real, const N: usize>(rows: &[[[T; N]; 2]]) -> T {
    rows.first()
        .map_or(T::zero(), |r| dot(r.as_flattened(), r.as_flattened()))
}

/// The reflection `(v₀, τ)` with vector `r` applied to `rows`, each with
/// its entry of the reflection's column of the factor; returns ‖first
/// row‖² after it (the next pivot's input), zero if there is no row.
#[inline(always)]
fn reflect_rows<'a, T: Real, const N: usize>(
    rows: impl Iterator<Item = (&'a mut [[T; N]; 2], &'a mut T)>,
    r: &[T],
    v0: T,
    tau: T,
) -> T {
    let mut first_norm2 = T::zero();
    for (i, (ri, si)) in rows.enumerate() {
        let ri = ri.as_flattened_mut();
        let wi = (*si * v0 + dot(ri, r)) * tau;
        *si -= wi * v0;
        if i == 0 {
            first_norm2 = axpy_norm2(ri, r, wi);
        } else {
            for (c, &f) in ri.iter_mut().zip(r) {
                *c -= wi * f;
            }
        }
    }
    first_norm2
}

/// Column `k`'s diagonal (of a `D × D` factor's slice) set to the
/// reflection's `β`, and the column from the diagonal down negated if that
/// is negative.
#[inline(always)]
fn set_diagonal<T: Real, const D: usize>(ss: &mut [T], k: usize, beta: T) {
    ss[k * D + k] = beta;
    flip_if_negative(&mut ss[k * D + k..k * D + D]);
}

/// The Householder reflection taking `(α, c)` with `‖c‖² = σ²` onto
/// `(β, 0)`: `(β, v₀, τ)` with `β = −sign(α)·√(α² + σ²)`, `v₀ = α − β` (no
/// cancellation) and `τ = 2 / (v₀² + σ²)`; `None` when `σ² = 0` (nothing to
/// fold).
#[inline(always)]
fn reflector<T: Real>(alpha: T, sigma2: T) -> Option<(T, T, T)> {
    if sigma2 == T::zero() {
        return None;
    }
    let norm = (alpha * alpha + sigma2).sqrt();
    let beta = if alpha >= T::zero() { -norm } else { norm };
    let v0 = alpha - beta;
    Some((beta, v0, (T::one() + T::one()) / (v0 * v0 + sigma2)))
}

/// Negates a factor's column (from the diagonal down) whose diagonal is
/// negative: an orthogonal transformation from the right, so the factor
/// keeps a non-negative diagonal.
#[inline(always)]
fn flip_if_negative<T: Real>(column: &mut [T]) {
    if column[0] < T::zero() {
        for v in column {
            *v = -*v;
        }
    }
}

/// `a ← a − w b`, returning `‖a‖²` of the result (summed in the lanes of
/// [`dot`]).
#[inline(always)]
fn axpy_norm2<T: Real>(a: &mut [T], b: &[T], w: T) -> T {
    let mut lanes = [T::zero(); 4];
    let (a4, a_rest) = a.as_chunks_mut::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    for (x, y) in a4.iter_mut().zip(b4) {
        for l in 0..4 {
            x[l] -= w * y[l];
            lanes[l] += x[l] * x[l];
        }
    }
    let mut sum = sum_lanes(lanes, a4.len());
    for (x, y) in a_rest.iter_mut().zip(b_rest) {
        *x -= w * *y;
        sum += *x * *x;
    }
    sum
}

/// `x ← x − wa a − wb b`, returning `‖x‖²` of the result (summed in the
/// lanes of [`dot`]) if `with_norm`, else zero.
#[inline(always)]
fn axpy2<T: Real>(x: &mut [T], a: &[T], wa: T, b: &[T], wb: T, with_norm: bool) -> T {
    let mut lanes = [T::zero(); 4];
    let (x4, x_rest) = x.as_chunks_mut::<4>();
    let (a4, a_rest) = a.as_chunks::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    if with_norm {
        for ((x, a), b) in x4.iter_mut().zip(a4).zip(b4) {
            for l in 0..4 {
                x[l] = (x[l] - wa * a[l]) - wb * b[l];
                lanes[l] += x[l] * x[l];
            }
        }
    } else {
        for ((x, a), b) in x4.iter_mut().zip(a4).zip(b4) {
            for l in 0..4 {
                x[l] = (x[l] - wa * a[l]) - wb * b[l];
            }
        }
    }
    let mut sum = if with_norm {
        sum_lanes(lanes, x4.len())
    } else {
        T::zero()
    };
    for ((x, a), b) in x_rest.iter_mut().zip(a_rest).zip(b_rest) {
        *x = (*x - wa * *a) - wb * *b;
        if with_norm {
            sum += *x * *x;
        }
    }
    sum
}

/// `[x·a, x·b, y·a, y·b]`, each in the four lanes of [`dot`], in one pass.
#[inline(always)]
fn dot2x2<T: Real>(x: &[T], y: &[T], a: &[T], b: &[T]) -> [T; 4] {
    let mut lanes = [[T::zero(); 4]; 4];
    let (x4, x_rest) = x.as_chunks::<4>();
    let (y4, y_rest) = y.as_chunks::<4>();
    let (a4, a_rest) = a.as_chunks::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    for (((x, y), a), b) in x4.iter().zip(y4).zip(a4).zip(b4) {
        for l in 0..4 {
            lanes[0][l] += x[l] * a[l];
            lanes[1][l] += x[l] * b[l];
            lanes[2][l] += y[l] * a[l];
            lanes[3][l] += y[l] * b[l];
        }
    }
    let n = x4.len();
    let mut sums = [
        sum_lanes(lanes[0], n),
        sum_lanes(lanes[1], n),
        sum_lanes(lanes[2], n),
        sum_lanes(lanes[3], n),
    ];
    for (((x, y), a), b) in x_rest.iter().zip(y_rest).zip(a_rest).zip(b_rest) {
        sums[0] += *x * *a;
        sums[1] += *x * *b;
        sums[2] += *y * *a;
        sums[3] += *y * *b;
    }
    sums
}

/// `x ← x − wx₀ a − wx₁ b` and `y ← y − wy₀ a − wy₁ b` in one pass.
#[inline(always)]
fn axpy2x2<T: Real>(x: &mut [T], y: &mut [T], a: &[T], b: &[T], wx: (T, T), wy: (T, T)) {
    let (x4, x_rest) = x.as_chunks_mut::<4>();
    let (y4, y_rest) = y.as_chunks_mut::<4>();
    let (a4, a_rest) = a.as_chunks::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    for (((x, y), a), b) in x4.iter_mut().zip(y4).zip(a4).zip(b4) {
        for l in 0..4 {
            x[l] = (x[l] - wx.0 * a[l]) - wx.1 * b[l];
            y[l] = (y[l] - wy.0 * a[l]) - wy.1 * b[l];
        }
    }
    for (((x, y), a), b) in x_rest.iter_mut().zip(y_rest).zip(a_rest).zip(b_rest) {
        *x = (*x - wx.0 * *a) - wx.1 * *b;
        *y = (*y - wy.0 * *a) - wy.1 * *b;
    }
}

/// `(x·a, x·b)`, each in the four lanes of [`dot`], in one pass over `x`.
#[inline(always)]
fn dot2<T: Real>(x: &[T], a: &[T], b: &[T]) -> (T, T) {
    let mut lanes_a = [T::zero(); 4];
    let mut lanes_b = [T::zero(); 4];
    let (x4, x_rest) = x.as_chunks::<4>();
    let (a4, a_rest) = a.as_chunks::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    for ((x, a), b) in x4.iter().zip(a4).zip(b4) {
        for l in 0..4 {
            lanes_a[l] += x[l] * a[l];
            lanes_b[l] += x[l] * b[l];
        }
    }
    let mut sum_a = sum_lanes(lanes_a, x4.len());
    let mut sum_b = sum_lanes(lanes_b, x4.len());
    for ((x, a), b) in x_rest.iter().zip(a_rest).zip(b_rest) {
        sum_a += *x * *a;
        sum_b += *x * *b;
    }
    (sum_a, sum_b)
}

/// `Σ aᵢ bᵢ` in four independent lanes (so it vectorises).
#[inline(always)]
fn dot<T: Real>(a: &[T], b: &[T]) -> T {
    let mut lanes = [T::zero(); 4];
    let (a4, a_rest) = a.as_chunks::<4>();
    let (b4, b_rest) = b.as_chunks::<4>();
    for (x, y) in a4.iter().zip(b4) {
        for l in 0..4 {
            lanes[l] += x[l] * y[l];
        }
    }
    let mut sum = sum_lanes(lanes, a4.len());
    for (x, y) in a_rest.iter().zip(b_rest) {
        sum += *x * *y;
    }
    sum
}

/// The sum of four lanes, `(l₀ + l₂) + (l₁ + l₃)`, accumulated over
/// `chunks` blocks of four.
///
/// From two blocks on, the lanes pass through [`black_box`] first. Without
/// it, LLVM's SLP vectoriser plans the lanes' registers from this final
/// sum backwards, and can regroup every product vector by shuffles into
/// the pairs that sum (it does for the order `(l₀ + l₁) + (l₂ + l₃)`, in
/// `f32` and in `f64`). Seen as an opaque value, the lanes stay one
/// register of four `f32` or two of two `f64`, and this order sums their
/// halves first.
/// With one block there is nothing to regroup, and the store and load the
/// barrier costs are left out (the lengths are constants, so the test is
/// too).
#[inline(always)]
fn sum_lanes<T: Real>(lanes: [T; 4], chunks: usize) -> T {
    let lanes = if chunks > 1 { black_box(lanes) } else { lanes };
    (lanes[0] + lanes[2]) + (lanes[1] + lanes[3])
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
    #[test]
    fn by_rows_equals_by_columns() {
        // 5 states and 2 × 7 columns (not a multiple of the four lanes),
        // from a singular start with a negative diagonal entry.
        const D: usize = 5;
        const N: usize = 7;
        let mut s0 = nalgebra::SMatrix::<f64, D, D>::from_fn(|i, j| {
            if i >= j {
                ((i * 3 + j * 5) as f64 * 0.61).sin()
            } else {
                0.0
            }
        });
        s0[(1, 1)] = 0.0;
        s0[(3, 3)] = -0.4;
        let col = |c: usize| {
            nalgebra::SVector::<f64, D>::from_fn(|i, _| ((i * 11 + c * 7) as f64 * 0.43).cos())
        };
        let mut cols: [nalgebra::SVector<f64, D>; 2 * N] = core::array::from_fn(col);
        let mut rows = [[[0.0; N]; 2]; D];
        for (c, v) in cols.iter().enumerate() {
            for (i, row) in rows.iter_mut().enumerate() {
                row[c / N][c % N] = v[i];
            }
        }
        let mut by_columns = s0;
        add_columns(&mut by_columns, &mut cols);
        let mut by_rows = s0;
        add_columns_by_rows(&mut by_rows, &mut rows);
        assert_relative_eq!(by_rows, by_columns, epsilon = 1e-13);
        let mut zero_rows = [[[0.0; N]; 2]; D];
        let mut s = s0;
        add_columns_by_rows(&mut s, &mut zero_rows);
        // Nothing folded: only the columns with a negative diagonal
        // (2 and 3) change, by their sign.
        assert!(s0[(2, 2)] < 0.0 && s0[(3, 3)] < 0.0);
        let mut expected = s0;
        for j in [2, 3] {
            for v in expected.column_mut(j).iter_mut() {
                *v = -*v;
            }
        }
        assert_eq!(s, expected);
    }

    type Fold<const D: usize, const N: usize> =
        fn(&mut nalgebra::SMatrix<f64, D, D>, &mut [[[f64; N]; 2]; D]);

    /// `add_columns_by_rows` and both its ways, see [`check_fold_by`].
    fn check_fold<const D: usize, const N: usize>(empty: &[usize]) {
        check_fold_by::<D, N>(empty, add_columns_by_rows);
        check_fold_by::<D, N>(empty, one_at_a_time);
        check_fold_by::<D, N>(empty, in_pairs);
    }

    /// `fold` against `add_columns` (one reflection at a time, by columns)
    /// and against `S Sᵀ + Σ cᵢ cᵢᵀ`, for a `D`-state factor and `2N`
    /// columns, with the rows in `empty` given nothing to fold (their
    /// columns' entries zero, and their factor row zero left of the
    /// diagonal, so no reflection before reaches them).
    fn check_fold_by<const D: usize, const N: usize>(empty: &[usize], fold: Fold<D, N>) {
        let mut s0 = nalgebra::SMatrix::<f64, D, D>::from_fn(|i, j| match (i, j) {
            _ if i < j => 0.0,
            _ if i == j => 1.0 + 0.3 * i as f64,
            _ if empty.contains(&i) => 0.0,
            _ => ((i * 5 + j * 3) as f64 * 0.71).sin(),
        });
        if D > 2 {
            // A negative diagonal entry: the fold leaves a positive one.
            s0[(2, 2)] = -0.8;
        }
        let col = |c: usize| {
            nalgebra::SVector::<f64, D>::from_fn(|i, _| {
                if empty.contains(&i) {
                    0.0
                } else {
                    ((i * 13 + c * 7) as f64 * 0.37).cos()
                }
            })
        };
        // `2N` of them (at most 16 here).
        let mut cols: [nalgebra::SVector<f64, D>; 16] = core::array::from_fn(col);
        let mut rows = [[[0.0; N]; 2]; D];
        for (c, v) in cols[..2 * N].iter().enumerate() {
            for (i, row) in rows.iter_mut().enumerate() {
                row[c / N][c % N] = v[i];
            }
        }
        let mut p = s0 * s0.transpose();
        for c in &cols[..2 * N] {
            p += c * c.transpose();
        }
        let mut by_columns = s0;
        add_columns(&mut by_columns, &mut cols[..2 * N]);
        let mut by_rows = s0;
        fold(&mut by_rows, &mut rows);
        assert_relative_eq!(by_rows, by_columns, epsilon = 1e-13);
        assert_relative_eq!(by_rows * by_rows.transpose(), p, epsilon = 1e-12);
        for i in 0..D {
            assert!(by_rows[(i, i)] >= 0.0, "diagonal {i} of {by_rows}");
            for j in i + 1..D {
                assert_eq!(by_rows[(i, j)], 0.0);
            }
        }
    }

    #[test]
    fn reflections_in_pairs_cover_every_case() {
        // Both ways at every size (in use, the sizes below `PAIRS_FROM` go
        // one at a time): every count of rows below a pair (none, one, an
        // odd and an even number), row lengths with and without a
        // remainder of the four lanes, and a row with nothing to fold
        // first and second in a pair.
        let cases: [&[usize]; 7] = [&[], &[0], &[1], &[2], &[3], &[1, 2], &[0, 1]];
        for empty in cases {
            check_fold::<1, 3>(empty);
            check_fold::<2, 3>(empty);
            check_fold::<3, 3>(empty);
            check_fold::<4, 4>(empty);
            check_fold::<5, 3>(empty);
            check_fold::<6, 4>(empty);
            check_fold::<7, 5>(empty);
            check_fold::<8, 3>(empty);
        }
    }
}
