//! The initial uncertainty (P0 as standard deviations): the same table is
//! `[initial.std]` of a `process` configuration and `[filter.p0]` of a
//! scenario file. Each quantity may be given in any of its units (one of
//! them); a bare key (`attitude`, `gyro_bias`) is in the unit the `process`
//! documentation states for it (degrees, °/h, µg, ppm; the odometer scale
//! as a ratio).

use serde::{Deserialize, Serialize};

use crate::config::check::{bounded, sigma, Bound, Res};
use crate::config::imu::{ACCEL_BIAS_BOUND, GYRO_BIAS_BOUND, SCALE_BOUND};
use crate::config::units::{Unit, ARCMIN, ARCSEC, DEG, DEG_PER_H, MG, PERCENT, PPM, SI, UG};
use crate::config::vec3::V3;
use crate::scenario::InitialUncertainty;
use kestrel_io::gins::physical;

/// The P0 table as written.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct P0Table {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attitude: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attitude_deg: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attitude_arcmin: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attitude_arcsec: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub velocity: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub velocity_m_s: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position_m: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias_deg_per_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_markov: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_markov_deg_per_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias_ug: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias_mg: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub odometer_scale: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub odometer_scale_ppm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub odometer_scale_percent: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale_ppm: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale_percent: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale_ppm: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale_percent: Option<V3>,
}

/// The initial attitude σ's bound: 180°, every heading.
const ATTITUDE_BOUND: Bound = Bound {
    max_si: physical::ATTITUDE_SIGMA,
    beyond: "180°, every attitude",
};
/// The initial velocity σ's bound.
const VELOCITY_BOUND: Bound = Bound {
    max_si: physical::VELOCITY_SIGMA,
    beyond: "1000 m/s, beyond any vehicle's speed",
};
/// The initial position σ's bound.
const POSITION_BOUND: Bound = Bound {
    max_si: physical::POSITION_SIGMA,
    beyond: "10 000 km, anywhere on Earth",
};

impl P0Table {
    /// The table at key path `prefix` in SI: attitude, velocity and
    /// position required and positive, every sensor error 0 (none) or
    /// positive; each a standard deviation whose variance is a normal
    /// double.
    pub(crate) fn uncertainty(&self, prefix: &str) -> Res<InitialUncertainty> {
        let required = |stem: &str, given: &[(&Unit, Option<V3>)], b: Bound| -> Res<_> {
            let v = sigma(prefix, stem, given, false)?.ok_or_else(|| {
                crate::config::check::bad(
                    crate::config::check::join(prefix, stem),
                    "missing: the initial σ of attitude, velocity and position are required",
                )
            })?;
            bounded(prefix, stem, given, b)?;
            Ok(v)
        };
        let optional = |stem: &str, given: &[(&Unit, Option<V3>)], b: Bound| -> Res<_> {
            let v = sigma(prefix, stem, given, true)?.unwrap_or_default();
            bounded(prefix, stem, given, b)?;
            Ok(v)
        };
        let one = |x: Option<f64>| x.map(|x| V3([x; 3]));
        let (deg, dph) = (DEG.bare(), DEG_PER_H.bare());
        let odometer = optional(
            "odometer_scale",
            &[
                (&SI, one(self.odometer_scale)),
                (&PPM, one(self.odometer_scale_ppm)),
                (&PERCENT, one(self.odometer_scale_percent)),
            ],
            SCALE_BOUND,
        )
        .map_err(scalar_key)?;
        Ok(InitialUncertainty {
            attitude: required(
                "attitude",
                &[
                    (&deg, self.attitude),
                    (&DEG, self.attitude_deg),
                    (&ARCMIN, self.attitude_arcmin),
                    (&ARCSEC, self.attitude_arcsec),
                ],
                ATTITUDE_BOUND,
            )?,
            velocity: required(
                "velocity",
                &[
                    (&SI, self.velocity),
                    (&crate::config::units::M_S, self.velocity_m_s),
                ],
                VELOCITY_BOUND,
            )?,
            position: required(
                "position",
                &[
                    (&SI, self.position),
                    (&crate::config::units::M, self.position_m),
                ],
                POSITION_BOUND,
            )?,
            gyro_bias: optional(
                "gyro_bias",
                &[
                    (&dph, self.gyro_bias),
                    (&DEG_PER_H, self.gyro_bias_deg_per_h),
                ],
                GYRO_BIAS_BOUND,
            )?,
            gyro_markov: optional(
                "gyro_markov",
                &[
                    (&dph, self.gyro_markov),
                    (&DEG_PER_H, self.gyro_markov_deg_per_h),
                ],
                GYRO_BIAS_BOUND,
            )?,
            accel_bias: optional(
                "accel_bias",
                &[
                    (&UG.bare(), self.accel_bias),
                    (&UG, self.accel_bias_ug),
                    (&MG, self.accel_bias_mg),
                ],
                ACCEL_BIAS_BOUND,
            )?,
            odometer_scale: odometer.x,
            gyro_scale: optional(
                "gyro_scale",
                &[
                    (&PPM.bare(), self.gyro_scale),
                    (&PPM, self.gyro_scale_ppm),
                    (&PERCENT, self.gyro_scale_percent),
                ],
                SCALE_BOUND,
            )?,
            accel_scale: optional(
                "accel_scale",
                &[
                    (&PPM.bare(), self.accel_scale),
                    (&PPM, self.accel_scale_ppm),
                    (&PERCENT, self.accel_scale_percent),
                ],
                SCALE_BOUND,
            )?,
        })
    }
}

/// A scalar's error names its key, not a component.
fn scalar_key(mut b: crate::config::check::Bad) -> crate::config::check::Bad {
    if let Some(i) = b.key.rfind('[') {
        b.key.truncate(i);
    }
    b
}
