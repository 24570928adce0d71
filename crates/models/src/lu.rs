//! LU factorisation with partial pivoting for fixed-size matrices
//! (nalgebra's own needs typenum bounds that a generic `const N` lacks).

use kestrel_core::nalgebra::SMatrix;
use kestrel_core::Real;

/// `P A = L U` stored in one matrix (unit-diagonal `L` below, `U` on and
/// above the diagonal), with the row permutation.
pub(crate) struct Lu<T: Real, const N: usize> {
    lu: SMatrix<T, N, N>,
    perm: [usize; N],
}

impl<T: Real, const N: usize> Lu<T, N> {
    /// Factors `a`; `None` on a zero or non-finite pivot.
    pub(crate) fn new(a: &SMatrix<T, N, N>) -> Option<Self> {
        let mut lu = *a;
        let mut perm: [usize; N] = core::array::from_fn(|i| i);
        for k in 0..N {
            let p = (k..N).fold(k, |best, i| {
                if lu[(i, k)].abs() > lu[(best, k)].abs() {
                    i
                } else {
                    best
                }
            });
            let pivot = lu[(p, k)];
            if pivot == T::zero() || !pivot.is_finite() {
                return None;
            }
            if p != k {
                lu.swap_rows(p, k);
                perm.swap(p, k);
            }
            for i in k + 1..N {
                let l = lu[(i, k)] / pivot;
                lu[(i, k)] = l;
                for j in k + 1..N {
                    let u = lu[(k, j)];
                    lu[(i, j)] -= l * u;
                }
            }
        }
        Some(Self { lu, perm })
    }

    /// `A⁻¹ b`.
    pub(crate) fn solve<const K: usize>(&self, b: &SMatrix<T, N, K>) -> SMatrix<T, N, K> {
        let mut x = SMatrix::<T, N, K>::from_fn(|i, j| b[(self.perm[i], j)]);
        for c in 0..K {
            for i in 1..N {
                let mut s = x[(i, c)];
                for k in 0..i {
                    s -= self.lu[(i, k)] * x[(k, c)];
                }
                x[(i, c)] = s;
            }
            for i in (0..N).rev() {
                let mut s = x[(i, c)];
                for k in i + 1..N {
                    s -= self.lu[(i, k)] * x[(k, c)];
                }
                x[(i, c)] = s / self.lu[(i, i)];
            }
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix3, Matrix3x2};

    #[test]
    fn solves_with_pivoting() {
        // A zero leading entry forces a row exchange.
        let a = Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let x = Matrix3x2::new(1.0, -1.0, 2.0, 0.5, -3.0, 4.0);
        let got = Lu::new(&a).unwrap().solve(&(a * x));
        assert!((got - x).norm() < 1e-14, "{got}");
    }

    #[test]
    fn singular_and_non_finite() {
        let a = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(Lu::new(&a).is_none());
        assert!(Lu::new(&Matrix3::from_element(f64::NAN)).is_none());
    }
}
