//! Jacobians by forward-mode automatic differentiation, for models written
//! generically over the scalar (dual numbers from the `num-dual` crate).

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{
    LinearizedMeasurement, LinearizedProcess, MeasurementModel, ProcessModel, Real,
};
use num_dual::{jacobian, DualSVec};

/// A scalar whose models can be differentiated automatically: `f32` and
/// `f64`, each with the dual number type that carries `N` partial
/// derivatives alongside the value.
pub trait AutoDiffScalar: Real {
    /// The dual number with `N` derivative components.
    type Dual<const N: usize>: Real;

    /// `f(x)` and its Jacobian `∂f/∂x`, exact to rounding.
    fn jacobian<const N: usize, const K: usize>(
        f: impl Fn(&SVector<Self::Dual<N>, N>) -> SVector<Self::Dual<N>, K>,
        x: &SVector<Self, N>,
    ) -> (SVector<Self, K>, SMatrix<Self, K, N>);

    /// The constant `v` as a dual number (zero derivative).
    fn constant<const N: usize>(v: Self) -> Self::Dual<N>;
}

macro_rules! auto_diff_scalar {
    ($t:ty) => {
        impl AutoDiffScalar for $t {
            type Dual<const N: usize> = DualSVec<$t, N>;

            fn jacobian<const N: usize, const K: usize>(
                f: impl Fn(&SVector<Self::Dual<N>, N>) -> SVector<Self::Dual<N>, K>,
                x: &SVector<Self, N>,
            ) -> (SVector<Self, K>, SMatrix<Self, K, N>) {
                jacobian(|xd: SVector<Self::Dual<N>, N>| f(&xd), x)
            }

            fn constant<const N: usize>(v: Self) -> Self::Dual<N> {
                DualSVec::from_re(v)
            }
        }
    };
}
auto_diff_scalar!(f32);
auto_diff_scalar!(f64);

/// Gives a model written generically over the scalar its Jacobian by
/// automatic differentiation, so the covariance form (`Ekf`) can use it
/// without a hand-derived `H` or `Φ`. The model must implement
/// [`MeasurementModel`] (or [`ProcessModel`]) for every [`Real`] `T`, which
/// is what writing `impl<T: Real> MeasurementModel<T, N, M> for MyModel`
/// with parameters converted by [`lit`](kestrel_core::real::lit) gives.
///
/// The Jacobian is exact to rounding (no step size), costs about `N` times
/// one evaluation of the model, and allocates nothing.
///
/// ```
/// use kestrel_core::{Ekf, MeasurementModel, LinearizedMeasurement, Real, real::lit,
///     nalgebra::{Matrix1, Matrix2, Vector1, Vector2}};
/// use kestrel_models::AutoJacobian;
///
/// /// Distance from a beacon at (bx, by).
/// struct Range { bx: f64, by: f64 }
/// impl<T: Real> MeasurementModel<T, 2, 1> for Range {
///     fn predict(&self, x: &Vector2<T>) -> Vector1<T> {
///         let (dx, dy) = (x[0] - lit(self.bx), x[1] - lit(self.by));
///         Vector1::new((dx * dx + dy * dy).sqrt())
///     }
///     fn noise(&self) -> Matrix1<T> { Matrix1::new(lit(0.01)) }
/// }
///
/// let range = AutoJacobian(Range { bx: 0.0, by: 0.0 });
/// let h = range.jacobian(&Vector2::new(3.0_f64, 4.0));
/// assert!((h[(0, 0)] - 0.6).abs() < 1e-15 && (h[(0, 1)] - 0.8).abs() < 1e-15);
/// let mut ekf = Ekf::new(Vector2::new(3.0, 4.0), Matrix2::identity()).unwrap();
/// ekf.update(&range, &Vector1::new(5.5)).unwrap();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AutoJacobian<M>(pub M);

impl<T: Real, M: MeasurementModel<T, N, K>, const N: usize, const K: usize>
    MeasurementModel<T, N, K> for AutoJacobian<M>
{
    fn predict(&self, x: &SVector<T, N>) -> SVector<T, K> {
        self.0.predict(x)
    }
    fn noise(&self) -> SMatrix<T, K, K> {
        self.0.noise()
    }
    fn residual(&self, z: &SVector<T, K>, predicted: &SVector<T, K>) -> SVector<T, K> {
        self.0.residual(z, predicted)
    }
}

impl<T, M, const N: usize, const K: usize> LinearizedMeasurement<T, N, K> for AutoJacobian<M>
where
    T: AutoDiffScalar,
    M: MeasurementModel<T, N, K> + MeasurementModel<T::Dual<N>, N, K>,
{
    fn jacobian(&self, x: &SVector<T, N>) -> SMatrix<T, K, N> {
        T::jacobian(
            |xd| MeasurementModel::<T::Dual<N>, N, K>::predict(&self.0, xd),
            x,
        )
        .1
    }
}

impl<T: Real, M: ProcessModel<T, N>, const N: usize> ProcessModel<T, N> for AutoJacobian<M> {
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        self.0.propagate(x, dt)
    }
    fn noise(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        self.0.noise(x, dt)
    }
}

impl<T, M, const N: usize> LinearizedProcess<T, N> for AutoJacobian<M>
where
    T: AutoDiffScalar,
    M: ProcessModel<T, N> + ProcessModel<T::Dual<N>, N>,
{
    fn transition(&self, x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let dt = T::constant::<N>(dt);
        T::jacobian(
            |xd| ProcessModel::<T::Dual<N>, N>::propagate(&self.0, xd, dt),
            x,
        )
        .1
    }
}
