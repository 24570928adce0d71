//! Angle and rate units of the papers, in SI.

/// Arc-minutes to radians.
pub(crate) fn arcmin(x: f64) -> f64 {
    (x / 60.0).to_radians()
}

/// Arc-seconds to radians.
pub(crate) fn arcsec(x: f64) -> f64 {
    (x / 3600.0).to_radians()
}

/// Degrees per hour to rad/s.
pub(crate) fn deg_per_h(x: f64) -> f64 {
    x.to_radians() / 3600.0
}

/// Micro-g to m/s².
pub(crate) fn ug(x: f64) -> f64 {
    x * 1e-6 * kestrel::nav::imu_spec::G0
}

/// Milli-g to m/s².
pub(crate) fn mg(x: f64) -> f64 {
    x * 1e-3 * kestrel::nav::imu_spec::G0
}
