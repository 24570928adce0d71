//! Register-blocked products `Σ Xₜ Yₜᵀ` on fixed-size matrices.
//!
//! The symmetric products of the filters are short (`N ≤ 32`), so loops
//! whose length varies with the column (a triangle walked element by element)
//! are dominated by loop overhead and, with wider vector units, by scalar
//! remainders. Here every output block is a fixed `MR × NR` tile held in
//! registers over the whole inner dimension, which the compiler unrolls and
//! vectorises; tiles wholly above the diagonal are skipped when only the
//! lower triangle is wanted. The columns left over at the edges get tiles of
//! their own smaller fixed size; so do the rows in `f64` on SSE2, while in
//! `f32`, and in `f64` with AVX, they are covered by a full-height tile that
//! overlaps the one before it (the rows in common computed twice, to the
//! same value). A tile is eight rows in `f32` (two SSE2 registers, one AVX
//! register) and four in `f64` (two SSE2 registers, one AVX register).

use nalgebra::{SMatrix, SVector};

use crate::Real;

/// Bytes in one vector register of the target the library is built for
/// (AVX registers with `-C target-cpu=x86-64-v3` or `native`, SSE2 ones by
/// default).
const VECTOR_BYTES: usize = if cfg!(target_feature = "avx") { 32 } else { 16 };

/// Elements of `T` in one vector register.
pub(super) const fn lanes<T>() -> usize {
    VECTOR_BYTES / core::mem::size_of::<T>()
}

/// Tile rows: eight for `f32` (two SSE2 registers, one AVX register),
/// four for `f64` (two SSE2 registers, one AVX register), so that a tile's
/// column is whole registers either way. Eight `f32` rows on SSE2 rather
/// than four share each broadcast element of the right-hand factor between
/// two multiplies, and a broadcast is a shuffle on the same port as half
/// the additions. In `f64` eight rows are four SSE2 registers a column, and
/// a tile's accumulators alone would take all sixteen.
const fn tile_rows<T>() -> usize {
    if core::mem::size_of::<T>() <= 4 {
        8
    } else {
        4
    }
}
/// Tile columns.
const NR: usize = 4;
/// Up to this many rows a whole output column fits in registers, and
/// computing it in full beats tiling a triangle.
const COLUMN_ROWS: usize = 12;

/// `A x` for a fixed-size matrix and vector, the result held in registers
/// over the columns of `A` (`Σⱼ xⱼ A[.., j]`, column order).
///
/// nalgebra's general product loads and stores the result once per column;
/// for the small sizes of a filter model (a 15-state transition applied to
/// 31 sigma points) this keeps it in registers instead. Always inlined:
/// left to itself the compiler keeps it out of line in some builds, a call
/// per sigma point.
///
/// ```
/// use kestrel_core::linalg::mul_vector;
/// use kestrel_core::nalgebra::{Matrix2x3, Vector3};
/// let a = Matrix2x3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
/// let x = Vector3::new(1.0, 0.0, -1.0);
/// assert_eq!(mul_vector(&a, &x), a * x);
/// ```
#[inline(always)]
pub fn mul_vector<T: Real, const R: usize, const C: usize>(
    a: &SMatrix<T, R, C>,
    x: &SVector<T, C>,
) -> SVector<T, R> {
    // Written out, not as the one-column case of `add_products`: that
    // needs `xᵀ` copied.
    let mut acc = [T::zero(); R];
    for (column, &f) in a.data.0.iter().zip(x.as_slice()) {
        add_scaled(&mut acc, column, f);
    }
    SVector::from_array_storage(nalgebra::ArrayStorage([acc]))
}

/// `acc += f · column` for a fixed-length column: the loop every column
/// product here is built from (fixed length, so it vectorises with the
/// accumulator in registers).
#[inline(always)]
pub(crate) fn add_scaled<T: Real, const R: usize>(acc: &mut [T; R], column: &[T; R], f: T) {
    for (v, &c) in acc.iter_mut().zip(column) {
        *v += c * f;
    }
}

/// `A L` for a lower-triangular `L` (its upper triangle is not read):
/// column `j` is `Σ_{k ≥ j} L[k, j] A[.., k]`, held in registers. The
/// products with the zeros above the diagonal are left out, about half of
/// the general product's work (nalgebra's product takes them all and
/// stores the result once per term).
#[inline]
pub(crate) fn mul_lower<T: Real, const R: usize, const C: usize>(
    a: &SMatrix<T, R, C>,
    l: &SMatrix<T, C, C>,
) -> SMatrix<T, R, C> {
    let mut out = SMatrix::<T, R, C>::zeros();
    for (j, (column, out)) in l.data.0.iter().zip(&mut out.data.0).enumerate() {
        let mut acc = [T::zero(); R];
        // Whole columns of `A` per term: the inner loop has the fixed
        // length `R` and vectorises.
        for (ak, &f) in a.data.0[j..].iter().zip(&column[j..]) {
            add_scaled(&mut acc, ak, f);
        }
        *out = acc;
    }
    out
}

/// The factors of a product as a sequence of fixed-length columns: a
/// fixed-size matrix, or the pairs of a sigma-point set (whose count `2N`
/// no const generic can name).
pub(crate) trait Columns<T, const R: usize> {
    /// The number of columns.
    fn count(&self) -> usize;
    /// Column `k`.
    fn column(&self, k: usize) -> &[T; R];
}

impl<T: Real, const R: usize, const K: usize> Columns<T, R> for SMatrix<T, R, K> {
    #[inline(always)]
    fn count(&self) -> usize {
        K
    }
    #[inline(always)]
    fn column(&self, k: usize) -> &[T; R] {
        &self.data.0[k]
    }
}

/// `N` pairs of columns, in pair order (a sigma-point set's deviations,
/// `[[plus, minus]; N]`): `2N` columns the compiler can count.
impl<T: Real, const R: usize, const N: usize> Columns<T, R> for [[SVector<T, R>; 2]; N] {
    #[inline(always)]
    fn count(&self) -> usize {
        2 * N
    }
    #[inline(always)]
    fn column(&self, k: usize) -> &[T; R] {
        &self.as_flattened()[k].data.0[0]
    }
}

/// `out = init + Σₜ xₜ yₜᵀ` (`init` zero when `None`) for `R × K` factors
/// `xₜ` and `C × K` factors `yₜ` (`K` the same within a term). With
/// `lower`, only the lower triangle is guaranteed; elements above the
/// diagonal may be left unspecified.
#[inline]
pub(crate) fn add_products<T, const R: usize, const C: usize, X, Y, const L: usize>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&X; L],
    y: [&Y; L],
    lower: bool,
) where
    T: Real,
    X: Columns<T, R> + ?Sized,
    Y: Columns<T, C> + ?Sized,
{
    // The size tests here and below are `const` blocks: the compiler then
    // instantiates only the branch taken, where a plain condition on the
    // same constants instantiates every kernel of every branch, and a build
    // compiles all of them for the one it runs.
    //
    // Tiled, the rows left over are covered, in `f32` and in `f64` with
    // AVX, by one more full-height tile ending at the last row, overlapping
    // the tile before it. The rows in common are computed twice with the
    // same operations in the same order, so they are written twice with the
    // same value; a 15-row `f32` column then takes four vector operations
    // rather than three and three scalar ones. With two registers to a
    // four-row tile's column (`f64` on SSE2) edge tiles of the rows' own
    // size are as cheap.
    if const { R <= COLUMN_ROWS || C < NR } {
        columns(out, init, x, y);
    } else if const { tile_rows::<T>() == 8 } {
        tiled::<T, R, C, X, Y, L, 8, true>(out, init, x, y, lower);
    } else if const { tile_rows::<T>() == lanes::<T>() } {
        tiled::<T, R, C, X, Y, L, 4, true>(out, init, x, y, lower);
    } else {
        tiled::<T, R, C, X, Y, L, 4, false>(out, init, x, y, lower);
    }
}

/// One output column at a time, accumulated in a fixed-size array.
#[inline(always)]
fn columns<T, const R: usize, const C: usize, X, Y, const L: usize>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&X; L],
    y: [&Y; L],
) where
    T: Real,
    X: Columns<T, R> + ?Sized,
    Y: Columns<T, C> + ?Sized,
{
    for j in 0..C {
        let mut acc = init.map_or([T::zero(); R], |p| p.data.0[j]);
        for (xt, yt) in x.iter().zip(&y) {
            for k in 0..xt.count().min(yt.count()) {
                add_scaled(&mut acc, xt.column(k), yt.column(k)[j]);
            }
        }
        out.data.0[j] = acc;
    }
}

/// `MR × NR` tiles held in registers over the whole inner dimension; the
/// columns left over at the edge (`C mod NR`) get tiles of exactly their
/// size, the rows left over (`R mod MR`) an overlapping full tile
/// (`OVERLAP`) or tiles of exactly their size.
#[inline(always)]
fn tiled<
    T,
    const R: usize,
    const C: usize,
    X,
    Y,
    const L: usize,
    const MR: usize,
    const OVERLAP: bool,
>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: [&X; L],
    y: [&Y; L],
    lower: bool,
) where
    T: Real,
    X: Columns<T, R> + ?Sized,
    Y: Columns<T, C> + ?Sized,
{
    let full = C / NR * NR;
    for jb in (0..full).step_by(NR) {
        column_block::<T, R, C, X, Y, L, MR, OVERLAP, NR>(out, init, &x, &y, lower, jb);
    }
    match const { C % NR } {
        1 => column_block::<T, R, C, X, Y, L, MR, OVERLAP, 1>(out, init, &x, &y, lower, full),
        2 => column_block::<T, R, C, X, Y, L, MR, OVERLAP, 2>(out, init, &x, &y, lower, full),
        3 => column_block::<T, R, C, X, Y, L, MR, OVERLAP, 3>(out, init, &x, &y, lower, full),
        _ => {}
    }
}

/// The tiles of columns `jb .. jb + TC`, `MR` rows each.
#[inline(always)]
fn column_block<
    T,
    const R: usize,
    const C: usize,
    X,
    Y,
    const L: usize,
    const MR: usize,
    const OVERLAP: bool,
    const TC: usize,
>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: &[&X; L],
    y: &[&Y; L],
    lower: bool,
    jb: usize,
) where
    T: Real,
    X: Columns<T, R> + ?Sized,
    Y: Columns<T, C> + ?Sized,
{
    let full = R / MR * MR;
    for ib in (0..full).step_by(MR) {
        // Wholly above the diagonal: not wanted.
        if lower && ib + MR <= jb {
            continue;
        }
        tile::<T, R, C, X, Y, L, MR, TC>(out, init, x, y, ib, jb);
    }
    // The rows left over (see `add_products`).
    if const { OVERLAP && !R.is_multiple_of(MR) && R >= MR } {
        tile::<T, R, C, X, Y, L, MR, TC>(out, init, x, y, R - MR, jb);
    } else {
        match const { R % MR } {
            1 => tile::<T, R, C, X, Y, L, 1, TC>(out, init, x, y, full, jb),
            2 => tile::<T, R, C, X, Y, L, 2, TC>(out, init, x, y, full, jb),
            3 => tile::<T, R, C, X, Y, L, 3, TC>(out, init, x, y, full, jb),
            4 => tile::<T, R, C, X, Y, L, 4, TC>(out, init, x, y, full, jb),
            5 => tile::<T, R, C, X, Y, L, 5, TC>(out, init, x, y, full, jb),
            6 => tile::<T, R, C, X, Y, L, 6, TC>(out, init, x, y, full, jb),
            7 => tile::<T, R, C, X, Y, L, 7, TC>(out, init, x, y, full, jb),
            _ => {}
        }
    }
}

/// One `TR × TC` tile at rows `ib ..`, columns `jb ..`, accumulated in
/// registers over the whole inner dimension.
#[inline(always)]
fn tile<T, const R: usize, const C: usize, X, Y, const L: usize, const TR: usize, const TC: usize>(
    out: &mut SMatrix<T, R, C>,
    init: Option<&SMatrix<T, R, C>>,
    x: &[&X; L],
    y: &[&Y; L],
    ib: usize,
    jb: usize,
) where
    T: Real,
    X: Columns<T, R> + ?Sized,
    Y: Columns<T, C> + ?Sized,
{
    let mut acc = [[T::zero(); TR]; TC];
    if let Some(p) = init {
        let p = p.as_slice();
        for (jj, a) in acc.iter_mut().enumerate() {
            a.copy_from_slice(&p[(jb + jj) * R + ib..(jb + jj) * R + ib + TR]);
        }
    }
    for (xt, yt) in x.iter().zip(y) {
        for k in 0..xt.count().min(yt.count()) {
            // Fixed-size, so the tile loops unroll into registers; copied
            // out before the multiply-adds rather than read through the
            // slices, so that each element is loaded once, into a
            // register, for all the multiply-adds that use it.
            let (Some(&xk), Some(&yk)) = (
                xt.column(k)[ib..].first_chunk::<TR>(),
                yt.column(k)[jb..].first_chunk::<TC>(),
            ) else {
                continue;
            };
            for (a, &yv) in acc.iter_mut().zip(&yk) {
                for (av, &xv) in a.iter_mut().zip(&xk) {
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
    fn pairs_are_read_as_their_columns_in_pair_order() {
        // 14 rows: the tiled path, with edge tiles; 5 pairs = 10 columns.
        let pairs: [[SVector<f64, 14>; 2]; 5] = core::array::from_fn(|i| {
            [0, 1].map(|side| SVector::from_fn(|r, _| ((r * 5 + i * 2 + side) as f64 * 0.41).cos()))
        });
        let gathered = SMatrix::<f64, 14, 10>::from_fn(|r, k| pairs[k / 2][k % 2][r]);
        let mut out = SMatrix::<f64, 14, 14>::zeros();
        add_products(&mut out, None, [&pairs], [&pairs], false);
        let expected = gathered * gathered.transpose();
        assert!((out - expected).abs().max() < 1e-13);
    }

    #[test]
    fn mul_lower_matches_nalgebra_and_ignores_the_upper_triangle() {
        let a = sample::<7, 5>(0.3);
        let full = sample::<5, 5>(1.7);
        let mut l = full;
        l.fill_upper_triangle(0.0, 1);
        // What lies above the diagonal is not read.
        let mut garbage = l;
        garbage.fill_upper_triangle(f64::NAN, 1);
        assert_eq!(mul_lower(&a, &garbage), a * l);
        assert_eq!(mul_lower(&a, &l), a * l);
    }

    #[test]
    fn mul_vector_matches_nalgebra() {
        let a = sample::<6, 15>(0.8);
        let x = SVector::<f64, 15>::from_fn(|i, _| (i as f64 * 0.3).sin());
        // The same sums in the same order (column by column): equal.
        assert_eq!(mul_vector(&a, &x), a * x);
        let a32 = sample::<15, 15>(0.2).cast::<f32>();
        let x32 = SVector::<f32, 15>::from_fn(|i, _| (i as f32 * 0.7).cos());
        assert!((mul_vector(&a32, &x32) - a32 * x32).abs().max() < 1e-5);
    }

    #[test]
    fn column_path_matches_nalgebra() {
        let x = sample::<6, 15>(0.3);
        let y = sample::<15, 15>(0.4);
        let mut out = SMatrix::<f64, 6, 15>::zeros();
        add_products(&mut out, None, [&x], [&y], false);
        assert!((out - x * y.transpose()).abs().max() < 1e-13);
    }

    /// `init + Σₜ Xₜ Yₜᵀ` element by element, terms in the kernel's order
    /// (term by term, then column by column): the same operations as every
    /// tile, so the kernel must match it exactly.
    fn in_order<const R: usize, const C: usize, const K: usize>(
        init: &SMatrix<f32, R, C>,
        terms: [(&SMatrix<f32, R, K>, &SMatrix<f32, C, K>); 2],
    ) -> SMatrix<f32, R, C> {
        SMatrix::from_fn(|i, j| {
            let mut acc = init[(i, j)];
            for (x, y) in terms {
                for k in 0..K {
                    acc += x[(i, k)] * y[(j, k)];
                }
            }
            acc
        })
    }

    /// The kernel as the target selects it, or one tiling chosen here.
    type Tiling<const R: usize> = fn(
        &mut SMatrix<f32, R, R>,
        Option<&SMatrix<f32, R, R>>,
        [&SMatrix<f32, R, 5>; 2],
        [&SMatrix<f32, R, 5>; 2],
        bool,
    );

    fn every_tiling<const R: usize>() {
        let (x1, y1) = (sample::<R, 5>(0.3).cast(), sample::<R, 5>(0.6).cast());
        let (x2, y2) = (sample::<R, 5>(0.8).cast(), sample::<R, 5>(1.4).cast());
        let init: SMatrix<f32, R, R> = sample::<R, R>(2.1).cast();
        let expected = in_order(&init, [(&x1, &y1), (&x2, &y2)]);
        let tilings: [(&str, Tiling<R>); 5] = [
            ("as the target selects", add_products::<f32, R, R, _, _, 2>),
            ("4 rows, edge tiles", tiled::<f32, R, R, _, _, 2, 4, false>),
            ("4 rows, overlapping", tiled::<f32, R, R, _, _, 2, 4, true>),
            ("8 rows, edge tiles", tiled::<f32, R, R, _, _, 2, 8, false>),
            ("8 rows, overlapping", tiled::<f32, R, R, _, _, 2, 8, true>),
        ];
        for (name, tiling) in tilings {
            let mut full = SMatrix::<f32, R, R>::zeros();
            tiling(&mut full, Some(&init), [&x1, &x2], [&y1, &y2], false);
            assert_eq!(full, expected, "{R} rows, {name}");
            let mut lower = SMatrix::<f32, R, R>::zeros();
            tiling(&mut lower, Some(&init), [&x1, &x2], [&y1, &y2], true);
            for j in 0..R {
                for i in j..R {
                    assert_eq!(
                        lower[(i, j)],
                        expected[(i, j)],
                        "{R} rows, {name}, ({i}, {j})"
                    );
                }
            }
        }
    }

    /// Every tiling a target can select (8 rows for `f32`, 4 for `f64`;
    /// the rows left over by edge tiles or by a full tile overlapping
    /// the one before it) gives the in-order sums exactly, the rows
    /// computed twice included, in both modes, whichever target runs the
    /// tests: 0 to 7 rows left over after 8-row tiles, 0 to 3 after 4-row
    /// ones.
    #[test]
    fn every_tiling_gives_the_in_order_sums() {
        every_tiling::<13>();
        every_tiling::<14>();
        every_tiling::<15>();
        every_tiling::<16>();
        every_tiling::<17>();
        every_tiling::<18>();
        every_tiling::<19>();
        every_tiling::<22>();
        every_tiling::<23>();
    }
}
