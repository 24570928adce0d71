use nalgebra::SMatrix;

use super::cholesky::UNROLL_FROM;
use super::product::add_scaled;
use crate::Real;

/// Solves `L X = B` in place (`B ← L⁻¹ B`) for a lower-triangular `L` with a
/// non-zero diagonal, such as a factor from [`cholesky`](super::cholesky).
///
/// ```
/// use kestrel_core::linalg::solve_lower;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let l = Matrix2::new(2.0, 0.0, 1.0, 4.0);
/// let mut b = Vector2::new(2.0, 9.0);
/// solve_lower(&l, &mut b);
/// assert_eq!(b, Vector2::new(1.0, 2.0));
/// ```
#[inline]
pub fn solve_lower<T: Real, const N: usize, const K: usize>(
    l: &SMatrix<T, N, N>,
    b: &mut SMatrix<T, N, K>,
) {
    let ls = l.as_slice();
    let inv = reciprocal_diagonal(l);
    for c in 0..K {
        let col = &mut b.as_mut_slice()[c * N..c * N + N];
        for k in 0..N {
            let xk = col[k] * inv[k];
            col[k] = xk;
            if N < UNROLL_FROM {
                // Constant trip counts, the bound as a condition: the
                // compiler unrolls the whole column (the same arithmetic).
                for i in 0..N {
                    if i > k {
                        col[i] -= ls[k * N + i] * xk;
                    }
                }
            } else {
                let lk = &ls[k * N + k + 1..k * N + N];
                for (bi, li) in col[k + 1..].iter_mut().zip(lk) {
                    *bi -= *li * xk;
                }
            }
        }
    }
}

/// Solves `Lᵀ X = B` in place (`B ← L⁻ᵀ B`) for a lower-triangular `L` with
/// a non-zero diagonal.
///
/// ```
/// use kestrel_core::linalg::solve_lower_transpose;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let l = Matrix2::new(2.0, 0.0, 1.0, 4.0);
/// let mut b = Vector2::new(4.0, 8.0); // Lᵀ = [[2, 1], [0, 4]]
/// solve_lower_transpose(&l, &mut b);
/// assert_eq!(b, Vector2::new(1.0, 2.0));
/// ```
#[inline]
pub fn solve_lower_transpose<T: Real, const N: usize, const K: usize>(
    l: &SMatrix<T, N, N>,
    b: &mut SMatrix<T, N, K>,
) {
    let ls = l.as_slice();
    let inv = reciprocal_diagonal(l);
    for c in 0..K {
        let col = &mut b.as_mut_slice()[c * N..c * N + N];
        for k in (0..N).rev() {
            let mut acc = col[k];
            if N < UNROLL_FROM {
                // As in `solve_lower`: unrolled, the same arithmetic.
                for i in 0..N {
                    if i > k {
                        acc -= ls[k * N + i] * col[i];
                    }
                }
            } else {
                let lk = &ls[k * N + k + 1..k * N + N];
                for (xi, li) in col[k + 1..].iter().zip(lk) {
                    acc -= *li * *xi;
                }
            }
            col[k] = acc * inv[k];
        }
    }
}

/// `B ← B C⁻¹` for `C = L Lᵀ` (the gain `K = P_xz C⁻¹` from the cross
/// covariance) by two right-hand solves, `B L⁻ᵀ` then `· L⁻¹`. Bit for bit
/// [`solve_lower`] then [`solve_lower_transpose`] on `Bᵀ`, transposed: each
/// element gets the same products subtracted in the same order. But the
/// work runs down the columns of `B`, all its `R` rows at once, where the
/// left-hand solves run one row of `B` at a time through `M` pivots (scalar
/// code when `M` is small).
#[inline]
pub(crate) fn solve_right_cholesky<T: Real, const R: usize, const M: usize>(
    l: &SMatrix<T, M, M>,
    b: &mut SMatrix<T, R, M>,
) {
    let inv = reciprocal_diagonal(l);
    let cols = &mut b.data.0;
    // `a + c · (−f)` is `a − c f` exactly: negation commutes with rounding.
    // Y Lᵀ = B, column by column forwards: Yⱼ = (Bⱼ − Σₖ₍ₖ<ⱼ₎ Yₖ Lⱼₖ) / Lⱼⱼ.
    for j in 0..M {
        let mut acc = cols[j];
        for k in 0..j {
            add_scaled(&mut acc, &cols[k], -l[(j, k)]);
        }
        scale(&mut acc, inv[j]);
        cols[j] = acc;
    }
    // X L = Y, backwards: Xⱼ = (Yⱼ − Σₖ₍ₖ>ⱼ₎ Xₖ Lₖⱼ) / Lⱼⱼ.
    for j in (0..M).rev() {
        let mut acc = cols[j];
        for k in j + 1..M {
            add_scaled(&mut acc, &cols[k], -l[(k, j)]);
        }
        scale(&mut acc, inv[j]);
        cols[j] = acc;
    }
}

#[inline(always)]
fn scale<T: Real, const R: usize>(acc: &mut [T; R], f: T) {
    for a in acc.iter_mut() {
        *a *= f;
    }
}

/// `1 / L_kk`: one division per pivot instead of one per pivot and
/// right-hand side (divisions dominate short solves with many columns).
fn reciprocal_diagonal<T: Real, const N: usize>(l: &SMatrix<T, N, N>) -> [T; N] {
    core::array::from_fn(|k| l[(k, k)].recip())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix3, Matrix3x2};

    #[test]
    fn solves_match_inverse() {
        let l = Matrix3::new(2.0, 0.0, 0.0, -1.0, 3.0, 0.0, 0.5, 0.25, 1.5);
        let b = Matrix3x2::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
        let inv = l.try_inverse().unwrap();
        let mut x = b;
        solve_lower(&l, &mut x);
        assert_relative_eq!(x, inv * b, epsilon = 1e-14);
        let mut y = b;
        solve_lower_transpose(&l, &mut y);
        assert_relative_eq!(y, inv.transpose() * b, epsilon = 1e-14);
    }

    /// `B C⁻¹` by the right-hand solves equals the left-hand solves on
    /// `Bᵀ`, transposed, bit for bit, in both types and for 1, 2, 3, 5, 6 and 7
    /// columns of `C` (the SR-UKF's gain takes this path).
    #[test]
    fn the_right_hand_solves_equal_the_left_hand_ones_bit_for_bit() {
        fn check<T: Real, const R: usize, const M: usize>() {
            let a = SMatrix::<T, M, M>::from_fn(|i, j| {
                crate::real::lit::<T>(
                    ((i * 5 + j * 3) as f64 * 0.71).sin() + if i == j { 3.0 } else { 0.0 },
                )
            });
            let c = a * a.transpose();
            let l = crate::linalg::cholesky(&c).unwrap();
            let b = SMatrix::<T, R, M>::from_fn(|i, j| {
                crate::real::lit::<T>(((i * 7 + j * 11) as f64 * 0.37).cos() * 10.0)
            });
            let mut left = b.transpose();
            solve_lower(&l, &mut left);
            solve_lower_transpose(&l, &mut left);
            let mut right = b;
            solve_right_cholesky(&l, &mut right);
            assert_eq!(right, left.transpose(), "R = {R}, M = {M}");
            let direct = b * c.try_inverse().unwrap();
            let tol = crate::real::lit::<T>(1e-4);
            for (x, y) in right.iter().zip(direct.iter()) {
                assert!(
                    (*x - *y).abs() <= tol * (T::one() + y.abs()),
                    "R = {R}, M = {M}"
                );
            }
        }
        check::<f64, 15, 1>();
        check::<f64, 15, 2>();
        check::<f64, 15, 6>();
        check::<f64, 4, 7>();
        check::<f64, 1, 3>();
        check::<f32, 15, 6>();
        check::<f32, 9, 5>();
    }
}
