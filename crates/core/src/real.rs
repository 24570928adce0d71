//! The scalar type every kestrel filter is generic over.

use nalgebra::RealField;

/// A real scalar usable by every filter: `f32` or `f64` (or any other
/// `Copy` [`RealField`]).
///
/// ```
/// fn half<T: kestrel_core::Real>(v: T) -> T {
///     v * kestrel_core::real::lit(0.5)
/// }
/// assert_eq!(half(3.0_f32), 1.5);
/// assert_eq!(half(3.0_f64), 1.5);
/// ```
pub trait Real: RealField + Copy {}

impl<T: RealField + Copy> Real for T {}

/// Converts an `f64` literal into `T` (rounding to nearest for `f32`).
///
/// ```
/// let x: f32 = kestrel_core::real::lit(0.25);
/// assert_eq!(x, 0.25);
/// ```
#[inline(always)]
pub fn lit<T: Real>(value: f64) -> T {
    nalgebra::convert(value)
}

/// The machine epsilon of `T`.
///
/// ```
/// assert_eq!(kestrel_core::real::epsilon::<f32>(), f32::EPSILON);
/// ```
#[inline(always)]
pub fn epsilon<T: Real>() -> T {
    T::default_epsilon()
}

/// Converts a `T` into `f64` (exact for `f32` and `f64`; NaN for a value a
/// custom scalar cannot express), for printing, statistics and parameters
/// computed in double precision.
///
/// ```
/// assert_eq!(kestrel_core::real::to_f64(0.1_f32), 0.1_f32 as f64);
/// assert_eq!(kestrel_core::real::to_f64(0.1_f64), 0.1);
/// ```
#[inline]
pub fn to_f64<T: Real>(value: T) -> f64 {
    nalgebra::try_convert(value).unwrap_or(f64::NAN)
}
