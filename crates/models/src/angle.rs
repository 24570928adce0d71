//! Angle arithmetic.

use kestrel_core::Real;

/// Wraps an angle in radians to `(−π, π]`. Non-finite input gives NaN.
///
/// ```
/// use kestrel_models::wrap_angle;
/// use core::f64::consts::PI;
/// assert!((wrap_angle(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
/// assert_eq!(wrap_angle(-PI), PI);
/// assert_eq!(wrap_angle(PI), PI);
/// assert_eq!(wrap_angle(0.5_f32), 0.5);
/// ```
pub fn wrap_angle<T: Real>(angle: T) -> T {
    let (pi, two_pi) = (T::pi(), T::two_pi());
    // The k with angle − 2πk in (−π, π], exactly; rounding can leave the
    // result a hair outside, which the two corrections fold back.
    let mut w = angle - two_pi * ((angle - pi) / two_pi).ceil();
    if w > pi {
        w -= two_pi;
    } else if w <= -pi {
        w += two_pi;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    #[test]
    fn wraps_into_half_open_interval() {
        for (a, want) in [
            (0.0, 0.0),
            (PI / 3.0, PI / 3.0),
            (-PI / 3.0, -PI / 3.0),
            (2.0 * PI + 0.25, 0.25),
            (-2.0 * PI - 0.25, -0.25),
            (3.0 * PI, PI),
            (-3.0 * PI, PI),
            (7.0 * PI - 0.5, PI - 0.5),
        ] {
            let w = wrap_angle(a);
            assert!((w - want).abs() < 1e-14, "{a}: {w}");
        }
        for k in -200..=200 {
            let w = wrap_angle(k as f64 * 0.37 + PI);
            assert!(w > -PI && w <= PI, "{w}");
            let w = wrap_angle(k as f32 * 0.37 + core::f32::consts::PI);
            assert!(
                w > -core::f32::consts::PI && w <= core::f32::consts::PI,
                "{w}"
            );
        }
        assert!(wrap_angle(f64::NAN).is_nan());
        assert!(wrap_angle(f64::INFINITY).is_nan());
    }
}
