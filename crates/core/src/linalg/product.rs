//! Register-blocked products `Σ Xₜ Yₜᵀ` on fixed-size matrices.
//!
//! The symmetric products of the filters are short (`N ≤ 32`), so loops
//! whose length varies with the column (a triangle walked element by element)
//! are dominated by loop overhead and, with wider vector units, by scalar
//! remainders. Here every output block is a fixed `MR × NR` tile held in
//! registers over the whole inner dimension, which the compiler unrolls and
//! vectorises; tiles wholly above the diagonal are skipped when only the
//! lower triangle is wanted. The last tile in each direction is moved back to
//! end at the matrix edge, so it overlaps its neighbour and every tile is
//! full: overlapping tiles compute the same elements by the same operations,
//! hence write identical values.

use nalgebra::SMatrix;

use crate::Real;

/// Tile rows: a 4-element column segment is two SSE2 or one AVX register.
const MR: usize = 4;
/// Tile columns.
const NR: usize = 4;
/// Up to this many rows a whole output column fits in registers, and
/// computing it in full beats tiling a triangle.
const COLUMN_ROWS: usize = 8;

/// Tile starts covering `0..n` with tiles of `b ≤ n`, the last one overlapping.
fn starts(n: usize, b: usize) -> impl Iterator<Item = usize> {
    (0..n).step_by(b).map(move |s| s.min(n - b))
}

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

/// `MR × NR` tiles held in registers over the whole inner dimension.
/// `out` must not alias `init` (overlapping tiles re-read it).
#[inline(always)]
fn tiled<T: Real, const R: usize, const C: usize, const K: usize, const L: usize>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&SMatrix<T, R, K>; L],
    y: [&SMatrix<T, C, K>; L],
    lower: bool,
) {
    let o = out.as_mut_slice();
    for jb in starts(C, NR) {
        for ib in starts(R, MR) {
            if lower && ib + MR <= jb {
                continue;
            }
            let mut acc = [[T::zero(); MR]; NR];
            if let Some(p) = init {
                let p = p.as_slice();
                for (jj, a) in acc.iter_mut().enumerate() {
                    a.copy_from_slice(&p[(jb + jj) * R + ib..(jb + jj) * R + ib + MR]);
                }
            }
            for (xt, yt) in x.iter().zip(&y) {
                let (xs, ys) = (xt.as_slice(), yt.as_slice());
                for k in 0..K {
                    // Fixed-size views, so the tile loops unroll into registers.
                    let (Some(xk), Some(yk)) = (
                        xs[k * R + ib..].first_chunk::<MR>(),
                        ys[k * C + jb..].first_chunk::<NR>(),
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
            for (jj, a) in acc.iter().enumerate() {
                o[(jb + jj) * R + ib..(jb + jj) * R + ib + MR].copy_from_slice(a);
            }
        }
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
        // 11 × 6 output: tiled, and both directions need an overlapping
        // last tile (rows 7..11, columns 2..6).
        let x = sample::<11, 3>(0.1);
        let y = sample::<6, 3>(0.7);
        let init = sample::<11, 6>(1.3);
        let mut out = SMatrix::<f64, 11, 6>::zeros();
        add_products(&mut out, Some(&init), [&x], [&y], false);
        let expected = init + x * y.transpose();
        assert!((out - expected).abs().max() < 1e-14);
    }

    #[test]
    fn lower_mode_fills_the_lower_triangle_of_two_terms() {
        let (x1, y1) = (sample::<9, 2>(0.2), sample::<9, 2>(0.5));
        let (x2, y2) = (sample::<9, 2>(0.9), sample::<9, 2>(1.1));
        let mut out = SMatrix::<f64, 9, 9>::zeros();
        add_products(&mut out, None, [&x1, &x2], [&y1, &y2], true);
        let expected = x1 * y1.transpose() + x2 * y2.transpose();
        for j in 0..9 {
            for i in j..9 {
                assert!((out[(i, j)] - expected[(i, j)]).abs() < 1e-14);
            }
        }
        // A tile strictly above the diagonal (rows 0..4, columns 5..9) is skipped.
        assert_eq!(out[(0, 8)], 0.0);
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
