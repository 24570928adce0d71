//! The one units module: every datasheet unit a configuration, a scenario
//! file, an importer or a built-in scenario gives a quantity in, with its
//! conversion to SI and back.
//!
//! Each conversion is the one `kestrel_nav::ImuSpec`'s builders use,
//! operation for operation, so a value read from a file, built in Rust or
//! imported from another tool's configuration gives the same bits in SI.
//! Writers invert a conversion exactly (the shortest decimal that converts
//! back to the same SI value, see [`Unit::exact`]).
//!
//! ```
//! use kestrel_app::config::units::{ARCMIN, DEG_PER_H, UG};
//! assert_eq!(DEG_PER_H.si(3600.0), 1.0_f64.to_radians());
//! assert_eq!(UG.si(1e6), 9.80665);
//! assert_eq!(ARCMIN.si(60.0), 1.0_f64.to_radians());
//! ```

use kestrel::nav::imu_spec::G0;
use kestrel::nav::ImuSpec;

/// A unit: the key suffix that names it in files and the conversions to
/// and from SI.
#[derive(Clone, Copy, Debug)]
pub struct Unit {
    /// Key suffix, e.g. `deg_per_h` (empty for the SI unit).
    pub suffix: &'static str,
    /// File value to SI.
    pub to_si: fn(f64) -> f64,
    /// SI to file value (approximate; [`exact`](Self::exact) refines it).
    pub from_si: fn(f64) -> f64,
}

impl Unit {
    /// The same unit named by the bare key (no suffix): the `process`
    /// configuration's keys state their unit in the documentation
    /// (`initial.std.attitude` in degrees) where scenario files name it
    /// (`attitude_deg`); both spellings read through the same table.
    pub const fn bare(self) -> Self {
        Self { suffix: "", ..self }
    }

    /// `x` in this unit, in SI.
    pub fn si(&self, x: f64) -> f64 {
        (self.to_si)(x)
    }

    /// The value in this unit that converts to exactly `si`, when there is
    /// one near the approximate inverse (the neighbouring doubles are
    /// tried), else the approximate inverse.
    ///
    /// ```
    /// use kestrel_app::config::units::DEG_PER_H;
    /// let si = DEG_PER_H.si(0.1);
    /// assert_eq!(DEG_PER_H.si(DEG_PER_H.exact(si)), si);
    /// ```
    pub fn exact(&self, si: f64) -> f64 {
        kestrel_io::gins::invert_exact(si, (self.from_si)(si), self.to_si)
    }

    /// The key of quantity `stem` in this unit: `stem_suffix`, or `stem`
    /// for the SI unit.
    ///
    /// ```
    /// use kestrel_app::config::units::{DEG_PER_H, SI};
    /// assert_eq!(DEG_PER_H.key("gyro_bias"), "gyro_bias_deg_per_h");
    /// assert_eq!(SI.key("odometer_scale"), "odometer_scale");
    /// ```
    pub fn key(&self, stem: &str) -> String {
        if self.suffix.is_empty() {
            stem.to_string()
        } else {
            format!("{stem}_{}", self.suffix)
        }
    }
}

const fn unit(suffix: &'static str, to_si: fn(f64) -> f64, from_si: fn(f64) -> f64) -> Unit {
    Unit {
        suffix,
        to_si,
        from_si,
    }
}

const P: ImuSpec = ImuSpec::perfect();

/// SI (no suffix): m, m/s, rad, s, or a ratio.
pub const SI: Unit = unit("", |x| x, |x| x);
/// Metres (a key that names its unit).
pub const M: Unit = unit("m", |x| x, |x| x);
/// Metres per second.
pub const M_S: Unit = unit("m_s", |x| x, |x| x);
/// Seconds.
pub const S: Unit = unit("s", |x| x, |x| x);
/// Hertz.
pub const HZ: Unit = unit("hz", |x| x, |x| x);
/// Degrees (angles).
pub const DEG: Unit = unit("deg", f64::to_radians, f64::to_degrees);
/// Arc minutes.
pub const ARCMIN: Unit = unit(
    "arcmin",
    |x| (x / 60.0).to_radians(),
    |x| x.to_degrees() * 60.0,
);
/// Arc seconds.
pub const ARCSEC: Unit = unit(
    "arcsec",
    |x| (x / 3600.0).to_radians(),
    |x| x.to_degrees() * 3600.0,
);
/// Degrees per second.
pub const DEG_S: Unit = unit("deg_s", f64::to_radians, f64::to_degrees);
/// Degrees per hour (gyro biases).
pub const DEG_PER_H: Unit = unit(
    "deg_per_h",
    |x| P.with_gyro_bias_deg_per_h(x).gyro_bias,
    |x| x.to_degrees() * 3600.0,
);
/// Degrees per root hour (gyro angle random walk).
pub const DEG_PER_SQRT_H: Unit = unit(
    "deg_per_sqrt_h",
    |x| P.with_gyro_arw_deg_per_sqrt_h(x).gyro_arw,
    |x| x.to_degrees() * 60.0,
);
/// Degrees per hour per root hertz (gyro noise density; 60 °/h/√Hz =
/// 1 °/√h).
pub const DEG_PER_H_PER_SQRT_HZ: Unit = unit(
    "deg_per_h_per_sqrt_hz",
    |x| P.with_gyro_arw_deg_per_sqrt_h(x / 60.0).gyro_arw,
    |x| x.to_degrees() * 3600.0,
);
/// Degrees per second per root hertz (gyro noise density; °/s/√Hz =
/// °/√s).
pub const DEG_PER_S_PER_SQRT_HZ: Unit =
    unit("deg_per_s_per_sqrt_hz", f64::to_radians, f64::to_degrees);
/// Degrees per hour per root hour (gyro bias random walk).
pub const DEG_PER_H_PER_SQRT_H: Unit = unit(
    "deg_per_h_per_sqrt_h",
    |x| P.with_gyro_bias_deg_per_h(x).gyro_bias / 60.0,
    |x| x.to_degrees() * 3600.0 * 60.0,
);
/// Micro-g (accelerometer biases).
pub const UG: Unit = unit(
    "ug",
    |x| P.with_accel_bias_ug(x).accel_bias,
    |x| x / G0 * 1e6,
);
/// Milli-g.
pub const MG: Unit = unit(
    "mg",
    |x| P.with_accel_bias_mg(x).accel_bias,
    |x| x / G0 * 1e3,
);
/// Micro-g per root hertz (accelerometer noise density).
pub const UG_PER_SQRT_HZ: Unit = unit(
    "ug_per_sqrt_hz",
    |x| P.with_accel_vrw_ug_per_sqrt_hz(x).accel_vrw,
    |x| x / G0 * 1e6,
);
/// Metres per second per root hour (velocity random walk).
pub const M_S_PER_SQRT_H: Unit = unit(
    "m_s_per_sqrt_h",
    |x| P.with_accel_vrw_m_s_per_sqrt_h(x).accel_vrw,
    |x| x * 60.0,
);
/// Micro-g per root hour (accelerometer bias random walk).
pub const UG_PER_SQRT_H: Unit = unit(
    "ug_per_sqrt_h",
    |x| P.with_accel_bias_ug(x).accel_bias / 60.0,
    |x| x / G0 * 1e6 * 60.0,
);
/// Parts per million (scale factors).
pub const PPM: Unit = unit("ppm", |x| P.with_gyro_scale_ppm(x).gyro_scale, |x| x * 1e6);
/// Percent (scale factors).
pub const PERCENT: Unit = unit("percent", |x| x / 100.0, |x| x * 100.0);

/// Angles, in order of preference for writing.
pub const ANGLE: [&Unit; 3] = [&DEG, &ARCMIN, &ARCSEC];
/// Gyro biases and Markov σ.
pub const GYRO_RATE: [&Unit; 1] = [&DEG_PER_H];
/// Gyro white noise.
pub const GYRO_NOISE: [&Unit; 2] = [&DEG_PER_SQRT_H, &DEG_PER_H_PER_SQRT_HZ];
/// Accelerometer biases and Markov σ.
pub const ACCEL: [&Unit; 2] = [&UG, &MG];
/// Accelerometer white noise.
pub const ACCEL_NOISE: [&Unit; 2] = [&UG_PER_SQRT_HZ, &M_S_PER_SQRT_H];
/// Scale factors.
pub const RATIO: [&Unit; 2] = [&PPM, &PERCENT];
