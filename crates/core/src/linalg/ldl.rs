use nalgebra::{SMatrix, SVector};

use super::cholesky::{eliminate_unrolled, regular_pivot, UNROLL_FROM};
use super::product::add_scaled;
use super::NotPositiveDefinite;
use crate::real::{epsilon, lit};
use crate::Real;

/// The square-root-free factorisation `A = L D Lᵀ` of a symmetric positive
/// definite matrix (`L` unit lower triangular, `D` diagonal), for solving
/// with `A` where no Cholesky factor is needed afterwards.
///
/// It accepts the matrices [`cholesky`](super::cholesky) accepts: the
/// pivots `dₖ` are, up to rounding, the squares of the Cholesky pivots and
/// pass the same test, with the same index on failure (a matrix singular
/// to within that rounding may fall either way). A pivot costs one division
/// instead of a square root and a division. In a Kalman update the
/// factorisation of `C` lies on the chain from one covariance to the next,
/// so at small sizes the square roots set the pace.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Ldl<T: Real, const M: usize> {
    /// `L` below the diagonal (the diagonal and above are not read).
    l: SMatrix<T, M, M>,
    /// `1 / dₖ`.
    inv_d: [T; M],
}

impl<T: Real, const M: usize> Ldl<T, M> {
    /// Factors `a`, reading its lower triangle.
    #[inline]
    pub fn new(a: &SMatrix<T, M, M>) -> Result<Self, NotPositiveDefinite> {
        let rel = epsilon::<T>() * lit::<T>(M as f64);
        if M == 2 {
            return Self::two_by_two(a, rel);
        }
        Self::by(a, M < UNROLL_FROM)
    }

    /// [`new`](Self::new) above two states, by the unrolled (`small`) or
    /// the column-loop elimination.
    #[inline(always)]
    fn by(a: &SMatrix<T, M, M>, small: bool) -> Result<Self, NotPositiveDefinite> {
        let rel = epsilon::<T>() * lit::<T>(M as f64);
        let mut l = *a;
        let s = l.as_mut_slice();
        if small {
            // The unrolled elimination the small Cholesky uses (it keeps the
            // columns unscaled), then `l_ij = u_ij / d_j`.
            let original: [T; M] = core::array::from_fn(|j| a[(j, j)]);
            let (inv_d, _) = eliminate_unrolled(s, &original, |j, pivot, a_jj, _| {
                if regular_pivot(pivot, a_jj, rel) {
                    Ok(Some(pivot))
                } else {
                    Err(NotPositiveDefinite { index: j })
                }
            })?;
            for j in 0..M {
                for i in 0..M {
                    if i > j {
                        s[j * M + i] *= inv_d[j];
                    }
                }
            }
            return Ok(Self { l, inv_d });
        }
        // Left-looking: column j receives −l_ik (l_jk d_k) for each finished
        // column k, then is divided by its pivot.
        let mut d = [T::zero(); M];
        let mut inv_d = [T::zero(); M];
        for j in 0..M {
            let (done, rest) = s.split_at_mut(j * M);
            let col = &mut rest[j..M];
            for k in 0..j {
                let ujk = done[k * M + j] * d[k];
                for (v, &lik) in col.iter_mut().zip(&done[k * M + j..k * M + M]) {
                    *v -= lik * ujk;
                }
            }
            let pivot = col[0];
            if !regular_pivot(pivot, a[(j, j)], rel) {
                return Err(NotPositiveDefinite { index: j });
            }
            d[j] = pivot;
            inv_d[j] = pivot.recip();
            for v in &mut col[1..] {
                *v *= inv_d[j];
            }
        }
        Ok(Self { l, inv_d })
    }

    /// `M = 2` from the leading minors: `d₂ = det A / a₁₁`, so
    /// `1/d₂ = a₁₁ / det A` is a division that does not wait for `1/d₁`
    /// (two divisions side by side instead of one after the other: at two
    /// measurements they are most of the chain). The same pivots, tests and
    /// indices as the general loop, to rounding.
    #[inline(always)]
    fn two_by_two(a: &SMatrix<T, M, M>, rel: T) -> Result<Self, NotPositiveDefinite> {
        let (a11, a21, a22) = (a[(0, 0)], a[(1, 0)], a[(1, 1)]);
        let det = a11 * a22 - a21 * a21;
        let inv_d1 = a11.recip();
        let inv_d2 = a11 / det;
        let d2 = det * inv_d1;
        if !regular_pivot(a11, a11, rel) {
            return Err(NotPositiveDefinite { index: 0 });
        }
        if !regular_pivot(d2, a22, rel) {
            return Err(NotPositiveDefinite { index: 1 });
        }
        let mut l = SMatrix::zeros();
        l[(1, 0)] = a21 * inv_d1;
        let mut inv_d = [T::zero(); M];
        inv_d[0] = inv_d1;
        inv_d[1] = inv_d2;
        Ok(Self { l, inv_d })
    }

    /// `X ← X A⁻¹ = X L⁻ᵀ D⁻¹ L⁻¹` for `X` of any height: each step one
    /// scaled subtraction of a whole column of `X`, so it vectorises down
    /// the columns where [`solve_in_place`](Self::solve_in_place) on `Xᵀ`
    /// runs every row through the `M` pivots in scalar code. Row `i` of the
    /// result is column `i` of `solve_in_place` on `Xᵀ` bit for bit: the
    /// same products, subtracted in the same order (`a + c · (−f)` is
    /// `a − c f` exactly).
    #[inline]
    pub fn solve_right_in_place<const R: usize>(&self, x: &mut SMatrix<T, R, M>) {
        // Y Lᵀ = X, forwards: Yⱼ = Xⱼ − Σₖ₍ₖ<ⱼ₎ Yₖ Lⱼₖ.
        self.solve_unit_lower_transpose_right_in_place(x);
        let cols = &mut x.data.0;
        // W L = Z = Y D⁻¹, backwards: Wⱼ = Zⱼ − Σₖ₍ₖ>ⱼ₎ Wₖ Lₖⱼ (the Yₖ
        // above stay unscaled until their own column is reached).
        for j in (0..M).rev() {
            let mut acc = cols[j];
            for v in &mut acc {
                *v *= self.inv_d[j];
            }
            for (k, wk) in cols.iter().enumerate().skip(j + 1) {
                add_scaled(&mut acc, wk, -self.l[(k, j)]);
            }
            cols[j] = acc;
        }
    }

    /// `X ← X L⁻ᵀ` for the unit lower triangular `L` (no divisions): `Y`
    /// with `Y Lᵀ = X`, each column one scaled subtraction of whole earlier
    /// columns. For a symmetric `X` this is `(L⁻¹ X)ᵀ` bit for bit (the
    /// same products as [`solve_unit_lower_in_place`](Self::solve_unit_lower_in_place),
    /// subtracted in the same order) without the transpose, and down the
    /// columns, where that solve works along each one.
    #[inline(always)]
    pub fn solve_unit_lower_transpose_right_in_place<const R: usize>(
        &self,
        x: &mut SMatrix<T, R, M>,
    ) {
        let cols = &mut x.data.0;
        for j in 0..M {
            let mut acc = cols[j];
            for (k, yk) in cols[..j].iter().enumerate() {
                add_scaled(&mut acc, yk, -self.l[(j, k)]);
            }
            cols[j] = acc;
        }
    }

    /// `B ← L⁻¹ B` for the unit lower triangular `L` (no divisions).
    #[inline]
    pub fn solve_unit_lower_in_place<const K: usize>(&self, b: &mut SMatrix<T, M, K>) {
        for c in 0..K {
            self.forward(&mut b.as_mut_slice()[c * M..c * M + M], M < UNROLL_FROM);
        }
    }

    /// `x ← L⁻¹ x` for one column `x` of `M` elements, unrolled (constant
    /// trip counts with the bounds as conditions: the same arithmetic) if
    /// `unroll`.
    #[inline(always)]
    fn forward(&self, col: &mut [T], unroll: bool) {
        let ls = self.l.as_slice();
        for k in 0..M {
            let xk = col[k];
            if unroll {
                for i in 0..M {
                    if i > k {
                        col[i] -= ls[k * M + i] * xk;
                    }
                }
            } else {
                for (bi, li) in col[k + 1..].iter_mut().zip(&ls[k * M + k + 1..k * M + M]) {
                    *bi -= *li * xk;
                }
            }
        }
    }

    /// `1 / dₖ`, the reciprocal pivots.
    #[inline(always)]
    pub fn inverse_pivots(&self) -> &[T; M] {
        &self.inv_d
    }

    /// `B ← A⁻¹ B`: `L⁻¹`, `D⁻¹`, `L⁻ᵀ`, column by column.
    #[inline]
    pub fn solve_in_place<const K: usize>(&self, b: &mut SMatrix<T, M, K>) {
        let ls = self.l.as_slice();
        for c in 0..K {
            let col = &mut b.as_mut_slice()[c * M..c * M + M];
            // Not unrolled: at a measurement's sizes the unrolled solve is
            // more code than the loop overhead it saves.
            self.forward(col, false);
            for (v, inv) in col.iter_mut().zip(&self.inv_d) {
                *v *= *inv;
            }
            for k in (0..M).rev() {
                let mut acc = col[k];
                for (xi, li) in col[k + 1..].iter().zip(&ls[k * M + k + 1..k * M + M]) {
                    acc -= *li * *xi;
                }
                col[k] = acc;
            }
        }
    }

    /// The lower Cholesky factor `L √D` of the factored matrix: the
    /// factor [`cholesky`](super::cholesky) gives, to rounding, for the
    /// price of `M` divisions and square roots side by side (none on a
    /// chain) and one product per element. (`dₖ` is not kept: the update
    /// without adapters never asks for this, and would pay for keeping it
    /// on every pivot.)
    pub fn cholesky_factor(&self) -> SMatrix<T, M, M> {
        let root: [T; M] = core::array::from_fn(|k| self.inv_d[k].recip().sqrt());
        SMatrix::from_fn(|i, j| {
            if i > j {
                self.l[(i, j)] * root[j]
            } else if i == j {
                root[j]
            } else {
                T::zero()
            }
        })
    }

    /// `vᵀ A⁻¹ v` (`Σ yₖ² / dₖ` for `y = L⁻¹ v`).
    #[inline]
    pub fn quadratic_form(&self, v: &SVector<T, M>) -> T {
        let ls = self.l.as_slice();
        let mut y = *v;
        let mut total = T::zero();
        for k in 0..M {
            let yk = y[k];
            for (bi, li) in y.as_mut_slice()[k + 1..]
                .iter_mut()
                .zip(&ls[k * M + k + 1..k * M + M])
            {
                *bi -= *li * yk;
            }
            total += yk * yk * self.inv_d[k];
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{cholesky, solve_lower, solve_lower_transpose};
    use approx::assert_relative_eq;
    use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

    #[test]
    fn a_hand_computed_3x3() {
        // A = L D Lᵀ with L = [[1,0,0],[0.5,1,0],[-1,2,1]], D = diag(4, 2, 3).
        let l = Matrix3::new(1.0, 0.0, 0.0, 0.5, 1.0, 0.0, -1.0, 2.0, 1.0);
        let d = Matrix3::from_diagonal(&Vector3::new(4.0, 2.0, 3.0));
        let a = l * d * l.transpose();
        let f = Ldl::new(&a).unwrap();
        assert_relative_eq!(f.inv_d[0], 0.25, epsilon = 1e-15);
        assert_relative_eq!(f.inv_d[1], 0.5, epsilon = 1e-15);
        assert_relative_eq!(f.inv_d[2], 1.0 / 3.0, epsilon = 1e-15);
        for (i, j) in [(1, 0), (2, 0), (2, 1)] {
            assert_relative_eq!(f.l[(i, j)], l[(i, j)], epsilon = 1e-15);
        }
        let b = Matrix3x2::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
        let mut x = b;
        f.solve_in_place(&mut x);
        assert_relative_eq!(a * x, b, epsilon = 1e-12);
        let v = Vector3::new(1.0, -2.0, 0.5);
        let direct = v.dot(&(a.try_inverse().unwrap() * v));
        assert_relative_eq!(f.quadratic_form(&v), direct, epsilon = 1e-13);
    }

    /// The unrolled elimination used below `UNROLL_FROM` equals the
    /// column loop to rounding and fails at the same pivot.
    #[test]
    fn the_unrolled_elimination_equals_the_column_loop() {
        fn check<const M: usize>() {
            for seed in 0..10 {
                let a = SMatrix::<f64, M, M>::from_fn(|i, j| {
                    ((i * i * 5 + j * 3 + i * j + seed * 11) as f64).sin()
                });
                let p = a * a.transpose() + SMatrix::identity() * 0.1;
                let (small, general) = (Ldl::by(&p, true).unwrap(), Ldl::by(&p, false).unwrap());
                assert_relative_eq!(
                    small.l.lower_triangle(),
                    general.l.lower_triangle(),
                    epsilon = 1e-12
                );
                for (s, g) in small.inv_d.iter().zip(&general.inv_d) {
                    assert_relative_eq!(*s, *g, max_relative = 1e-12);
                }
                let mut bad = p;
                bad[(seed % M, seed % M)] = -1.0;
                assert_eq!(Ldl::by(&bad, true).err(), Ldl::by(&bad, false).err());
                assert!(Ldl::by(&bad, true).is_err());
            }
        }
        check::<3>();
        check::<4>();
        check::<6>();
        check::<9>();
    }

    /// `X A⁻¹` by the right-hand solves is `(A⁻¹ Xᵀ)ᵀ` by the left-hand
    /// ones bit for bit (the unadapted update picks either by size), on
    /// both sides of `UNROLL_FROM`, for `f64` and `f32`; and a
    /// hand-computed case: `[[4, 2], [2, 5]]⁻¹` applied to the row `(8, 9)`.
    #[test]
    fn right_hand_solves_equal_the_left_hand_ones_bit_for_bit() {
        fn check<T: Real, const M: usize, const R: usize>() {
            for seed in 0..5 {
                let a = SMatrix::<f64, M, M>::from_fn(|i, j| {
                    ((i * i * 5 + j * 3 + i * j + seed * 11) as f64).sin()
                });
                let p = (a * a.transpose() + SMatrix::identity() * 0.1).map(lit::<T>);
                let x = SMatrix::<f64, R, M>::from_fn(|i, j| {
                    ((i * 7 + j * 13 + seed) as f64).cos() * 3.0
                })
                .map(lit::<T>);
                let f = Ldl::new(&p).unwrap();
                let mut right = x;
                f.solve_right_in_place(&mut right);
                let mut left = x.transpose();
                f.solve_in_place(&mut left);
                assert_eq!(right, left.transpose(), "M = {M}, R = {R}, seed {seed}");
            }
        }
        check::<f64, 1, 4>();
        check::<f64, 2, 2>();
        check::<f64, 3, 7>();
        check::<f64, 6, 15>();
        check::<f64, 9, 11>();
        check::<f64, 12, 24>();
        check::<f32, 6, 15>();
        check::<f32, 12, 3>();

        let f = Ldl::new(&Matrix2::new(4.0, 2.0, 2.0, 5.0)).unwrap();
        let mut row = nalgebra::Matrix1x2::new(8.0, 9.0);
        f.solve_right_in_place(&mut row);
        assert_relative_eq!(row, nalgebra::Matrix1x2::new(1.375, 1.25), epsilon = 1e-15);
    }

    #[test]
    fn two_by_two_from_the_minors() {
        // [[4, 2], [2, 5]] = L D Lᵀ with l₂₁ = ½, D = diag(4, 4).
        let a = Matrix2::new(4.0, 2.0, 2.0, 5.0);
        let f = Ldl::new(&a).unwrap();
        assert_eq!((f.l[(1, 0)], f.inv_d), (0.5, [0.25, 0.25]));
        let mut x = Vector2::new(8.0, 9.0);
        f.solve_in_place(&mut x);
        assert_relative_eq!(x, Vector2::new(1.375, 1.25), epsilon = 1e-15);
        assert_relative_eq!(
            f.quadratic_form(&Vector2::new(8.0, 9.0)),
            22.25,
            epsilon = 1e-13
        );
        let l = cholesky(&a).unwrap();
        let mut by_cholesky = Vector2::new(-3.0, 0.7);
        solve_lower(&l, &mut by_cholesky);
        solve_lower_transpose(&l, &mut by_cholesky);
        let mut by_ldl = Vector2::new(-3.0, 0.7);
        f.solve_in_place(&mut by_ldl);
        assert_relative_eq!(by_ldl, by_cholesky, epsilon = 1e-15, max_relative = 1e-14);
        for bad in [
            Matrix2::new(1.0, 2.0, 2.0, 1.0),
            Matrix2::new(-1.0, 0.0, 0.0, 1.0),
            Matrix2::new(0.0, 0.0, 0.0, 1.0),
            Matrix2::new(1.0, 1.0, 1.0, 1.0),
            Matrix2::new(1.0, f64::NAN, f64::NAN, 1.0),
            Matrix2::new(f64::INFINITY, 0.0, 0.0, 1.0),
            Matrix2::new(1.0, 0.0, 0.0, f64::NAN),
        ] {
            assert_eq!(
                Ldl::new(&bad).unwrap_err(),
                cholesky(&bad).unwrap_err(),
                "{bad}"
            );
        }
    }

    /// `L⁻¹ B` with the unit `L`: hand-computed at three, and equal to
    /// the first of `solve_in_place`'s passes (`D⁻¹` and `L⁻ᵀ` applied by
    /// hand after it) on both sides of `UNROLL_FROM`.
    #[test]
    fn the_unit_lower_solve() {
        // L = [[1,0,0],[0.5,1,0],[-1,2,1]], D = diag(4, 2, 3); L y = (1, 2.5, 3):
        // y = (1, 2, 3 + 1 − 4) = (1, 2, 0).
        let l = Matrix3::new(1.0, 0.0, 0.0, 0.5, 1.0, 0.0, -1.0, 2.0, 1.0);
        let d = Matrix3::from_diagonal(&Vector3::new(4.0, 2.0, 3.0));
        let f = Ldl::new(&(l * d * l.transpose())).unwrap();
        let mut y = Vector3::new(1.0, 2.5, 3.0);
        f.solve_unit_lower_in_place(&mut y);
        assert_relative_eq!(y, Vector3::new(1.0, 2.0, 0.0), epsilon = 1e-15);
        fn check<const M: usize>() {
            let a = SMatrix::<f64, M, M>::from_fn(|i, j| ((i * 3 + j * 5) as f64 * 0.41).sin());
            let c = a * a.transpose() + SMatrix::identity() * 0.3;
            let f = Ldl::new(&c).unwrap();
            let b = SMatrix::<f64, M, 2>::from_fn(|i, j| ((i + 4 * j) as f64).cos());
            let mut x = b;
            f.solve_unit_lower_in_place(&mut x);
            let unit = SMatrix::<f64, M, M>::from_fn(|i, j| match i.cmp(&j) {
                core::cmp::Ordering::Greater => f.l[(i, j)],
                core::cmp::Ordering::Equal => 1.0,
                core::cmp::Ordering::Less => 0.0,
            });
            assert_relative_eq!(unit * x, b, epsilon = 1e-12);
            let d = SMatrix::<f64, M, M>::from_diagonal(&SVector::from_fn(|k, _| {
                f.inverse_pivots()[k].recip()
            }));
            assert_relative_eq!(unit * d * unit.transpose(), c, epsilon = 1e-12);
        }
        check::<4>();
        check::<9>();
        check::<12>();
    }

    /// `X L⁻ᵀ` from the right: `Y Lᵀ = X` (by hand at three components,
    /// to rounding at 1–12), and for a symmetric `X` the transpose of the
    /// left solve on `X` bit for bit, as the posterior view takes it.
    #[test]
    fn the_unit_lower_transpose_solve_from_the_right() {
        // L as above; X = [[1, 2.5, 3]] (one row): Y Lᵀ = X is L y = x,
        // y = (1, 2, 0).
        let l = Matrix3::new(1.0, 0.0, 0.0, 0.5, 1.0, 0.0, -1.0, 2.0, 1.0);
        let d = Matrix3::from_diagonal(&Vector3::new(4.0, 2.0, 3.0));
        let f = Ldl::new(&(l * d * l.transpose())).unwrap();
        let mut x = nalgebra::RowVector3::new(1.0, 2.5, 3.0);
        f.solve_unit_lower_transpose_right_in_place(&mut x);
        assert_relative_eq!(x, nalgebra::RowVector3::new(1.0, 2.0, 0.0), epsilon = 1e-15);
        fn check<const M: usize>() {
            let a = SMatrix::<f64, M, M>::from_fn(|i, j| ((i * 3 + j * 5) as f64 * 0.41).sin());
            let c = a * a.transpose() + SMatrix::identity() * 0.3;
            let f = Ldl::new(&c).unwrap();
            let unit = SMatrix::<f64, M, M>::from_fn(|i, j| match i.cmp(&j) {
                core::cmp::Ordering::Greater => f.l[(i, j)],
                core::cmp::Ordering::Equal => 1.0,
                core::cmp::Ordering::Less => 0.0,
            });
            let b = SMatrix::<f64, 3, M>::from_fn(|i, j| ((i + 4 * j) as f64).cos());
            let mut y = b;
            f.solve_unit_lower_transpose_right_in_place(&mut y);
            assert_relative_eq!(y * unit.transpose(), b, epsilon = 1e-12);
            // A symmetric X: the left solve's transpose, bit for bit.
            let s = SMatrix::<f64, M, M>::from_fn(|i, j| ((i * j + i + j) as f64 * 0.7).sin());
            let s = s + s.transpose();
            let mut left = s;
            f.solve_unit_lower_in_place(&mut left);
            let mut right = s;
            f.solve_unit_lower_transpose_right_in_place(&mut right);
            assert_eq!(right, left.transpose());
        }
        check::<1>();
        check::<2>();
        check::<4>();
        check::<6>();
        check::<9>();
        check::<12>();
    }

    #[test]
    fn equals_the_cholesky_solves_to_rounding() {
        let a = Matrix3::new(4.0, 1.0, -0.5, 1.0, 3.0, 0.25, -0.5, 0.25, 2.0);
        let l = cholesky(&a).unwrap();
        let b = Matrix3x2::new(1.0, -2.0, 0.5, 3.0, -1.0, 4.0);
        let mut by_cholesky = b;
        solve_lower(&l, &mut by_cholesky);
        solve_lower_transpose(&l, &mut by_cholesky);
        let mut by_ldl = b;
        Ldl::new(&a).unwrap().solve_in_place(&mut by_ldl);
        assert_relative_eq!(by_ldl, by_cholesky, epsilon = 1e-15, max_relative = 1e-14);
    }

    #[test]
    fn its_cholesky_factor_is_the_cholesky_factor_to_rounding() {
        fn check<const M: usize>() {
            let a = SMatrix::<f64, M, M>::from_fn(|i, j| ((i * 5 + j * 3) as f64 * 0.71).sin());
            let c = a * a.transpose() + SMatrix::identity() * 0.5;
            let l = Ldl::new(&c).unwrap().cholesky_factor();
            let reference = cholesky(&c).unwrap();
            assert_relative_eq!(l, reference, epsilon = 1e-14 * reference.amax());
            // Exactly lower triangular, and L Lᵀ = C.
            for j in 0..M {
                for i in 0..j {
                    assert_eq!(l[(i, j)], 0.0);
                }
            }
            assert_relative_eq!(l * l.transpose(), c, epsilon = 1e-13 * c.amax());
        }
        check::<1>();
        check::<2>();
        check::<3>();
        check::<6>();
        check::<12>();
        // Hand-computed: [[4, 2], [2, 5]] = [[2, 0], [1, 2]] [[2, 1], [0, 2]].
        let l = Ldl::new(&Matrix2::new(4.0, 2.0, 2.0, 5.0))
            .unwrap()
            .cholesky_factor();
        assert_eq!(l, Matrix2::new(2.0, 0.0, 1.0, 2.0));
    }

    #[test]
    fn refuses_what_cholesky_refuses_with_the_same_index() {
        let cases = [
            Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0),
            Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0),
            Matrix3::new(1.0, 0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 1.0),
            Matrix3::new(0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
            // Singular to working precision: rank one.
            Matrix3::new(1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0),
        ];
        for a in cases {
            let expected = cholesky(&a).unwrap_err();
            assert_eq!(Ldl::new(&a).unwrap_err(), expected, "{a}");
        }
    }
}
