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

/// Whether `v` is finite, tested as `v − v = 0`: the difference is exactly
/// 0 for every finite `v` (subnormals included), and NaN for `±∞` and NaN,
/// which equals nothing. Two float operations that stay in the vector
/// registers, and over an array vectorise without a branch per element,
/// where `is_finite` moves each value to an integer register to test its
/// bits.
#[inline(always)]
// `v − v` is the test, not a slip.
#[allow(clippy::eq_op)]
pub(crate) fn finite<T: Real>(v: T) -> bool {
    v - v == T::zero()
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

#[cfg(test)]
mod tests {
    use super::finite;
    use proptest::prelude::*;

    #[test]
    fn finite_agrees_with_is_finite_on_the_special_values() {
        for v in [
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            5.0e-324,
            -5.0e-324,
            f64::MAX,
            f64::MIN,
            1.0,
        ] {
            assert!(finite(v), "{v}");
        }
        for v in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, -f64::NAN] {
            assert!(!finite(v), "{v}");
        }
        for v in [f32::MAX, f32::MIN, 1.0e-45, -0.0] {
            assert!(finite(v), "{v}");
        }
        for v in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN] {
            assert!(!finite(v), "{v}");
        }
    }

    proptest! {
        /// Any bit pattern, half of them with the exponent all ones (both
        /// infinities and NaN with any payload and sign).
        #[test]
        fn finite_is_is_finite_for_every_f64(bits in prop_oneof![
            any::<u64>(),
            any::<u64>().prop_map(|b| b | 0x7ff0_0000_0000_0000),
        ]) {
            let v = f64::from_bits(bits);
            prop_assert_eq!(finite(v), v.is_finite());
        }

        #[test]
        fn finite_is_is_finite_for_every_f32(bits in prop_oneof![
            any::<u32>(),
            any::<u32>().prop_map(|b| b | 0x7f80_0000),
        ]) {
            let v = f32::from_bits(bits);
            prop_assert_eq!(finite(v), v.is_finite());
        }
    }
}
