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
pub(crate) fn add_columns_by_rows<T: Real, const D: usize, const N: usize>(
    s: &mut SMatrix<T, D, D>,
    rows: &mut [[[T; N]; 2]; D],
) {
    let ss = s.as_mut_slice();
    // ‖row k‖², computed while row k is updated at step k − 1 (it is the
    // next pivot's input, so computing it then shortens the chain from one
    // reflection to the next).
    let mut sigma2 = rows
        .first()
        .map_or(T::zero(), |r| dot(r.as_flattened(), r.as_flattened()));
    for k in 0..D {
        let (head, tail) = rows.split_at_mut(k + 1);
        let rk = head[k].as_flattened();
        let alpha = ss[k * D + k];
        let Some((beta, v0, tau)) = reflector(alpha, sigma2) else {
            flip_if_negative(&mut ss[k * D + k..k * D + D]);
            sigma2 = tail
                .first()
                .map_or(T::zero(), |r| dot(r.as_flattened(), r.as_flattened()));
            continue;
        };
        let below = &mut ss[k * D + k + 1..k * D + D];
        for (i, (si, ri)) in below.iter_mut().zip(tail.iter_mut()).enumerate() {
            let ri = ri.as_flattened_mut();
            let wi = (*si * v0 + dot(ri, rk)) * tau;
            *si -= wi * v0;
            if i == 0 {
                sigma2 = axpy_norm2(ri, rk, wi);
            } else {
                for (c, &f) in ri.iter_mut().zip(rk) {
                    *c -= wi * f;
                }
            }
        }
        ss[k * D + k] = beta;
        flip_if_negative(&mut ss[k * D + k..k * D + D]);
    }
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
/// sum backwards, and for the `(l₀ + l₁) + (l₂ + l₃)` order formerly used
/// it regrouped every product vector by shuffles into the pairs that sum,
/// in `f32` and in `f64`: at 15 states this fold took 28,386 instructions
/// a step in `f64` and 21,392 in `f32`, against 23,231 and 15,301 with the
/// barrier. Seen as an opaque value, the lanes stay one register of four
/// `f32` or two of two `f64`, and this order sums their halves first.
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
}
