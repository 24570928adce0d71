use nalgebra::{SMatrix, SVector};

use crate::Real;

/// What an `M`-dimensional sensor measures of an `N`-dimensional state.
///
/// ```
/// use kestrel_core::{MeasurementModel, nalgebra::{SMatrix, SVector, Vector1, Vector2}};
///
/// /// Observes the first state component with variance `r`.
/// struct First { r: f64 }
///
/// impl MeasurementModel<f64, 2, 1> for First {
///     fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> { Vector1::new(x[0]) }
///     fn noise(&self) -> SMatrix<f64, 1, 1> { SMatrix::from_element(self.r) }
/// }
/// let z = First { r: 1.0 }.predict(&Vector2::new(3.0, 4.0));
/// assert_eq!(z[0], 3.0);
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a model of {M}-dimensional measurements of a {N}-state filter",
    label = "not a MeasurementModel<{T}, {N}, {M}>",
    note = "the measurement size M of `update` must agree between `z`, the model and the filter's noise adapter, which may fix it",
    note = "to update with a sensor whose size differs from the adapter's, call `update_with(&model, &z, &mut adapter)` (`&mut ()` for no adapter)"
)]
pub trait MeasurementModel<T: Real, const N: usize, const M: usize> {
    /// The predicted measurement `ẑ = h(x)`. The unscented forms call it
    /// once per sigma point; see [`ProcessModel::propagate`] on inlining.
    ///
    /// [`ProcessModel::propagate`]: crate::ProcessModel::propagate
    fn predict(&self, x: &SVector<T, N>) -> SVector<T, M>;

    /// The measurement noise covariance `R` (symmetric positive definite).
    fn noise(&self) -> SMatrix<T, M, M>;

    /// The innovation `z ⊟ ẑ`. Override it for components that wrap, such as
    /// a bearing, so the difference of 359° and 1° is −2°, not 358°.
    /// Unscented forms also average predicted measurements through it.
    #[inline]
    fn residual(&self, z: &SVector<T, M>, predicted: &SVector<T, M>) -> SVector<T, M> {
        z - predicted
    }
}

/// A measurement model with a Jacobian `H = ∂h/∂x`, required by the
/// covariance (KF / EKF) form.
///
/// ```
/// use kestrel_core::{LinearizedMeasurement, MeasurementModel,
///     nalgebra::{SMatrix, Vector1, Vector2, RowVector2}};
///
/// struct Sum;
/// impl MeasurementModel<f64, 2, 1> for Sum {
///     fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> { Vector1::new(x[0] + x[1]) }
///     fn noise(&self) -> SMatrix<f64, 1, 1> { SMatrix::identity() }
/// }
/// impl LinearizedMeasurement<f64, 2, 1> for Sum {
///     fn jacobian(&self, _x: &Vector2<f64>) -> SMatrix<f64, 1, 2> { RowVector2::new(1.0, 1.0) }
/// }
/// assert_eq!(Sum.jacobian(&Vector2::zeros()).sum(), 2.0);
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a linearised model of {M}-dimensional measurements of a {N}-state filter",
    label = "not a LinearizedMeasurement<{T}, {N}, {M}>",
    note = "the measurement size M of `update` must agree between `z`, the model and the filter's noise adapter, which may fix it; for a sensor of another size than the adapter's, call `update_with(&model, &z, &mut adapter)` (`&mut ()` for no adapter)",
    note = "the covariance form (`Ekf`) needs `H = ∂h/∂x`: implement `LinearizedMeasurement`, derive it with `kestrel::models::AutoJacobian`, or use `Ukf` / `SrUkf`"
)]
pub trait LinearizedMeasurement<T: Real, const N: usize, const M: usize>:
    MeasurementModel<T, N, M>
{
    /// The Jacobian `H = ∂h/∂x` evaluated at `x`.
    fn jacobian(&self, x: &SVector<T, N>) -> SMatrix<T, M, N>;
}
