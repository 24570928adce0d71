//! The constant-velocity (white-noise acceleration) kinematic model.

use kestrel_core::nalgebra::{Matrix2, SMatrix, SVector};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

use crate::axes::{apply_per_axis, block_diagonal, Densities};
use crate::sizes::{Size, VelocityAxes};

/// Constant velocity in 1 to 3 axes, driven by continuous white acceleration
/// noise of spectral density `q` [unit²/s³] per axis (the nearly constant
/// velocity model).
///
/// The state is interleaved per axis: `[p₁, v₁, p₂, v₂, …]`, so `N` is 2, 4
/// or 6; any other `N` is a type error that `cargo check` reports
/// ([`VelocityAxes`](crate::VelocityAxes)). For each
/// axis, over `dt`:
///
/// `Φ = [[1, dt], [0, 1]]`, `Q = q [[dt³/3, dt²/2], [dt²/2, dt]]`.
///
/// ```
/// use kestrel_models::{ConstantVelocity2d};
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::Vector4};
/// let cv = ConstantVelocity2d::per_axis(&[2.0, 0.5]).unwrap();
/// // x = [pₓ, vₓ, p_y, v_y]
/// let x = Vector4::new(1.0, 2.0, 0.0, -1.0);
/// assert_eq!(cv.propagate(&x, 0.5), Vector4::new(2.0, 2.0, -0.5, -1.0));
/// let q = cv.noise(&x, 1.0);
/// assert_eq!((q[(0, 0)], q[(0, 1)], q[(1, 1)]), (2.0 / 3.0, 1.0, 2.0));
/// assert_eq!((q[(2, 3)], q[(0, 2)]), (0.25, 0.0));
/// assert_eq!(cv.transition(&x, 0.5)[(2, 3)], 0.5);
/// assert_eq!(cv.densities(), &[2.0, 0.5]);
/// ```
///
/// An odd state size does not build:
///
/// ```compile_fail,E0277
/// use kestrel_models::ConstantVelocity;
/// let cv = ConstantVelocity::<f64, 3>::new(1.0).unwrap();
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantVelocity<T: Real, const N: usize>
where
    Size<N>: VelocityAxes,
{
    q: Densities<T>,
}

/// Constant velocity along one axis: `[p, v]`.
pub type ConstantVelocity1d<T> = ConstantVelocity<T, 2>;
/// Constant velocity in the plane: `[pₓ, vₓ, p_y, v_y]`.
pub type ConstantVelocity2d<T> = ConstantVelocity<T, 4>;
/// Constant velocity in space: `[pₓ, vₓ, p_y, v_y, p_z, v_z]`.
pub type ConstantVelocity3d<T> = ConstantVelocity<T, 6>;

/// The number of axes.
const fn axes<const N: usize>() -> usize {
    N / 2
}

impl<T: Real, const N: usize> ConstantVelocity<T, N>
where
    Size<N>: VelocityAxes,
{
    /// The same acceleration density `q ≥ 0` [unit²/s³] on every axis.
    pub fn new(q: T) -> Result<Self, FilterError> {
        Ok(Self {
            q: Densities::uniform(q, axes::<N>())?,
        })
    }

    /// One density per axis.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"q"` unless `q` has `N / 2`
    /// entries, each finite and `≥ 0`.
    pub fn per_axis(q: &[T]) -> Result<Self, FilterError> {
        Ok(Self {
            q: Densities::per_axis(q, axes::<N>())?,
        })
    }

    /// The acceleration densities, one per axis.
    pub fn densities(&self) -> &[T] {
        self.q.as_slice()
    }

    fn axis_transition(dt: T) -> Matrix2<T> {
        Matrix2::new(T::one(), dt, T::zero(), T::one())
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for ConstantVelocity<T, N>
where
    Size<N>: VelocityAxes,
{
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        apply_per_axis(&Self::axis_transition(dt), x)
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let (d2, d3) = (dt * dt * lit(0.5), dt * dt * dt / lit(3.0));
        let unit = Matrix2::new(d3, d2, d2, dt);
        block_diagonal::<T, N, 2>(|axis| unit * self.q.get(axis))
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for ConstantVelocity<T, N>
where
    Size<N>: VelocityAxes,
{
    fn transition(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        block_diagonal::<T, N, 2>(|_| Self::axis_transition(dt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix6, Vector2, Vector6};

    #[test]
    fn one_axis_hand_computed() {
        let cv = ConstantVelocity1d::new(0.3).unwrap();
        let x = Vector2::new(10.0, -2.0);
        assert_eq!(cv.propagate(&x, 2.0), Vector2::new(6.0, -2.0));
        // dt = 2: q [[8/3, 2], [2, 2]]
        let q = cv.noise(&x, 2.0);
        assert!((q - Matrix2::new(0.8, 0.6, 0.6, 0.6)).norm() < 1e-15, "{q}");
        assert_eq!(cv.transition(&x, 2.0), Matrix2::new(1.0, 2.0, 0.0, 1.0));
    }

    #[test]
    fn three_axes_layout() {
        let cv = ConstantVelocity3d::per_axis(&[1.0, 2.0, 4.0]).unwrap();
        let x = Vector6::new(0.0, 1.0, 1.0, 2.0, 2.0, 3.0);
        assert_eq!(
            cv.propagate(&x, 1.0),
            Vector6::new(1.0, 1.0, 3.0, 2.0, 5.0, 3.0)
        );
        let phi = cv.transition(&x, 1.0);
        assert_eq!(phi * x, cv.propagate(&x, 1.0));
        let q = cv.noise(&x, 1.0);
        // Axis i block is q_i [[1/3, 1/2], [1/2, 1]]; nothing couples axes.
        for (axis, qi) in [1.0, 2.0, 4.0].into_iter().enumerate() {
            let b = q.fixed_view::<2, 2>(2 * axis, 2 * axis);
            assert!((b - Matrix2::new(1.0 / 3.0, 0.5, 0.5, 1.0) * qi).norm() < 1e-15);
        }
        let mut off = q;
        for axis in 0..3 {
            off.fixed_view_mut::<2, 2>(2 * axis, 2 * axis).fill(0.0);
        }
        assert_eq!(off, Matrix6::zeros());
        assert_eq!(cv.densities(), &[1.0, 2.0, 4.0]);
    }

    #[test]
    fn per_axis_length_checked() {
        assert!(ConstantVelocity2d::<f64>::per_axis(&[1.0]).is_err());
        assert!(ConstantVelocity2d::<f64>::per_axis(&[1.0, 2.0, 3.0]).is_err());
        assert_eq!(
            ConstantVelocity2d::new(1.5).unwrap().densities(),
            &[1.5, 1.5]
        );
    }

    #[test]
    fn matches_van_loan() {
        let cv = ConstantVelocity1d::new(0.7).unwrap();
        let f = Matrix2::new(0.0, 1.0, 0.0, 0.0);
        let g = Vector2::new(0.0, 1.0);
        let (_, want) = crate::van_loan(&f, &g, &kestrel_core::nalgebra::Matrix1::new(0.7), 3.0);
        assert!((cv.noise(&Vector2::zeros(), 3.0) - want).norm() < 1e-12 * want.norm());
    }
}
