//! Degrees in text, radians inside: conversions that survive a round trip.

use core::fmt;

use kestrel_nav::Geodetic;

/// Radians from degrees, the one conversion every reader uses.
///
/// ```
/// assert_eq!(kestrel_io::gins::degrees_to_radians(180.0), std::f64::consts::PI);
/// ```
pub fn degrees_to_radians(deg: f64) -> f64 {
    deg.to_radians()
}

/// Degrees for `rad` that [`degrees_to_radians`] maps back to exactly
/// `rad`: the nearest degrees first, then its neighbours a few units in the
/// last place away (`x.to_degrees().to_radians()` is not always `x`).
/// Falls back to the nearest degrees if none does: about one double in ten
/// is not the image of any double in degrees, and comes back within one
/// unit in the last place.
///
/// ```
/// use kestrel_io::gins::{degrees_exact, degrees_to_radians};
/// for deg in [30.531_234_567_891_23_f64, 114.0, -0.3] {
///     let rad = degrees_to_radians(deg) * (1.0 + f64::EPSILON);
///     let back = degrees_to_radians(degrees_exact(rad));
///     assert!((back - rad).abs() <= f64::EPSILON * rad.abs());
/// }
/// let rad = degrees_to_radians(30.5);
/// assert_eq!(degrees_to_radians(degrees_exact(rad)), rad);
/// ```
pub fn degrees_exact(rad: f64) -> f64 {
    invert_exact(rad, rad.to_degrees(), degrees_to_radians)
}

/// A value `x` near `approx` with `forward(x) == target` exactly, searched
/// among `approx` and its neighbours up to 8 units in the last place away;
/// `approx` if none is. Writers use it to print a quantity in display units
/// that the reader's conversion `forward` maps back to the same bits.
///
/// ```
/// use kestrel_io::gins::invert_exact;
/// let to_si = |ug: f64| ug * 1e-6 * 9.80665;
/// let si = to_si(50.0) * 1.000000000000001;
/// let ug = invert_exact(si, si / (1e-6 * 9.80665), to_si);
/// assert_eq!(to_si(ug), si);
/// ```
pub fn invert_exact(target: f64, approx: f64, forward: impl Fn(f64) -> f64) -> f64 {
    if !approx.is_finite() || forward(approx) == target {
        return approx;
    }
    let (mut up, mut down) = (approx, approx);
    for _ in 0..8 {
        up = up.next_up();
        down = down.next_down();
        for x in [up, down] {
            if forward(x) == target {
                return x;
            }
        }
    }
    approx
}

/// The three position columns `lat lon h` of the GNSS and navigation
/// formats: degrees by [`degrees_exact`], metres.
pub(crate) struct PositionColumns<'a>(pub &'a Geodetic);

impl fmt::Display for PositionColumns<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.0;
        write!(
            f,
            "{} {} {}",
            degrees_exact(p.lat),
            degrees_exact(p.lon),
            p.h
        )
    }
}
