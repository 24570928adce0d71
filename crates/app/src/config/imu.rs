//! The IMU table: the same keys describe the simulated IMU's true errors
//! (`[imu]` of a scenario file) and the IMU model a filter assumes
//! (`[filter.imu]` of a scenario file, `[imu]` of a `process`
//! configuration). Each quantity may be given in any of its units (one of
//! them); the bare keys of the `process` documentation (`gyro_arw` in
//! °/√h, `gyro_markov_sigma` in °/h, `accel_markov_sigma` in µg) read as
//! the same quantities.

use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::ImuSpec;
use kestrel::sim::ImuErrors;
use serde::{Deserialize, Serialize};

use crate::config::check::{bad, bounded, join, quantity, sigma, Bound, Range, Res};
use crate::config::units::{
    Unit, DEG_PER_H, DEG_PER_H_PER_SQRT_H, DEG_PER_H_PER_SQRT_HZ, DEG_PER_SQRT_H,
    DEG_PER_S_PER_SQRT_HZ, MG, M_S_PER_SQRT_H, PERCENT, PPM, S, SI, UG, UG_PER_SQRT_H,
    UG_PER_SQRT_HZ,
};
use crate::config::vec3::V3;
use kestrel_io::gins::physical;

/// The IMU table as written. The keys of one file that the other does not
/// take are refused by its reader with the reason.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub(crate) struct ImuTable {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rate_hz: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias_deg_per_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_arw: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_arw_deg_per_sqrt_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_arw_deg_per_h_per_sqrt_hz: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_arw_deg_per_s_per_sqrt_hz: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_markov_sigma: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_markov_deg_per_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_markov_tau: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_markov_tau_s: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias_rw: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_bias_rw_deg_per_h_per_sqrt_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale_ppm: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale_percent: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias_ug: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias_mg: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_vrw: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_vrw_ug_per_sqrt_hz: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_vrw_m_s_per_sqrt_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_markov_sigma: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_markov_ug: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_markov_mg: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_markov_tau: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_markov_tau_s: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias_rw: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_bias_rw_ug_per_sqrt_h: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale_ppm: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale_percent: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale_tau: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro_scale_sigma: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel_scale_sigma: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_gap: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub long_gap: Option<String>,
}

/// The plausibility bounds of the IMU's quantities (see
/// [`physical`](kestrel_io::gins::physical)).
pub(crate) const GYRO_BIAS_BOUND: Bound = Bound {
    max_si: physical::GYRO_BIAS,
    beyond: "100 000 °/h, beyond any gyro's bias",
};
pub(crate) const GYRO_ARW_BOUND: Bound = Bound {
    max_si: physical::GYRO_ARW,
    beyond: "100 °/√h, beyond any gyro's noise",
};
const GYRO_WALK_BOUND: Bound = Bound {
    max_si: physical::GYRO_BIAS_WALK,
    beyond: "100 000 °/h/√h, beyond any gyro's bias instability",
};
pub(crate) const ACCEL_BIAS_BOUND: Bound = Bound {
    max_si: physical::ACCEL_BIAS,
    beyond: "1 g, beyond any accelerometer's bias",
};
const ACCEL_VRW_BOUND: Bound = Bound {
    max_si: physical::ACCEL_VRW,
    beyond: "100 m/s/√h, beyond any accelerometer's noise",
};
const ACCEL_WALK_BOUND: Bound = Bound {
    max_si: physical::ACCEL_BIAS_WALK,
    beyond: "1 g/√h, beyond any accelerometer's bias instability",
};
pub(crate) const SCALE_BOUND: Bound = Bound {
    max_si: physical::SCALE_FACTOR,
    beyond: "50 %, beyond which the sensor does not measure the quantity",
};

/// A unit under the `process` spelling `stem_sigma`.
const fn sigma_key(u: Unit) -> Unit {
    Unit {
        suffix: "sigma",
        ..u
    }
}

impl ImuTable {
    /// The per-axis errors at key path `prefix`, SI; absent keys are zero
    /// (correlation times ∞). Biases and scale factors are values of either
    /// sign, noise densities and Markov σ standard deviations (0 for none).
    pub(crate) fn errors(&self, prefix: &str) -> Res<ImuErrors> {
        let p = prefix;
        let signed = |stem: &str, given: &[(&Unit, Option<V3>)], b: Bound| -> Res<Vector3<f64>> {
            let v = quantity(p, stem, given, Range::Any)?.unwrap_or_default();
            bounded(p, stem, given, b)?;
            Ok(v)
        };
        let sd = |stem: &str, given: &[(&Unit, Option<V3>)], b: Bound| -> Res<Vector3<f64>> {
            let v = sigma(p, stem, given, true)?.unwrap_or_default();
            bounded(p, stem, given, b)?;
            Ok(v)
        };
        let tau = |stem: &str, given: &[(&Unit, Option<V3>)]| -> Res<Vector3<f64>> {
            Ok(quantity(p, stem, given, Range::Tau)?
                .unwrap_or_else(|| Vector3::repeat(f64::INFINITY)))
        };
        let (dph, arw) = (DEG_PER_H.bare(), DEG_PER_SQRT_H.bare());
        Ok(ImuErrors {
            gyro_bias: signed(
                "gyro_bias",
                &[
                    (&dph, self.gyro_bias),
                    (&DEG_PER_H, self.gyro_bias_deg_per_h),
                ],
                GYRO_BIAS_BOUND,
            )?,
            gyro_arw: sd(
                "gyro_arw",
                &[
                    (&arw, self.gyro_arw),
                    (&DEG_PER_SQRT_H, self.gyro_arw_deg_per_sqrt_h),
                    (&DEG_PER_H_PER_SQRT_HZ, self.gyro_arw_deg_per_h_per_sqrt_hz),
                    (&DEG_PER_S_PER_SQRT_HZ, self.gyro_arw_deg_per_s_per_sqrt_hz),
                ],
                GYRO_ARW_BOUND,
            )?,
            gyro_markov_sigma: sd(
                "gyro_markov",
                &[
                    (&sigma_key(DEG_PER_H), self.gyro_markov_sigma),
                    (&DEG_PER_H, self.gyro_markov_deg_per_h),
                ],
                GYRO_BIAS_BOUND,
            )?,
            gyro_markov_tau: tau(
                "gyro_markov_tau",
                &[(&SI, self.gyro_markov_tau), (&S, self.gyro_markov_tau_s)],
            )?,
            gyro_scale: signed(
                "gyro_scale",
                &[
                    (&PPM.bare(), self.gyro_scale),
                    (&PPM, self.gyro_scale_ppm),
                    (&PERCENT, self.gyro_scale_percent),
                ],
                SCALE_BOUND,
            )?,
            accel_bias: signed(
                "accel_bias",
                &[
                    (&UG.bare(), self.accel_bias),
                    (&UG, self.accel_bias_ug),
                    (&MG, self.accel_bias_mg),
                ],
                ACCEL_BIAS_BOUND,
            )?,
            accel_vrw: sd(
                "accel_vrw",
                &[
                    (&M_S_PER_SQRT_H.bare(), self.accel_vrw),
                    (&UG_PER_SQRT_HZ, self.accel_vrw_ug_per_sqrt_hz),
                    (&M_S_PER_SQRT_H, self.accel_vrw_m_s_per_sqrt_h),
                ],
                ACCEL_VRW_BOUND,
            )?,
            accel_markov_sigma: sd(
                "accel_markov",
                &[
                    (&sigma_key(UG), self.accel_markov_sigma),
                    (&UG, self.accel_markov_ug),
                    (&MG, self.accel_markov_mg),
                ],
                ACCEL_BIAS_BOUND,
            )?,
            accel_markov_tau: tau(
                "accel_markov_tau",
                &[(&SI, self.accel_markov_tau), (&S, self.accel_markov_tau_s)],
            )?,
            accel_scale: signed(
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

    /// The bias random walks (gyro, accelerometer), SI per √s; zero when
    /// absent. A bias is a Gauss-Markov process or a random walk, not both.
    pub(crate) fn random_walks(&self, prefix: &str, e: &ImuErrors) -> Res<(f64, f64)> {
        let walk = |stem: &str, given: &[(&Unit, Option<V3>)], markov: &Vector3<f64>, b: Bound| {
            let Some(v) = sigma(prefix, stem, given, true)? else {
                return Ok(0.0);
            };
            bounded(prefix, stem, given, b)?;
            if *markov != Vector3::zeros() {
                let key = given
                    .iter()
                    .find(|(_, v)| v.is_some())
                    .map(|(u, _)| u.key(stem));
                return Err(bad(
                    join(prefix, key.as_deref().unwrap_or(stem)),
                    "one bias model per sensor: a Gauss-Markov process (`*_markov_sigma`) or a \
                     random walk, not both",
                ));
            }
            same(prefix, stem, &v).map(|x| x.x)
        };
        Ok((
            walk(
                "gyro_bias_rw",
                &[
                    (&DEG_PER_H_PER_SQRT_H.bare(), self.gyro_bias_rw),
                    (
                        &DEG_PER_H_PER_SQRT_H,
                        self.gyro_bias_rw_deg_per_h_per_sqrt_h,
                    ),
                ],
                &e.gyro_markov_sigma,
                GYRO_WALK_BOUND,
            )?,
            walk(
                "accel_bias_rw",
                &[
                    (&UG_PER_SQRT_H.bare(), self.accel_bias_rw),
                    (&UG_PER_SQRT_H, self.accel_bias_rw_ug_per_sqrt_h),
                ],
                &e.accel_markov_sigma,
                ACCEL_WALK_BOUND,
            )?,
        ))
    }

    /// The IMU model a filter assumes at key path `prefix`: one value per
    /// quantity (the same on every axis), with the bias random walks.
    pub(crate) fn model(&self, prefix: &str) -> Res<ImuSpec> {
        let e = self.errors(prefix)?;
        let axes = [
            ("gyro_bias", e.gyro_bias),
            ("gyro_arw", e.gyro_arw),
            ("gyro_markov", e.gyro_markov_sigma),
            ("gyro_markov_tau", e.gyro_markov_tau),
            ("gyro_scale", e.gyro_scale),
            ("accel_bias", e.accel_bias),
            ("accel_vrw", e.accel_vrw),
            ("accel_markov", e.accel_markov_sigma),
            ("accel_markov_tau", e.accel_markov_tau),
            ("accel_scale", e.accel_scale),
        ];
        for (stem, v) in &axes {
            same(prefix, stem, v)?;
        }
        let (gyro_bias_rw, accel_bias_rw) = self.random_walks(prefix, &e)?;
        Ok(ImuSpec {
            gyro_bias: e.gyro_bias.x,
            gyro_arw: e.gyro_arw.x,
            gyro_markov_sigma: e.gyro_markov_sigma.x,
            gyro_markov_tau: e.gyro_markov_tau.x,
            accel_bias: e.accel_bias.x,
            accel_vrw: e.accel_vrw.x,
            accel_markov_sigma: e.accel_markov_sigma.x,
            accel_markov_tau: e.accel_markov_tau.x,
            gyro_scale: e.gyro_scale.x,
            accel_scale: e.accel_scale.x,
            gyro_bias_rw,
            accel_bias_rw,
        })
    }

    /// The `process`-only keys (the 21-state model's scale factors and the
    /// IMU timing rule), as `(key, present)` for a scenario file's
    /// refusal.
    pub(crate) fn process_keys(&self) -> [(&'static str, bool); 5] {
        [
            ("scale_tau", self.scale_tau.is_some()),
            ("gyro_scale_sigma", self.gyro_scale_sigma.is_some()),
            ("accel_scale_sigma", self.accel_scale_sigma.is_some()),
            ("max_gap", self.max_gap.is_some()),
            ("long_gap", self.long_gap.is_some()),
        ]
    }

    /// The bias random-walk keys, as `(key, present)`.
    pub(crate) fn random_walk_keys(&self) -> [(&'static str, bool); 4] {
        [
            ("gyro_bias_rw", self.gyro_bias_rw.is_some()),
            (
                "gyro_bias_rw_deg_per_h_per_sqrt_h",
                self.gyro_bias_rw_deg_per_h_per_sqrt_h.is_some(),
            ),
            ("accel_bias_rw", self.accel_bias_rw.is_some()),
            (
                "accel_bias_rw_ug_per_sqrt_h",
                self.accel_bias_rw_ug_per_sqrt_h.is_some(),
            ),
        ]
    }
}

/// `v` with the same value on every axis (a filter's IMU model is
/// isotropic).
fn same(prefix: &str, stem: &str, v: &Vector3<f64>) -> Res<Vector3<f64>> {
    if v.x.to_bits() == v.y.to_bits() && v.y.to_bits() == v.z.to_bits() {
        Ok(*v)
    } else {
        Err(bad(
            join(prefix, stem),
            "the assumed IMU model is the same on every axis: give one number",
        ))
    }
}
