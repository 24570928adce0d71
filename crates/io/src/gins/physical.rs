//! The physical ranges every input is checked against — the same limits in
//! the readers and the configuration, so a value one accepts the other
//! accepts too.
//!
//! The limits are wide enough for any land, sea or air vehicle an INS
//! navigates and narrow enough to catch a value in the wrong unit or
//! column (a longitude in radians × 1e6, a speed in mm/s, a height in
//! feet × 1000).

/// Latitude, deg.
pub const LATITUDE: (f64, f64) = (-90.0, 90.0);
/// Longitude, deg: east-positive, either from −180 to 180 or 0 to 360.
pub const LONGITUDE: (f64, f64) = (-180.0, 360.0);
/// Ellipsoidal height, m: below the deepest ocean floor (−10 935 m, plus
/// the geoid's ±110 m) to the edge of space (100 km).
pub const HEIGHT: (f64, f64) = (-12_000.0, 100_000.0);
/// A speed (each velocity component, the odometer's speed), m/s: about
/// three times the speed of sound; beyond it the value is taken to be in
/// the wrong unit.
pub const SPEED: f64 = 1_000.0;
/// The smallest and largest standard deviation whose square (the variance
/// the filter uses) is a normal, finite double.
pub const SIGMA: (f64, f64) = (1.0e-150, 1.0e150);

/// Why `x` is outside `[lo, hi]`, or `None` when inside.
///
/// ```
/// use kestrel_io::gins::physical::{outside, HEIGHT};
/// assert_eq!(outside("a height", "m", -1e7, HEIGHT).unwrap(),
///     "expected a height in [-12000, 100000] m, found -10000000");
/// assert!(outside("a height", "m", 25.0, HEIGHT).is_none());
/// assert!(outside("a height", "m", f64::NAN, HEIGHT).is_some());
/// ```
pub fn outside(what: &str, unit: &str, x: f64, (lo, hi): (f64, f64)) -> Option<String> {
    if x >= lo && x <= hi {
        None
    } else {
        Some(format!(
            "expected {what} in [{lo}, {hi}] {unit}, found {}",
            show(x)
        ))
    }
}

/// Why `sigma` cannot be a standard deviation (zero, negative, non-finite,
/// or a square that underflows to 0 or overflows to ∞), or `None`.
///
/// ```
/// use kestrel_io::gins::physical::bad_sigma;
/// assert!(bad_sigma(0.5).is_none());
/// assert_eq!(bad_sigma(1e-200).unwrap(),
///     "expected a standard deviation in [1e-150, 1e150] (its square must be a normal \
///      double), found 1e-200");
/// assert!(bad_sigma(0.0).is_some() && bad_sigma(-1.0).is_some());
/// ```
pub fn bad_sigma(sigma: f64) -> Option<String> {
    let (lo, hi) = SIGMA;
    if sigma >= lo && sigma <= hi {
        None
    } else {
        Some(format!(
            "expected a standard deviation in [{lo:e}, {hi:e}] (its square must be a normal \
             double), found {}",
            show(sigma)
        ))
    }
}

/// `x` as people read it in a message: plain decimals from 1e-4 to 1e16,
/// otherwise scientific notation (never 200 zeros).
///
/// ```
/// use kestrel_io::gins::physical::show;
/// assert_eq!(show(1e-200), "1e-200");
/// assert_eq!(show(1e308), "1e308");
/// assert_eq!(show(-3000.0), "-3000");
/// assert_eq!(show(0.5), "0.5");
/// assert_eq!(show(f64::NAN), "NaN");
/// ```
pub fn show(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}
