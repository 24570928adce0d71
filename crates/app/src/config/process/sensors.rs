//! The sensors' tables: `[imu]` (the filter's IMU model and the timing
//! rule), the known initial sensor errors, `[alignment]`, `[nhc]`, `[zupt]`,
//! `[odometer]`, and the filter kind of `[filter]`.

use super::check::{id, Check, Zero};
use super::schema::*;
use super::*;

impl Check<'_> {
    /// `[imu] max_gap` (s, > 0, default 1) and `long_gap` (`"error"`,
    /// the default, or `"coast"`).
    pub(super) fn timing(&self, m: &ImuTable) -> Result<TimingRule, InputError> {
        let default = TimingRule::default();
        let max_gap = self.positive("imu.max_gap", m.max_gap.unwrap_or(default.max_gap))?;
        let long_gap = match m.long_gap.as_deref() {
            None | Some("error") => LongGap::Error,
            Some("coast") => LongGap::Coast,
            Some(other) => {
                return Err(self.err(
                    "imu.long_gap",
                    format!("expected `error` or `coast`, found `{other}`"),
                ))
            }
        };
        Ok(TimingRule { max_gap, long_gap })
    }

    /// `initial.gyro_bias` (°/h), `accel_bias` (µg), `gyro_scale`,
    /// `accel_scale` (ppm): known sensor errors, within physical bounds.
    pub(super) fn initial_imu(&self, i: &Initial) -> Result<ImuBiases, InputError> {
        let bounded = |key: &str, v: Option<V3>, unit: fn(f64) -> f64, name: (&str, &str, f64)| {
            let Some(v) = v else {
                return Ok(Vector3::zeros());
            };
            let (what, unit_name, limit) = name;
            self.vec(
                &format!("initial.{key}"),
                v,
                |c: &Self, k: &str, x: f64| c.within(k, what, unit_name, x, (-limit, limit)),
                unit,
            )
        };
        let scale = ("a scale-factor error", "ppm", 100_000.0);
        Ok(ImuBiases {
            gyro: bounded(
                "gyro_bias",
                i.gyro_bias,
                deg_per_h,
                ("a gyro bias", "°/h", 36_000.0),
            )?,
            accel: bounded(
                "accel_bias",
                i.accel_bias,
                ug,
                ("an accelerometer bias", "µg", 200_000.0),
            )?,
            gyro_scale: bounded("gyro_scale", i.gyro_scale, ppm, scale)?,
            accel_scale: bounded("accel_scale", i.accel_scale, ppm, scale)?,
        })
    }

    /// `[imu]`: the filter's IMU model ([`ImuTable`]); the turn-on biases
    /// and scale factors are P0 here, so their keys are refused with the
    /// keys to use.
    pub(super) fn imu(&self, m: &ImuTable) -> Result<ImuSpec, InputError> {
        let use_p0 = |sensor: &str, unit: &str| {
            format!(
                "not used by `process`: the filter's initial {sensor} bias σ is \
                 `initial.std.{sensor}_bias` ({unit}) and a drifting bias is \
                 `imu.{sensor}_markov_sigma` / `imu.{sensor}_markov_tau`"
            )
        };
        let no_state = "not used by `process`: the filter's scale-factor σ is \
                        `initial.std.gyro_scale` / `accel_scale` (ppm, error_model = `ins21`) \
                        and a known scale-factor error is `initial.gyro_scale` / `accel_scale`";
        let refused = [
            ("gyro_bias", m.gyro_bias.is_some(), use_p0("gyro", "°/h")),
            (
                "gyro_bias_deg_per_h",
                m.gyro_bias_deg_per_h.is_some(),
                use_p0("gyro", "°/h"),
            ),
            ("accel_bias", m.accel_bias.is_some(), use_p0("accel", "µg")),
            (
                "accel_bias_ug",
                m.accel_bias_ug.is_some(),
                use_p0("accel", "µg"),
            ),
            (
                "accel_bias_mg",
                m.accel_bias_mg.is_some(),
                use_p0("accel", "µg"),
            ),
            ("gyro_scale", m.gyro_scale.is_some(), no_state.to_owned()),
            (
                "gyro_scale_ppm",
                m.gyro_scale_ppm.is_some(),
                no_state.to_owned(),
            ),
            (
                "gyro_scale_percent",
                m.gyro_scale_percent.is_some(),
                no_state.to_owned(),
            ),
            ("accel_scale", m.accel_scale.is_some(), no_state.to_owned()),
            (
                "accel_scale_ppm",
                m.accel_scale_ppm.is_some(),
                no_state.to_owned(),
            ),
            (
                "accel_scale_percent",
                m.accel_scale_percent.is_some(),
                no_state.to_owned(),
            ),
            (
                "rate_hz",
                m.rate_hz.is_some(),
                "not used by `process`: the IMU rate is the IMU file's".to_owned(),
            ),
        ];
        if let Some((key, _, why)) = refused.into_iter().find(|(_, given, _)| *given) {
            return Err(self.err(&format!("imu.{key}"), why));
        }
        m.model("imu").map_err(|b| self.source.bad(b))
    }

    pub(super) fn alignment(&self, a: &Alignment) -> Result<AlignmentSettings, InputError> {
        let yaw = match a.yaw.as_str() {
            "gnss-course" => YawSource::GnssCourse,
            "gyrocompass" => YawSource::Gyrocompass,
            other => {
                return Err(self.err(
                    "alignment.yaw",
                    format!("expected `gnss-course` or `gyrocompass`, found `{other}`"),
                ))
            }
        };
        if yaw == YawSource::Gyrocompass && (a.min_speed.is_some() || a.gyro_bias == Some(true)) {
            let key = if a.min_speed.is_some() {
                "alignment.min_speed"
            } else {
                "alignment.gyro_bias"
            };
            return Err(self.err(
                key,
                "not used by `gyrocompass` (the static rate is the Earth rate it measures)",
            ));
        }
        Ok(AlignmentSettings {
            static_time: self.within(
                "alignment.static_time",
                "a duration",
                "s",
                self.positive("alignment.static_time", a.static_time)?,
                (0.0, 86_400.0),
            )?,
            yaw,
            min_speed: self.within(
                "alignment.min_speed",
                "a speed at which the GNSS course gives the heading",
                "m/s",
                a.min_speed.unwrap_or(3.0),
                (physical::COURSE_MIN_SPEED, physical::SPEED),
            )?,
            gyro_bias: a.gyro_bias.unwrap_or(yaw == YawSource::GnssCourse),
            max_accel_std: self
                .positive("alignment.max_accel_std", a.max_accel_std.unwrap_or(0.1))?,
        })
    }

    pub(super) fn nhc(&self, n: &Nhc) -> Result<NhcSettings, InputError> {
        Ok(NhcSettings {
            rate: self.within(
                "nhc.rate",
                "an update rate",
                "Hz",
                self.positive("nhc.rate", n.rate)?,
                (0.0, MAX_RATE),
            )?,
            std: [
                self.sigma("nhc.std[0]", n.std.0[0], id, Zero::Refused)?,
                self.sigma("nhc.std[1]", n.std.0[1], id, Zero::Refused)?,
            ],
            mounting: [
                deg(self.within(
                    "nhc.mounting[0]",
                    "a pitch",
                    "deg",
                    n.mounting.0[0],
                    (-90.0, 90.0),
                )?),
                deg(self.within(
                    "nhc.mounting[1]",
                    "a yaw",
                    "deg",
                    n.mounting.0[1],
                    (-180.0, 360.0),
                )?),
            ],
            lever_arm: self.lever_arm("nhc.lever_arm", n.lever_arm)?,
        })
    }

    pub(super) fn zupt(&self, z: &Zupt) -> Result<ZuptSettings, InputError> {
        Ok(ZuptSettings {
            window: self.within(
                "zupt.window",
                "a duration",
                "s",
                self.positive("zupt.window", z.window.unwrap_or(1.0))?,
                (0.0, 3_600.0),
            )?,
            accel_std: self.positive_at_most(
                "zupt.accel_std",
                "a standstill threshold",
                "m/s²",
                z.accel_std,
                physical::ZUPT_ACCEL_STD,
            )?,
            gyro_std: deg(self.positive_at_most(
                "zupt.gyro_std",
                "a standstill threshold",
                "deg/s",
                z.gyro_std,
                physical::ZUPT_GYRO_STD,
            )?),
            rate: self.within(
                "zupt.rate",
                "an update rate",
                "Hz",
                self.positive("zupt.rate", z.rate)?,
                (0.0, MAX_RATE),
            )?,
            velocity_std: self.sigma("zupt.velocity_std", z.velocity_std, id, Zero::Refused)?,
            angular_rate_std: self.sigma(
                "zupt.angular_rate_std",
                z.angular_rate_std,
                deg,
                Zero::Absent,
            )?,
            max_speed: self.positive_at_most(
                "zupt.max_speed",
                "a standstill speed",
                "m/s",
                z.max_speed.unwrap_or(0.5),
                physical::ZUPT_MAX_SPEED,
            )?,
        })
    }

    pub(super) fn odometer(&self, o: &Odometer) -> Result<OdometerSettings, InputError> {
        Ok(OdometerSettings {
            rate: self.positive("odometer.rate", o.rate)?,
            speed_std: self.sigma("odometer.speed_std", o.speed_std, id, Zero::Refused)?,
            nhc_std: self.sigma("odometer.nhc_std", o.nhc_std, id, Zero::Refused)?,
            mounting: [
                deg(self.within(
                    "odometer.mounting[0]",
                    "a pitch",
                    "deg",
                    o.mounting.0[0],
                    (-90.0, 90.0),
                )?),
                deg(self.within(
                    "odometer.mounting[1]",
                    "a yaw",
                    "deg",
                    o.mounting.0[1],
                    (-180.0, 360.0),
                )?),
            ],
            lever_arm: self.lever_arm("odometer.lever_arm", o.lever_arm)?,
            scale_sigma: self.sigma("odometer.scale_sigma", o.scale_sigma, id, Zero::Absent)?,
        })
    }

    pub(super) fn kind(&self, f: &Filter, model: ErrorModelKind) -> Result<FilterKind, InputError> {
        let kind = read_kind(&f.kind, "filter", Some("ekf"), Kinds::Engine)
            .map_err(|b| self.err(&b.key, b.message))?;
        let odometer = matches!(model, ErrorModelKind::Odometer16 { .. });
        let name = kind.name();
        if kind.is_odometer() && !odometer {
            return Err(self.err(
                "filter.kind",
                format!("`{name}` needs error_model = `odometer16`"),
            ));
        }
        if odometer && !(kind.is_odometer() || kind == FilterKind::Standard) {
            return Err(self.err(
                "filter.kind",
                format!(
                    "`odometer16` runs `ekf`, `max-threshold` or `fuzzy-adaptive`, not `{name}`"
                ),
            ));
        }
        Ok(kind)
    }
}
