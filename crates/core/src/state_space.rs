//! State addition and difference for states that are not plain vectors.

use nalgebra::SVector;

use crate::Real;

/// The arithmetic of an `N`-dimensional state: `x ⊞ δ` and `a ⊟ b`.
///
/// Filters use it wherever a state is moved by a correction (the update
/// `x⁺ = x⁻ ⊞ Kν`, sigma points `x ⊞ ηSᵢ`) or two states are compared
/// (sigma-point deviations). Unscented means are taken around the central
/// sigma point as `χ₀ ⊞ Σ Wᵢ (χᵢ ⊟ χ₀)`, so a wrapped angle averages
/// correctly. For vector states use [`Euclidean`].
///
/// ```
/// use kestrel_core::{StateSpace, nalgebra::Vector1};
/// use core::f64::consts::PI;
///
/// /// A heading in radians, kept in (−π, π].
/// struct Heading;
/// impl StateSpace<f64, 1> for Heading {
///     fn add(&self, x: &Vector1<f64>, dx: &Vector1<f64>) -> Vector1<f64> {
///         Vector1::new(wrap(x[0] + dx[0]))
///     }
///     fn difference(&self, a: &Vector1<f64>, b: &Vector1<f64>) -> Vector1<f64> {
///         Vector1::new(wrap(a[0] - b[0]))
///     }
/// }
/// fn wrap(a: f64) -> f64 { (a + PI).rem_euclid(2.0 * PI) - PI }
///
/// let d = Heading.difference(&Vector1::new(-3.1), &Vector1::new(3.1));
/// assert!((d[0] - (2.0 * PI - 6.2)).abs() < 1e-12);
/// ```
pub trait StateSpace<T: Real, const N: usize> {
    /// `x ⊞ dx`: the state `x` moved by the correction `dx`.
    fn add(&self, x: &SVector<T, N>, dx: &SVector<T, N>) -> SVector<T, N>;
    /// `a ⊟ b`: the correction that moves `b` to `a`.
    fn difference(&self, a: &SVector<T, N>, b: &SVector<T, N>) -> SVector<T, N>;
}

/// Ordinary vector arithmetic: `x ⊞ dx = x + dx`, `a ⊟ b = a − b`.
///
/// ```
/// use kestrel_core::{Euclidean, StateSpace, nalgebra::Vector2};
/// let s = Euclidean.add(&Vector2::new(1.0, 2.0), &Vector2::new(0.5, 0.5));
/// assert_eq!(s, Vector2::new(1.5, 2.5));
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Euclidean;

impl<T: Real, const N: usize> StateSpace<T, N> for Euclidean {
    #[inline(always)]
    fn add(&self, x: &SVector<T, N>, dx: &SVector<T, N>) -> SVector<T, N> {
        x + dx
    }
    #[inline(always)]
    fn difference(&self, a: &SVector<T, N>, b: &SVector<T, N>) -> SVector<T, N> {
        a - b
    }
}
