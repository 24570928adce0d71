use nalgebra::{SMatrix, SVector};

use crate::Real;

/// How an `N`-dimensional state evolves over a time step.
///
/// A model value is passed to every `predict` call, so control inputs and
/// time-varying parameters (an IMU reading, the current navigation solution)
/// live in the model value itself.
///
/// ```
/// use kestrel_core::{ProcessModel, nalgebra::{SMatrix, SVector}};
///
/// /// A scalar random walk with noise density `q` [unit²/s].
/// struct Drift { q: f64 }
///
/// impl ProcessModel<f64, 1> for Drift {
///     fn propagate(&self, x: &SVector<f64, 1>, _dt: f64) -> SVector<f64, 1> { *x }
///     fn noise(&self, _x: &SVector<f64, 1>, dt: f64) -> SMatrix<f64, 1, 1> {
///         SMatrix::from_element(self.q * dt)
///     }
/// }
/// assert_eq!(Drift { q: 2.0 }.noise(&SVector::zeros(), 0.5)[0], 1.0);
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a process model of a {N}-state filter over `{T}`",
    label = "not a ProcessModel<{T}, {N}>",
    note = "the model's state size and scalar must be the filter's"
)]
pub trait ProcessModel<T: Real, const N: usize> {
    /// Propagates the state over `dt` seconds: `x⁻ = f(x, dt)`.
    ///
    /// The unscented forms call it once per sigma point, `2N + 1` times a
    /// step. A small model is fastest inlined there, which the compiler does
    /// not always choose on its own: the library's linear models and
    /// [`mul_vector`](crate::linalg::mul_vector) are `#[inline(always)]`, so
    /// that no build calls them out of line once per sigma point.
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N>;

    /// The discrete process noise covariance added over `dt` seconds, in state
    /// space: `Q_d = Γ Q_w Γᵀ` when the noise enters through a gain `Γ`.
    /// `x` is the state before propagation. Must be symmetric positive
    /// semi-definite.
    fn noise(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N>;
}

/// A process model with a state-transition matrix, required by the
/// covariance (KF / EKF) form.
///
/// ```
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::{SMatrix, SVector}};
///
/// struct Decay;
/// impl ProcessModel<f64, 1> for Decay {
///     fn propagate(&self, x: &SVector<f64, 1>, dt: f64) -> SVector<f64, 1> { x * (-dt).exp() }
///     fn noise(&self, _x: &SVector<f64, 1>, _dt: f64) -> SMatrix<f64, 1, 1> { SMatrix::zeros() }
/// }
/// impl LinearizedProcess<f64, 1> for Decay {
///     fn transition(&self, _x: &SVector<f64, 1>, dt: f64) -> SMatrix<f64, 1, 1> {
///         SMatrix::from_element((-dt).exp())
///     }
/// }
/// assert!((Decay.transition(&SVector::zeros(), 1.0)[0] - 0.367879).abs() < 1e-6);
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no transition matrix for a {N}-state filter over `{T}`",
    label = "not a LinearizedProcess<{T}, {N}>",
    note = "the covariance form (`Ekf`) needs `Φ = ∂f/∂x`: implement `LinearizedProcess`, derive it with `kestrel::models::AutoJacobian`, or use `Ukf` / `SrUkf`"
)]
pub trait LinearizedProcess<T: Real, const N: usize>: ProcessModel<T, N> {
    /// The state-transition matrix `Φ = ∂f/∂x` evaluated at `x` (the state
    /// before propagation) over `dt` seconds.
    fn transition(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N>;
}
