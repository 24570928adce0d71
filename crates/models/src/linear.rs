//! Linear time-invariant models given directly by their matrices.

use kestrel_core::linalg::mul_vector;
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{
    LinearizedMeasurement, LinearizedProcess, MeasurementModel, ProcessModel, Real,
};

/// `x⁻ = Φ x` with discrete process noise `Q`, independent of the time step
/// (the matrices are for the filter's fixed step).
///
/// ```
/// use kestrel_models::LinearProcess;
/// use kestrel_core::{ProcessModel, nalgebra::{Matrix2, Vector2}};
/// let m = LinearProcess::new(Matrix2::new(1.0, 1.0, 0.0, 1.0), Matrix2::identity() * 0.1);
/// assert_eq!(m.propagate(&Vector2::new(1.0, 2.0), 1.0), Vector2::new(3.0, 2.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearProcess<T: Real, const N: usize> {
    /// The transition matrix `Φ`.
    pub transition: SMatrix<T, N, N>,
    /// The discrete process noise covariance `Q`.
    pub noise: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> LinearProcess<T, N> {
    /// The model `x⁻ = Φ x`, noise `Q`.
    pub fn new(transition: SMatrix<T, N, N>, noise: SMatrix<T, N, N>) -> Self {
        Self { transition, noise }
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for LinearProcess<T, N> {
    // Always inlined, like the product itself: the unscented forms call it
    // once per sigma point, and a call there cost a tenth of their step.
    #[inline(always)]
    fn propagate(&self, x: &SVector<T, N>, _dt: T) -> SVector<T, N> {
        mul_vector(&self.transition, x)
    }
    fn noise(&self, _x: &SVector<T, N>, _dt: T) -> SMatrix<T, N, N> {
        self.noise
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for LinearProcess<T, N> {
    fn transition(&self, _x: &SVector<T, N>, _dt: T) -> SMatrix<T, N, N> {
        self.transition
    }
}

/// `z = H x + v`, `v ~ N(0, R)`.
///
/// ```
/// use kestrel_models::LinearMeasurement;
/// use kestrel_core::{MeasurementModel, nalgebra::{Matrix1, Matrix1x2, Vector2}};
/// let m = LinearMeasurement::new(Matrix1x2::new(1.0, -1.0), Matrix1::new(0.5));
/// assert_eq!(m.predict(&Vector2::new(3.0, 1.0))[0], 2.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMeasurement<T: Real, const N: usize, const M: usize> {
    /// The measurement matrix `H`.
    pub matrix: SMatrix<T, M, N>,
    /// The measurement noise covariance `R`.
    pub noise: SMatrix<T, M, M>,
}

impl<T: Real, const N: usize, const M: usize> LinearMeasurement<T, N, M> {
    /// The model `z = H x`, noise `R`.
    pub fn new(matrix: SMatrix<T, M, N>, noise: SMatrix<T, M, M>) -> Self {
        Self { matrix, noise }
    }
}

impl<T: Real, const N: usize, const M: usize> MeasurementModel<T, N, M>
    for LinearMeasurement<T, N, M>
{
    // Always inlined, as `LinearProcess::propagate` is.
    #[inline(always)]
    fn predict(&self, x: &SVector<T, N>) -> SVector<T, M> {
        mul_vector(&self.matrix, x)
    }
    fn noise(&self) -> SMatrix<T, M, M> {
        self.noise
    }
}

impl<T: Real, const N: usize, const M: usize> LinearizedMeasurement<T, N, M>
    for LinearMeasurement<T, N, M>
{
    fn jacobian(&self, _x: &SVector<T, N>) -> SMatrix<T, M, N> {
        self.matrix
    }
}
