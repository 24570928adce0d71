//! Direct observation of chosen state components.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{FilterError, LinearizedMeasurement, MeasurementModel, Real};

/// Measures `M` components of an `N`-state directly: `zᵢ = x[indices[i]] + vᵢ`,
/// `v ~ N(0, R)`. `H` is the selection matrix with a single 1 per row.
///
/// ```
/// use kestrel_models::Selection;
/// use kestrel_core::{LinearizedMeasurement, MeasurementModel,
///     nalgebra::{Matrix2, Vector2, Vector4}};
/// // The two positions of a planar constant-velocity state [pₓ, vₓ, p_y, v_y].
/// let pos = Selection::<f64, 4, 2>::new([0, 2], Matrix2::identity() * 0.25).unwrap();
/// let x = Vector4::new(1.0, 2.0, 3.0, 4.0);
/// assert_eq!(pos.predict(&x), Vector2::new(1.0, 3.0));
/// assert_eq!(pos.jacobian(&x) * x, pos.predict(&x));
/// assert_eq!(pos.indices(), &[0, 2]);
/// assert!(Selection::<f64, 4, 1>::new([4], Default::default()).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Selection<T: Real, const N: usize, const M: usize> {
    indices: [usize; M],
    /// The measurement noise covariance `R`.
    pub noise: SMatrix<T, M, M>,
}

impl<T: Real, const N: usize, const M: usize> Selection<T, N, M> {
    /// Observes `x[indices[i]]` with noise `r` (checked by the filter's
    /// input contract at each update). Repeated indices are allowed (two
    /// sensors of one state).
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"indices"` unless every index is
    /// below `N`.
    pub fn new(indices: [usize; M], r: SMatrix<T, M, M>) -> Result<Self, FilterError> {
        if !indices.iter().all(|&i| i < N) {
            return Err(FilterError::InvalidParameter {
                name: "indices",
                valid: "each below the state size N",
            });
        }
        Ok(Self { indices, noise: r })
    }

    /// The observed state indices.
    pub fn indices(&self) -> &[usize; M] {
        &self.indices
    }
}

impl<T: Real, const N: usize, const M: usize> MeasurementModel<T, N, M> for Selection<T, N, M> {
    fn predict(&self, x: &SVector<T, N>) -> SVector<T, M> {
        SVector::from_fn(|i, _| x[self.indices[i]])
    }

    fn noise(&self) -> SMatrix<T, M, M> {
        self.noise
    }
}

impl<T: Real, const N: usize, const M: usize> LinearizedMeasurement<T, N, M>
    for Selection<T, N, M>
{
    fn jacobian(&self, _x: &SVector<T, N>) -> SMatrix<T, M, N> {
        let mut h = SMatrix::zeros();
        for (row, &col) in self.indices.iter().enumerate() {
            h[(row, col)] = T::one();
        }
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix1, Matrix3, Matrix3x6, Vector3, Vector6};

    #[test]
    fn selection_matrix() {
        let s = Selection::<f64, 6, 3>::new([5, 0, 5], Matrix3::identity()).unwrap();
        #[rustfmt::skip]
        let want = Matrix3x6::new(
            0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        );
        let x = Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
        assert_eq!(s.jacobian(&x), want);
        assert_eq!(s.predict(&x), Vector3::new(6.0, 1.0, 6.0));
        assert_eq!(s.noise(), Matrix3::identity());
    }

    #[test]
    fn indices_validated() {
        assert!(Selection::<f32, 3, 1>::new([2], Matrix1::new(1.0)).is_ok());
        assert!(Selection::<f32, 3, 1>::new([3], Matrix1::new(1.0)).is_err());
        assert!(Selection::<f32, 3, 2>::new([0, usize::MAX], Default::default()).is_err());
    }
}
