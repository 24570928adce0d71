//! A covariance held together with its Cholesky factor.

use nalgebra::SMatrix;

use super::{cholesky, mirror_lower, NotPositiveDefinite};
use crate::Real;

/// A symmetric positive-definite matrix `A` and its lower Cholesky factor
/// `L` (`A = L Lᵀ` to rounding), computed together so that they cannot
/// disagree: the only way to make one is [`new`](Self::new), which factors
/// the matrix it is given.
///
/// An adapter that estimates a covariance checks each estimate by factoring
/// it anyway; handing both to
/// [`GainStep::set_factored_noise`](crate::adapter::GainStep::set_factored_noise)
/// spares the update a factorisation (for its Joseph form) and the product
/// `L Lᵀ` (for its innovation covariance): the pair stands where the
/// model's `R` and its cached factor stand in an update without adapters.
///
/// ```
/// use kestrel_core::linalg::FactoredCovariance;
/// use kestrel_core::nalgebra::Matrix2;
/// // The lower triangle is used: the 9 above the diagonal is not read.
/// let r = FactoredCovariance::new(Matrix2::new(4.0, 9.0, 2.0, 10.0)).unwrap();
/// assert_eq!(*r.matrix(), Matrix2::new(4.0, 2.0, 2.0, 10.0));
/// assert_eq!(*r.factor(), Matrix2::new(2.0, 0.0, 1.0, 3.0));
/// // An indefinite matrix has no factor: the pivot that failed is named.
/// let e = FactoredCovariance::new(Matrix2::new(1.0, 2.0, 2.0, 1.0)).unwrap_err();
/// assert_eq!(e.index, 1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FactoredCovariance<T: Real, const M: usize> {
    matrix: SMatrix<T, M, M>,
    factor: SMatrix<T, M, M>,
}

impl<T: Real, const M: usize> FactoredCovariance<T, M> {
    /// Factors `a` (its lower triangle, mirrored, so the matrix kept is
    /// exactly symmetric) by [`cholesky`].
    ///
    /// # Errors
    /// [`NotPositiveDefinite`] with the failing pivot when `a` is not
    /// finite and positive definite to working precision.
    #[inline]
    pub fn new(a: SMatrix<T, M, M>) -> Result<Self, NotPositiveDefinite> {
        let mut matrix = a;
        mirror_lower(&mut matrix);
        let factor = cholesky(&matrix)?;
        Ok(Self { matrix, factor })
    }

    /// The matrix `A`, exactly symmetric.
    pub fn matrix(&self) -> &SMatrix<T, M, M> {
        &self.matrix
    }

    /// Its lower Cholesky factor `L` (zeros above the diagonal).
    pub fn factor(&self) -> &SMatrix<T, M, M> {
        &self.factor
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Vector3};

    use super::*;

    #[test]
    fn the_factor_reproduces_the_matrix_and_is_lower_triangular() {
        let a = Matrix3::new(4.0, 0.0, 0.0, 2.0, 5.0, 0.0, -2.0, 1.0, 6.0);
        let f = FactoredCovariance::new(a).unwrap();
        let symmetric = Matrix3::new(4.0, 2.0, -2.0, 2.0, 5.0, 1.0, -2.0, 1.0, 6.0);
        assert_eq!(*f.matrix(), symmetric);
        // By hand: L = [2 0 0; 1 2 0; −1 1 2].
        let l = Matrix3::new(2.0, 0.0, 0.0, 1.0, 2.0, 0.0, -1.0, 1.0, 2.0);
        assert_eq!(*f.factor(), l);
        assert_eq!(l * l.transpose(), symmetric);
    }

    #[test]
    fn non_finite_or_indefinite_matrices_are_refused_with_their_pivot() {
        let mut a = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0));
        a[(2, 2)] = f64::NAN;
        assert_eq!(FactoredCovariance::new(a).unwrap_err().index, 2);
        a[(2, 2)] = -1.0;
        assert_eq!(FactoredCovariance::new(a).unwrap_err().index, 2);
        let f32_zero = Matrix3::<f32>::zeros();
        assert_eq!(FactoredCovariance::new(f32_zero).unwrap_err().index, 0);
        // Overflow on the way is refused, not carried as ∞ or NaN.
        // (1e308 + 1e308 on the diagonal is ∞: pivot 0.)
        let huge = Matrix3::from_element(1e308) + Matrix3::identity() * 1e308;
        assert_eq!(FactoredCovariance::new(huge).unwrap_err().index, 0);
        // 1e308 on the diagonal, 1e154 off it: the products stay finite.
        let large: Matrix3<f64> = Matrix3::identity() * 1e308 + Matrix3::from_element(1e154);
        let f = FactoredCovariance::new(large).unwrap();
        assert!(f.factor().iter().all(|v: &f64| v.is_finite()));
        let mut infinite = Matrix3::<f64>::identity();
        infinite[(1, 0)] = f64::INFINITY;
        assert!(FactoredCovariance::new(infinite).is_err());
    }
}
