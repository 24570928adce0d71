use nalgebra::SMatrix;

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
            let lk = &ls[k * N + k + 1..k * N + N];
            for (bi, li) in col[k + 1..].iter_mut().zip(lk) {
                *bi -= *li * xk;
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
            let lk = &ls[k * N + k + 1..k * N + N];
            let mut acc = col[k];
            for (xi, li) in col[k + 1..].iter().zip(lk) {
                acc -= *li * *xi;
            }
            col[k] = acc * inv[k];
        }
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
}
