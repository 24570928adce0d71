//! Register-blocked products `Σ Xₜ Yₜᵀ` on fixed-size matrices.
//!
//! The symmetric products of the filters are short (`N ≤ 32`), so loops
//! whose length varies with the column (a triangle walked element by element)
//! are dominated by loop overhead and, with wider vector units, by scalar
//! remainders. Here every output block is a fixed `MR × NR` tile held in
//! registers over the whole inner dimension, which the compiler unrolls and
//! vectorises; tiles wholly above the diagonal are skipped when only the
//! lower triangle is wanted. The rows and columns left over at the edges get
//! tiles of their own smaller fixed size, so every element is computed once.

use nalgebra::SMatrix;

use crate::Real;

/// Tile rows: a 4-element column segment is two SSE2 or one AVX register.
const MR: usize = 4;
/// Tile columns.
const NR: usize = 4;
/// Up to this many rows a whole output column fits in registers, and
/// computing it in full beats tiling a triangle.
const COLUMN_ROWS: usize = 12;

/// `out = init + Σₜ xₜ yₜᵀ` (`init` zero when `None`) for `R × K` factors
/// `xₜ` and `C × K` factors `yₜ`. With `lower`, only the lower triangle is
/// guaranteed; elements above the diagonal may be left unspecified.
#[inline]
pub(crate) fn add_products<
    T: Real,
    const R: usize,
    const C: usize,
    const K: usize,
    const L: usize,
>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&SMatrix<T, R, K>; L],
    y: [&SMatrix<T, C, K>; L],
    lower: bool,
) {
    if R <= COLUMN_ROWS || C < NR {
        columns(out, init, x, y);
    } else {
        tiled(out, init, x, y, lower);
    }
}

/// One output column at a time, accumulated in a fixed-size array.
#[inline(always)]
fn columns<T: Real, const R: usize, const C: usize, const K: usize, const L: usize>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&SMatrix<T, R, K>; L],
    y: [&SMatrix<T, C, K>; L],
) {
    for j in 0..C {
        let mut acc = [T::zero(); R];
        if let Some(p) = init {
            acc.copy_from_slice(&p.as_slice()[j * R..j * R + R]);
        }
        for (xt, yt) in x.iter().zip(&y) {
            let xs = xt.as_slice();
            for k in 0..K {
                let f = yt[(j, k)];
                let Some(xk) = xs[k * R..].first_chunk::<R>() else {
                    continue;
                };
                for (a, &xv) in acc.iter_mut().zip(xk) {
                    *a += xv * f;
                }
            }
        }
        out.as_mut_slice()[j * R..j * R + R].copy_from_slice(&acc);
    }
}

/// `MR × NR` tiles held in registers over the whole inner dimension; the
/// rows and columns left over at the edges (`R mod MR`, `C mod NR`) get
/// tiles of exactly their size, so no element is computed twice.
#[inline(always)]
fn tiled<T: Real, const R: usize, const C: usize, const K: usize, const L: usize>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&SMatrix<T, R, K>; L],
    y: [&SMatrix<T, C, K>; L],
    lower: bool,
) {
    let full = C / NR * NR;
    for jb in (0..full).step_by(NR) {
        column_block::<T, R, C, K, L, NR>(out, init, &x, &y, lower, jb);
    }
    // The size is a constant of each instantiation: one arm remains.
    match C % NR {
        1 => column_block::<T, R, C, K, L, 1>(out, init, &x, &y, lower, full),
        2 => column_block::<T, R, C, K, L, 2>(out, init, &x, &y, lower, full),
        3 => column_block::<T, R, C, K, L, 3>(out, init, &x, &y, lower, full),
        _ => {}
    }
}

/// The tiles of columns `jb .. jb + TC`.
#[inline(always)]
fn column_block<
    T: Real,
    const R: usize,
    const C: usize,
    const K: usize,
    const L: usize,
    const TC: usize,
>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: &[&SMatrix<T, R, K>; L],
    y: &[&SMatrix<T, C, K>; L],
    lower: bool,
    jb: usize,
) {
    let full = R / MR * MR;
    for ib in (0..full).step_by(MR) {
        // Wholly above the diagonal: not wanted.
        if lower && ib + MR <= jb {
            continue;
        }
        tile::<T, R, C, K, L, MR, TC>(out, init, x, y, ib, jb);
    }
    match R % MR {
        1 => tile::<T, R, C, K, L, 1, TC>(out, init, x, y, full, jb),
        2 => tile::<T, R, C, K, L, 2, TC>(out, init, x, y, full, jb),
        3 => tile::<T, R, C, K, L, 3, TC>(out, init, x, y, full, jb),
        _ => {}
    }
}

/// One `TR × TC` tile at rows `ib ..`, columns `jb ..`, accumulated in
/// registers over the whole inner dimension.
#[inline(always)]
fn tile<
    T: Real,
    const R: usize,
    const C: usize,
    const K: usize,
    const L: usize,
    const TR: usize,
    const TC: usize,
>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: &[&SMatrix<T, R, K>; L],
    y: &[&SMatrix<T, C, K>; L],
    ib: usize,
    jb: usize,
) {
    let mut acc = [[T::zero(); TR]; TC];
    if let Some(p) = init {
        let p = p.as_slice();
        for (jj, a) in acc.iter_mut().enumerate() {
            a.copy_from_slice(&p[(jb + jj) * R + ib..(jb + jj) * R + ib + TR]);
        }
    }
    for (xt, yt) in x.iter().zip(y) {
        let (xs, ys) = (xt.as_slice(), yt.as_slice());
        for k in 0..K {
            // Fixed-size views, so the tile loops unroll into registers.
            let (Some(xk), Some(yk)) = (
                xs[k * R + ib..].first_chunk::<TR>(),
                ys[k * C + jb..].first_chunk::<TC>(),
            ) else {
                continue;
            };
            for (a, &yv) in acc.iter_mut().zip(yk) {
                for (av, &xv) in a.iter_mut().zip(xk) {
                    *av += xv * yv;
                }
            }
        }
    }
    let o = out.as_mut_slice();
    for (jj, a) in acc.iter().enumerate() {
        o[(jb + jj) * R + ib..(jb + jj) * R + ib + TR].copy_from_slice(a);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample<const R: usize, const C: usize>(seed: f64) -> SMatrix<f64, R, C> {
        SMatrix::from_fn(|i, j| ((i * 7 + j * 3) as f64 * 0.37 + seed).sin())
    }

    #[test]
    fn full_product_matches_nalgebra_on_ragged_sizes() {
        // 14 × 7 output: tiled, with two rows and three columns left over
        // at the edges (tiles of 2 × 4, 4 × 3 and 2 × 3).
        let x = sample::<14, 3>(0.1);
        let y = sample::<7, 3>(0.7);
        let init = sample::<14, 7>(1.3);
        let mut out = SMatrix::<f64, 14, 7>::zeros();
        add_products(&mut out, Some(&init), [&x], [&y], false);
        let expected = init + x * y.transpose();
        assert!((out - expected).abs().max() < 1e-14);
    }

    #[test]
    fn lower_mode_fills_the_lower_triangle_of_two_terms() {
        // 13 × 13: tiled, one row and one column left over.
        let (x1, y1) = (sample::<13, 2>(0.2), sample::<13, 2>(0.5));
        let (x2, y2) = (sample::<13, 2>(0.9), sample::<13, 2>(1.1));
        let mut out = SMatrix::<f64, 13, 13>::zeros();
        add_products(&mut out, None, [&x1, &x2], [&y1, &y2], true);
        let expected = x1 * y1.transpose() + x2 * y2.transpose();
        for j in 0..13 {
            for i in j..13 {
                assert!((out[(i, j)] - expected[(i, j)]).abs() < 1e-14);
            }
        }
        // A tile strictly above the diagonal (rows 0..4, column 12) is skipped.
        assert_eq!(out[(0, 12)], 0.0);
    }

    #[test]
    fn column_path_matches_nalgebra() {
        let x = sample::<6, 15>(0.3);
        let y = sample::<15, 15>(0.4);
        let mut out = SMatrix::<f64, 6, 15>::zeros();
        add_products(&mut out, None, [&x], [&y], false);
        assert!((out - x * y.transpose()).abs().max() < 1e-13);
    }
}
