//! The last noise covariance a form checked, with its Cholesky factor.

use nalgebra::SMatrix;

use crate::contract::{check_covariance, same_values};
use crate::{FilterError, Quantity, Real};

/// The last `Q` or `R` a form checked and its Cholesky factor, in the
/// leading `M × M` block of `N × N` storage (`M ≤ N`; larger matrices are
/// checked every time). A noise that stays the same from step to step — the
/// common case — is checked and factored once; any change, and any NaN
/// (which never compares equal), goes through the full check again.
#[derive(Debug, Clone)]
pub(crate) struct CheckedNoise<T: Real, const N: usize> {
    noise: SMatrix<T, N, N>,
    factor: SMatrix<T, N, N>,
    /// The size `M` held, 0 when empty.
    size: usize,
}

impl<T: Real, const N: usize> CheckedNoise<T, N> {
    /// Nothing checked yet.
    pub fn new() -> Self {
        Self {
            noise: SMatrix::zeros(),
            factor: SMatrix::zeros(),
            size: 0,
        }
    }

    /// The lower Cholesky factor of `a` after the checks of
    /// [`check_covariance`], from the cache when `a` equals the matrix
    /// checked last (element for element, as supplied).
    #[inline(always)]
    pub fn check<const M: usize>(
        &mut self,
        a: &SMatrix<T, M, M>,
        what: Quantity,
    ) -> Result<SMatrix<T, M, M>, FilterError> {
        if self.holds(a) {
            return Ok(SMatrix::from_column_slice(&self.factor.as_slice()[..M * M]));
        }
        self.check_and_keep(a, what)
    }

    /// [`check`](Self::check) for a matrix of the storage's own size (a
    /// process noise), the factor borrowed from the cache rather than
    /// copied out of it.
    #[inline(always)]
    pub fn check_full(
        &mut self,
        a: &SMatrix<T, N, N>,
        what: Quantity,
    ) -> Result<&SMatrix<T, N, N>, FilterError> {
        if !self.holds(a) {
            self.check_and_keep(a, what)?;
        }
        Ok(&self.factor)
    }

    /// Whether the cache holds `a`, element for element as supplied.
    #[inline(always)]
    fn holds<const M: usize>(&self, a: &SMatrix<T, M, M>) -> bool {
        M <= N && self.size == M && same_values(&self.noise.as_slice()[..M * M], a.as_slice())
    }

    /// The full check of [`check`](Self::check), out of line, keeping the
    /// result.
    #[inline(never)]
    fn check_and_keep<const M: usize>(
        &mut self,
        a: &SMatrix<T, M, M>,
        what: Quantity,
    ) -> Result<SMatrix<T, M, M>, FilterError> {
        let len = M * M;
        let factor = check_covariance(a, what)?;
        if M <= N {
            self.noise.as_mut_slice()[..len].copy_from_slice(a.as_slice());
            self.factor.as_mut_slice()[..len].copy_from_slice(factor.as_slice());
            self.size = M;
        }
        Ok(factor)
    }
}

/// A cache is not part of a form's value: two forms holding the same
/// covariance are equal whatever they checked last.
impl<T: Real, const N: usize> PartialEq for CheckedNoise<T, N> {
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix2, Matrix3};

    use super::*;

    #[test]
    fn a_repeated_noise_comes_from_the_cache_and_a_changed_one_is_checked() {
        let mut c = CheckedNoise::<f64, 2>::new();
        let r = Matrix2::new(4.0, 2.0, 2.0, 5.0);
        let l = c.check(&r, Quantity::MeasurementNoise).unwrap();
        assert_eq!(l, Matrix2::new(2.0, 0.0, 1.0, 2.0));
        assert_eq!(c.check(&r, Quantity::MeasurementNoise).unwrap(), l);
        // A change is checked again: an indefinite R is refused even right
        // after a valid one was cached.
        let bad = Matrix2::new(1.0, 2.0, 2.0, 1.0);
        assert_eq!(
            c.check(&bad, Quantity::MeasurementNoise).unwrap_err(),
            FilterError::NotPositiveDefinite {
                what: Quantity::MeasurementNoise,
                index: 1
            }
        );
        // A NaN never equals the cached matrix.
        let mut nan = r;
        nan[(0, 0)] = f64::NAN;
        assert!(matches!(
            c.check(&nan, Quantity::MeasurementNoise),
            Err(FilterError::NonFinite { .. })
        ));
        // A 1 × 1 noise after a 2 × 2 one is not confused with its corner.
        let one = nalgebra::Matrix1::new(4.0);
        assert_eq!(c.check(&one, Quantity::MeasurementNoise).unwrap()[0], 2.0);
        // Larger than the storage: checked every time, still correct.
        let big = Matrix3::from_diagonal_element(9.0);
        assert_eq!(
            c.check(&big, Quantity::MeasurementNoise).unwrap(),
            Matrix3::from_diagonal_element(3.0)
        );
    }

    #[test]
    fn a_full_size_noise_lends_its_factor_and_is_checked_again_when_changed() {
        let mut c = CheckedNoise::<f64, 2>::new();
        let q = Matrix2::new(4.0, 2.0, 2.0, 5.0);
        let l = Matrix2::new(2.0, 0.0, 1.0, 2.0);
        assert_eq!(c.check_full(&q, Quantity::ProcessNoise).unwrap(), &l);
        assert_eq!(c.check_full(&q, Quantity::ProcessNoise).unwrap(), &l);
        // A smaller noise checked in between does not stand for the full one.
        let one = nalgebra::Matrix1::new(9.0);
        assert_eq!(c.check(&one, Quantity::ProcessNoise).unwrap()[0], 3.0);
        assert_eq!(c.check_full(&q, Quantity::ProcessNoise).unwrap(), &l);
        // A change is checked again and refused; the one before still holds.
        let bad = Matrix2::new(1.0, 2.0, 2.0, 1.0);
        assert_eq!(
            c.check_full(&bad, Quantity::ProcessNoise).unwrap_err(),
            FilterError::NotPositiveDefinite {
                what: Quantity::ProcessNoise,
                index: 1
            }
        );
        let mut nan = q;
        nan[(1, 1)] = f64::NAN;
        assert!(matches!(
            c.check_full(&nan, Quantity::ProcessNoise),
            Err(FilterError::NonFinite { .. })
        ));
        assert_eq!(c.check_full(&q, Quantity::ProcessNoise).unwrap(), &l);
    }
}
