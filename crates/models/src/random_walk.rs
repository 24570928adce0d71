//! Random-walk states (biases, slowly drifting parameters).

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

/// `N` independent random walks: `ẋᵢ = wᵢ` with white noise of spectral
/// density `qᵢ` [unit²/s], so over `dt`: `Φ = I`, `Q = diag(qᵢ) dt`.
///
/// ```
/// use kestrel_models::RandomWalk;
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::{Matrix2, Vector2}};
/// let rw = RandomWalk::new(Vector2::new(0.5, 2.0)).unwrap();
/// let x = Vector2::new(3.0, -1.0);
/// assert_eq!(rw.propagate(&x, 4.0), x);
/// assert_eq!(rw.noise(&x, 4.0), Matrix2::new(2.0, 0.0, 0.0, 8.0));
/// assert_eq!(rw.transition(&x, 4.0), Matrix2::identity());
/// assert_eq!(RandomWalk::<f64, 2>::uniform(0.5).unwrap().densities, Vector2::new(0.5, 0.5));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RandomWalk<T: Real, const N: usize> {
    /// The spectral densities `qᵢ ≥ 0` [unit²/s], one per state.
    pub densities: SVector<T, N>,
}

impl<T: Real, const N: usize> RandomWalk<T, N> {
    /// Random walks with densities `q` (one per state).
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"q"` unless every density is
    /// finite and `≥ 0`.
    pub fn new(q: SVector<T, N>) -> Result<Self, FilterError> {
        if !q.iter().all(|v| v.is_finite() && *v >= T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "q",
                valid: "finite and at least 0 for every state",
            });
        }
        Ok(Self { densities: q })
    }

    /// The same density `q` for every state (the same errors as
    /// [`new`](Self::new)).
    pub fn uniform(q: T) -> Result<Self, FilterError> {
        Self::new(SVector::repeat(q))
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for RandomWalk<T, N> {
    fn propagate(&self, x: &SVector<T, N>, _dt: T) -> SVector<T, N> {
        *x
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        SMatrix::from_diagonal(&(self.densities * dt))
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for RandomWalk<T, N> {
    fn transition(&self, _x: &SVector<T, N>, _dt: T) -> SMatrix<T, N, N> {
        SMatrix::identity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix3, Vector3};

    #[test]
    fn hand_computed() {
        let rw = RandomWalk::new(Vector3::new(1.0, 0.0, 4.0)).unwrap();
        let q = rw.noise(&Vector3::zeros(), 0.25);
        assert_eq!(q, Matrix3::from_diagonal(&Vector3::new(0.25, 0.0, 1.0)));
        assert_eq!(rw.noise(&Vector3::zeros(), 0.0), Matrix3::zeros());
    }

    #[test]
    fn matches_van_loan() {
        let rw = RandomWalk::new(Vector3::new(1.0, 3.0, 4.0)).unwrap();
        let (phi, q) = crate::van_loan(
            &Matrix3::zeros(),
            &Matrix3::identity(),
            &Matrix3::from_diagonal(&rw.densities),
            0.6,
        );
        assert_eq!(phi, rw.transition(&Vector3::zeros(), 0.6));
        assert!((q - rw.noise(&Vector3::zeros(), 0.6)).norm() < 1e-15);
    }
}
