//! The units a file may give a quantity in. Each conversion is the one the
//! built-in scenarios use, operation for operation, so a file reproduces
//! them bit for bit.

use kestrel::nav::ImuSpec;

/// A unit: the key suffix and the conversions to and from SI.
pub(super) struct Unit {
    /// Key suffix, e.g. `deg_per_h`.
    pub suffix: &'static str,
    /// File value to SI.
    pub to_si: fn(f64) -> f64,
    /// SI to file value (for writing; exactness is checked by the writer).
    pub from_si: fn(f64) -> f64,
}

const fn unit(suffix: &'static str, to_si: fn(f64) -> f64, from_si: fn(f64) -> f64) -> Unit {
    Unit {
        suffix,
        to_si,
        from_si,
    }
}

const P: ImuSpec = ImuSpec::perfect();

/// SI already (m, m/s, s, Hz, ratio).
pub(super) const SI: Unit = unit("", |x| x, |x| x);
/// Degrees.
pub(super) const DEG: Unit = unit("deg", f64::to_radians, f64::to_degrees);
/// Arc-minutes.
pub(super) const ARCMIN: Unit = unit(
    "arcmin",
    |x| (x / 60.0).to_radians(),
    |x| x.to_degrees() * 60.0,
);
/// Arc-seconds.
pub(super) const ARCSEC: Unit = unit(
    "arcsec",
    |x| (x / 3600.0).to_radians(),
    |x| x.to_degrees() * 3600.0,
);
/// Degrees per hour (gyro bias and drift).
pub(super) const DEG_PER_H: Unit = unit(
    "deg_per_h",
    |x| P.with_gyro_bias_deg_per_h(x).gyro_bias,
    |x| x.to_degrees() * 3600.0,
);
/// Degrees per root hour (angle random walk).
pub(super) const DEG_PER_SQRT_H: Unit = unit(
    "deg_per_sqrt_h",
    |x| P.with_gyro_arw_deg_per_sqrt_h(x).gyro_arw,
    |x| x.to_degrees() * 60.0,
);
/// Degrees per hour per root hertz (rate-noise density; 1/60 of °/√h).
pub(super) const DEG_PER_H_PER_SQRT_HZ: Unit = unit(
    "deg_per_h_per_sqrt_hz",
    |x| P.with_gyro_arw_deg_per_sqrt_h(x / 60.0).gyro_arw,
    |x| x.to_degrees() * 3600.0,
);
/// Micro-g.
pub(super) const UG: Unit = unit(
    "ug",
    |x| P.with_accel_bias_ug(x).accel_bias,
    |x| x / kestrel::nav::imu_spec::G0 * 1e6,
);
/// Milli-g.
pub(super) const MG: Unit = unit(
    "mg",
    |x| P.with_accel_bias_mg(x).accel_bias,
    |x| x / kestrel::nav::imu_spec::G0 * 1e3,
);
/// Micro-g per root hertz (accelerometer noise density).
pub(super) const UG_PER_SQRT_HZ: Unit = unit(
    "ug_per_sqrt_hz",
    |x| P.with_accel_vrw_ug_per_sqrt_hz(x).accel_vrw,
    |x| x / kestrel::nav::imu_spec::G0 * 1e6,
);
/// Metres per second per root hour (velocity random walk).
pub(super) const M_S_PER_SQRT_H: Unit = unit(
    "m_s_per_sqrt_h",
    |x| P.with_accel_vrw_m_s_per_sqrt_h(x).accel_vrw,
    |x| x * 60.0,
);
/// Parts per million.
pub(super) const PPM: Unit = unit("ppm", |x| P.with_gyro_scale_ppm(x).gyro_scale, |x| x * 1e6);
/// Percent.
pub(super) const PERCENT: Unit = unit("percent", |x| x / 100.0, |x| x * 100.0);

/// Angles.
pub(super) const ANGLE: [&Unit; 3] = [&DEG, &ARCMIN, &ARCSEC];
/// Gyro biases and drifts.
pub(super) const GYRO_RATE: [&Unit; 1] = [&DEG_PER_H];
/// Gyro white noise.
pub(super) const GYRO_NOISE: [&Unit; 2] = [&DEG_PER_SQRT_H, &DEG_PER_H_PER_SQRT_HZ];
/// Accelerometer biases.
pub(super) const ACCEL: [&Unit; 2] = [&UG, &MG];
/// Accelerometer white noise.
pub(super) const ACCEL_NOISE: [&Unit; 2] = [&UG_PER_SQRT_HZ, &M_S_PER_SQRT_H];
/// Scale factors.
pub(super) const RATIO: [&Unit; 2] = [&PPM, &PERCENT];
