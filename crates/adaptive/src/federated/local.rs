//! What fusion needs of a local filter: its estimate and a reset.

use kestrel_core::form::Form;
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{Filter, FilterError, Quantity, Real, StateSpace};

/// A local filter of a federated filter: any estimator of the common
/// `N`-state that can give its estimate and be reset to a new one.
///
/// Implemented for every [`Filter`] (covariance form, UKF, SR-UKF, with any
/// adapter and state space), so locals of different forms share one
/// federated filter without dynamic dispatch. The square-root form refactors
/// the reset covariance (its [`Form::set_covariance`] takes the Cholesky
/// factor).
///
/// ```
/// use kestrel_adaptive::federated::LocalFilter;
/// use kestrel_core::{SrUkf, nalgebra::{Matrix2, Vector2}};
/// let mut f = SrUkf::new(Vector2::zeros(), Matrix2::identity()).unwrap();
/// f.reset(&Vector2::new(1.0, 2.0), &Matrix2::new(4.0, 2.0, 2.0, 5.0)).unwrap();
/// assert_eq!(f.form().factor(), Matrix2::new(2.0, 0.0, 1.0, 2.0));
/// assert_eq!(LocalFilter::estimate(&f).0, Vector2::new(1.0, 2.0));
/// ```
pub trait LocalFilter<T: Real, const N: usize> {
    /// The state estimate and its covariance.
    fn estimate(&self) -> (SVector<T, N>, SMatrix<T, N, N>);

    /// `x ⊟ reference` in the local's state arithmetic: the deviation that
    /// enters fusion.
    fn deviation(&self, x: &SVector<T, N>, reference: &SVector<T, N>) -> SVector<T, N>;

    /// `x ⊞ dx` in the local's state arithmetic.
    fn moved(&self, x: &SVector<T, N>, dx: &SVector<T, N>) -> SVector<T, N>;

    /// Replaces the estimate by `x` with covariance `p` (lower triangle
    /// used). On error the filter is unchanged.
    fn reset(&mut self, x: &SVector<T, N>, p: &SMatrix<T, N, N>) -> Result<(), FilterError>;
}

impl<T: Real, const N: usize, F: Form<T, N>, A, S: StateSpace<T, N>> LocalFilter<T, N>
    for Filter<T, N, F, A, S>
{
    fn estimate(&self) -> (SVector<T, N>, SMatrix<T, N, N>) {
        (*self.state(), self.covariance())
    }

    fn deviation(&self, x: &SVector<T, N>, reference: &SVector<T, N>) -> SVector<T, N> {
        self.state_space().difference(x, reference)
    }

    fn moved(&self, x: &SVector<T, N>, dx: &SVector<T, N>) -> SVector<T, N> {
        self.state_space().add(x, dx)
    }

    fn reset(&mut self, x: &SVector<T, N>, p: &SMatrix<T, N, N>) -> Result<(), FilterError> {
        // Check the state first so a refused state cannot leave the new
        // covariance behind.
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(FilterError::NonFinite {
                what: Quantity::UpdatedState,
                row: index,
                col: 0,
            });
        }
        self.set_covariance(p)?;
        self.set_state(*x)
    }
}
