//! The physical ranges every input is checked against — the same limits in
//! the readers and the configuration, so a value one accepts the other
//! accepts too.
//!
//! The limits are wide enough for any land, sea or air vehicle an INS
//! navigates and narrow enough to catch a value in the wrong unit or
//! column (a longitude in radians × 1e6, a speed in mm/s, a height in
//! feet × 1000).

/// Latitude, deg: within 0.1° (11 km) of a pole the north-pointing
/// (local-level NED) mechanisation is singular — its transport rate grows
/// as tan(latitude) without bound and the heading is undefined — so a
/// position there is refused, not navigated wrongly.
pub const LATITUDE: (f64, f64) = (-89.9, 89.9);
/// Longitude, deg: east-positive, either from −180 to 180 or 0 to 360.
pub const LONGITUDE: (f64, f64) = (-180.0, 360.0);
/// Ellipsoidal height, m: below the deepest ocean floor (−10 935 m, plus
/// the geoid's ±110 m) to the edge of space (100 km).
pub const HEIGHT: (f64, f64) = (-12_000.0, 100_000.0);
/// A speed (each velocity component, the odometer's speed), m/s: about
/// three times the speed of sound; beyond it the value is taken to be in
/// the wrong unit.
pub const SPEED: f64 = 1_000.0;
/// An odometer's (wheel) speed, m/s: no wheeled vehicle an odometer is
/// fitted to goes faster than 200 m/s (720 km/h), forwards or in reverse.
pub const WHEEL_SPEED: f64 = 200.0;
/// A rotation rate, rad/s: 20 revolutions per second (7200 °/s), above
/// the range of any gyro an INS uses (the widest MEMS parts measure
/// ±4000 °/s).
pub const ROTATION_RATE: f64 = 40.0 * std::f64::consts::PI;
/// A specific force, m/s²: 1000 g, above the range of any accelerometer an
/// INS uses (shock-rated parts measure ±400 g).
pub const SPECIFIC_FORCE: f64 = 9_806.65;
/// The shortest correlation time of a Gauss-Markov model, s: a shorter one
/// is white noise at any IMU rate (≤ 1 kHz), and its discrete process
/// noise `2σ²/τ` would overflow.
pub const CORRELATION_TIME_MIN: f64 = 1e-3;
/// A lever arm's component, m: no vehicle carries an antenna, wheel or
/// constraint point 100 m from its IMU.
pub const LEVER_ARM: f64 = 100.0;
/// A gyro bias (constant or Gauss-Markov σ), rad/s: 100 000 °/h (28 °/s),
/// above the worst consumer MEMS part's (about 1000 °/h).
pub const GYRO_BIAS: f64 = 1e5 * DEG_PER_H;
/// A gyro angle random walk, rad/√s: 100 °/√h, above the worst consumer
/// MEMS part's (about 3 °/√h).
pub const GYRO_ARW: f64 = 100.0 * std::f64::consts::PI / 180.0 / 60.0;
/// A gyro bias random walk, rad/s/√s: 100 000 °/h/√h.
pub const GYRO_BIAS_WALK: f64 = 1e5 * DEG_PER_H / 60.0;
/// An accelerometer bias (constant or Gauss-Markov σ), m/s²: 1 g, above
/// the worst consumer MEMS part's (about 100 mg).
pub const ACCEL_BIAS: f64 = 9.806_65;
/// An accelerometer velocity random walk, m/s/√s: 100 m/s/√h.
pub const ACCEL_VRW: f64 = 100.0 / 60.0;
/// An accelerometer bias random walk, m/s²/√s: 1 g/√h.
pub const ACCEL_BIAS_WALK: f64 = 9.806_65 / 60.0;
/// A scale-factor error (gyro, accelerometer, odometer), as a fraction:
/// 50 %, beyond which the sensor is not measuring the quantity.
pub const SCALE_FACTOR: f64 = 0.5;
/// The initial attitude σ, rad: 180°, every heading.
pub const ATTITUDE_SIGMA: f64 = std::f64::consts::PI;
/// The initial velocity σ, m/s: [`SPEED`].
pub const VELOCITY_SIGMA: f64 = SPEED;
/// The initial position σ, m: 10 000 km, anywhere on Earth.
pub const POSITION_SIGMA: f64 = 1e7;

/// A standstill detector's threshold on the accelerometer's standard
/// deviation, m/s²: a car's vibration while driving is about 0.5–2 m/s², so
/// a threshold above 2 m/s² reads driving as standing.
pub const ZUPT_ACCEL_STD: f64 = 2.0;
/// A standstill detector's threshold on the gyro's standard deviation,
/// deg/s: above 20 °/s turning reads as standing.
pub const ZUPT_GYRO_STD: f64 = 20.0;
/// A standstill detector's speed limit, m/s: walking pace; above it the
/// vehicle is moving.
pub const ZUPT_MAX_SPEED: f64 = 2.0;
/// The lowest speed at which a GNSS course gives the heading, m/s: below
/// it the course between fixes with metre-level noise is noise.
pub const COURSE_MIN_SPEED: f64 = 1.0;
/// The largest GPS week number (full, not modulo 1024): week 9999 is in
/// the year 2171.
pub const GPS_WEEK_MAX: u32 = 9_999;
/// How far an Earth constant (semi-major axis, GM, rotation rate) may be
/// from WGS-84's, as a fraction: 1 %, wider than any reference ellipsoid
/// differs and narrow enough to catch a constant in the wrong unit.
pub const EARTH_CONSTANT_TOLERANCE: f64 = 0.01;
/// The largest flattening of an Earth model: 0.01 (WGS-84's is 0.00335).
pub const EARTH_FLATTENING_MAX: f64 = 0.01;

/// 1 °/h in rad/s.
const DEG_PER_H: f64 = std::f64::consts::PI / 180.0 / 3600.0;

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
