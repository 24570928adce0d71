//! Datasheet units of the process configuration and their SI values.
//!
//! Each function maps a configuration value to SI; writers of
//! configurations invert them with [`invert_exact`](kestrel_io::gins::invert_exact)
//! so that a written value reads back to the same bits.

use std::f64::consts::PI;

/// Standard gravity for µg, m/s².
pub const G0: f64 = 9.806_65;

/// Degrees to radians.
///
/// ```
/// assert_eq!(kestrel_app::process::units::deg(180.0), std::f64::consts::PI);
/// ```
pub fn deg(x: f64) -> f64 {
    kestrel_io::gins::degrees_to_radians(x)
}

/// °/h to rad/s.
///
/// ```
/// let r = kestrel_app::process::units::deg_per_h(3600.0);
/// assert!((r - 1f64.to_radians()).abs() < 1e-15);
/// ```
pub fn deg_per_h(x: f64) -> f64 {
    x * (PI / 180.0 / 3600.0)
}

/// °/√h to rad/√s.
///
/// ```
/// let r = kestrel_app::process::units::deg_per_sqrt_h(60.0);
/// assert!((r - 1f64.to_radians()).abs() < 1e-15);
/// ```
pub fn deg_per_sqrt_h(x: f64) -> f64 {
    x * (PI / 180.0 / 60.0)
}

/// m/s/√h to m/s/√s.
///
/// ```
/// assert_eq!(kestrel_app::process::units::m_s_per_sqrt_h(0.6), 0.01);
/// ```
pub fn m_s_per_sqrt_h(x: f64) -> f64 {
    x / 60.0
}

/// µg (or µg/√Hz) to m/s² (or m/s/√s).
///
/// ```
/// assert!((kestrel_app::process::units::ug(100.0) - 9.80665e-4).abs() < 1e-18);
/// ```
pub fn ug(x: f64) -> f64 {
    x * (1e-6 * G0)
}

/// ppm to a ratio.
///
/// ```
/// assert_eq!(kestrel_app::process::units::ppm(1e6), 1.0);
/// ```
pub fn ppm(x: f64) -> f64 {
    x * 1e-6
}
