//! The constant-acceleration (white-noise jerk) kinematic model.

use kestrel_core::nalgebra::{Matrix3, SMatrix, SVector};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

use crate::axes::{apply_per_axis, block_diagonal, Densities};
use crate::sizes::{AccelerationAxes, Size};

/// Constant acceleration in 1 to 3 axes, driven by continuous white jerk
/// noise of spectral density `q` [unit²/s⁵] per axis (the Wiener-process
/// acceleration model).
///
/// The state is interleaved per axis: `[p₁, v₁, a₁, p₂, v₂, a₂, …]`, so `N`
/// is 3, 6 or 9; any other `N` is a type error that `cargo check` reports
/// ([`AccelerationAxes`](crate::AccelerationAxes)).
/// For each axis, over `dt`:
///
/// `Φ = [[1, dt, dt²/2], [0, 1, dt], [0, 0, 1]]`,
/// `Q = q [[dt⁵/20, dt⁴/8, dt³/6], [dt⁴/8, dt³/3, dt²/2], [dt³/6, dt²/2, dt]]`.
///
/// ```
/// use kestrel_models::ConstantAcceleration1d;
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::Vector3};
/// let ca = ConstantAcceleration1d::new(6.0).unwrap();
/// let x = Vector3::new(0.0, 1.0, 2.0);
/// assert_eq!(ca.propagate(&x, 2.0), Vector3::new(6.0, 5.0, 2.0));
/// assert_eq!(ca.transition(&x, 2.0)[(0, 2)], 2.0);
/// let q = ca.noise(&x, 1.0);
/// assert_eq!((q[(0, 2)], q[(1, 2)], q[(2, 2)]), (1.0, 3.0, 6.0));
/// ```
///
/// ```compile_fail,E0277
/// use kestrel_models::ConstantAcceleration;
/// let ca = ConstantAcceleration::<f64, 4>::new(1.0).unwrap();
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantAcceleration<T: Real, const N: usize>
where
    Size<N>: AccelerationAxes,
{
    q: Densities<T>,
}

/// Constant acceleration along one axis: `[p, v, a]`.
pub type ConstantAcceleration1d<T> = ConstantAcceleration<T, 3>;
/// Constant acceleration in the plane: `[pₓ, vₓ, aₓ, p_y, v_y, a_y]`.
pub type ConstantAcceleration2d<T> = ConstantAcceleration<T, 6>;
/// Constant acceleration in space, three `[p, v, a]` blocks.
pub type ConstantAcceleration3d<T> = ConstantAcceleration<T, 9>;

/// The number of axes.
const fn axes<const N: usize>() -> usize {
    N / 3
}

impl<T: Real, const N: usize> ConstantAcceleration<T, N>
where
    Size<N>: AccelerationAxes,
{
    /// The same jerk density `q ≥ 0` [unit²/s⁵] on every axis (refused
    /// unless finite and `≥ 0`).
    pub fn new(q: T) -> Result<Self, FilterError> {
        Ok(Self {
            q: Densities::uniform(q, axes::<N>())?,
        })
    }

    /// One density per axis.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"q"` unless `q` has `N / 3`
    /// entries, each finite and `≥ 0`.
    pub fn per_axis(q: &[T]) -> Result<Self, FilterError> {
        Ok(Self {
            q: Densities::per_axis(q, axes::<N>())?,
        })
    }

    /// The jerk densities, one per axis.
    pub fn densities(&self) -> &[T] {
        self.q.as_slice()
    }

    fn axis_transition(dt: T) -> Matrix3<T> {
        let (o, z) = (T::one(), T::zero());
        Matrix3::new(o, dt, dt * dt * lit(0.5), z, o, dt, z, z, o)
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for ConstantAcceleration<T, N>
where
    Size<N>: AccelerationAxes,
{
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        apply_per_axis(&Self::axis_transition(dt), x)
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let d2 = dt * dt;
        let (d3, d4) = (d2 * dt, d2 * d2);
        let (a, b, c) = (d4 * dt / lit(20.0), d4 / lit(8.0), d3 / lit(6.0));
        let (d, e) = (d3 / lit(3.0), d2 * lit(0.5));
        let unit = Matrix3::new(a, b, c, b, d, e, c, e, dt);
        block_diagonal::<T, N, 3>(|axis| unit * self.q.get(axis))
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for ConstantAcceleration<T, N>
where
    Size<N>: AccelerationAxes,
{
    fn transition(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        block_diagonal::<T, N, 3>(|_| Self::axis_transition(dt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix1, SVector, Vector3, Vector6};

    #[test]
    fn one_axis_hand_computed() {
        let ca = ConstantAcceleration1d::new(2.0).unwrap();
        // dt = 2: q [[32/20, 16/8, 8/6], [2, 8/3, 2], [4/3, 2, 2]] with q = 2.
        #[rustfmt::skip]
        let want = Matrix3::new(
            3.2, 4.0, 8.0 / 3.0,
            4.0, 16.0 / 3.0, 4.0,
            8.0 / 3.0, 4.0, 4.0,
        );
        let q = ca.noise(&Vector3::zeros(), 2.0);
        assert!((q - want).norm() < 1e-14, "{q}");
        let phi = ca.transition(&Vector3::zeros(), 2.0);
        assert_eq!(
            phi,
            Matrix3::new(1.0, 2.0, 2.0, 0.0, 1.0, 2.0, 0.0, 0.0, 1.0)
        );
    }

    #[test]
    fn two_axes_layout() {
        let ca = ConstantAcceleration2d::per_axis(&[1.0, 3.0]).unwrap();
        let x = Vector6::new(1.0, 0.0, 2.0, 0.0, 1.0, -2.0);
        // p = p + v dt + a dt²/2 with dt = 1.
        let want = Vector6::new(2.0, 2.0, 2.0, 0.0, -1.0, -2.0);
        assert_eq!(ca.propagate(&x, 1.0), want);
        assert_eq!(ca.transition(&x, 1.0) * x, want);
        let q = ca.noise(&x, 1.0);
        assert_eq!(q[(3, 5)], 3.0 / 6.0);
        assert_eq!(q[(0, 3)], 0.0);
        assert_eq!(q[(2, 5)], 0.0);
        assert!(ConstantAcceleration2d::<f64>::per_axis(&[1.0]).is_err());
    }

    #[test]
    fn matches_van_loan() {
        let ca = ConstantAcceleration::<f64, 9>::new(0.4).unwrap();
        let f = Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
        let (_, want) = crate::van_loan(&f, &Vector3::new(0.0, 0.0, 1.0), &Matrix1::new(0.4), 1.7);
        let q = ca.noise(&SVector::zeros(), 1.7);
        for axis in 0..3 {
            let block = q.fixed_view::<3, 3>(3 * axis, 3 * axis);
            assert!((block - want).norm() < 1e-12 * want.norm());
        }
    }
}
