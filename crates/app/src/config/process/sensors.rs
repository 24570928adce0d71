//! The sensors' tables: `[imu]` (the filter's IMU model and the timing
//! rule), the known initial sensor errors, `[alignment]`, `[nhc]`, `[zupt]`,
//! `[odometer]`, and the filter kind of `[filter]`.

use super::check::{id, Check, Zero};
use super::schema::*;
use super::*;

impl Check<'_> {
    /// `[imu] max_gap` (s, > 0, default 1) and `long_gap` (`"error"`,
    /// the default, or `"coast"`).
    pub(super) fn timing(&self, m: &Imu) -> Result<TimingRule, InputError> {
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

    pub(super) fn imu(&self, m: &Imu) -> Result<ImuSpec, InputError> {
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
            (
                "imu.gyro_bias",
                m.gyro_bias.is_some(),
                use_p0("gyro", "°/h"),
            ),
            (
                "imu.accel_bias",
                m.accel_bias.is_some(),
                use_p0("accel", "µg"),
            ),
            (
                "imu.gyro_scale",
                m.gyro_scale.is_some(),
                no_state.to_owned(),
            ),
            (
                "imu.accel_scale",
                m.accel_scale.is_some(),
                no_state.to_owned(),
            ),
        ];
        if let Some((key, _, why)) = refused.into_iter().find(|(_, given, _)| *given) {
            return Err(self.err(key, why));
        }
        let vrw = match (m.accel_vrw, m.accel_vrw_ug_per_sqrt_hz) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    "imu.accel_vrw_ug_per_sqrt_hz",
                    "give either accel_vrw or accel_vrw_ug_per_sqrt_hz",
                ))
            }
            (Some(x), None) => self.sigma("imu.accel_vrw", x, m_s_per_sqrt_h, Zero::Absent)?,
            (None, Some(x)) => self.sigma("imu.accel_vrw_ug_per_sqrt_hz", x, ug, Zero::Absent)?,
            (None, None) => 0.0,
        };
        let z = Zero::Absent;
        let arw = match (m.gyro_arw, m.gyro_arw_deg_per_s_per_sqrt_hz) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    "imu.gyro_arw_deg_per_s_per_sqrt_hz",
                    "give either gyro_arw or gyro_arw_deg_per_s_per_sqrt_hz",
                ))
            }
            (Some(x), None) => self.sigma("imu.gyro_arw", x, deg_per_sqrt_h, z)?,
            // °/s/√Hz = °/√s.
            (None, Some(x)) => self.sigma("imu.gyro_arw_deg_per_s_per_sqrt_hz", x, deg, z)?,
            (None, None) => 0.0,
        };
        // Bias random walks, per √h in the datasheet: 1/√h = 1/60 per √s.
        let per_sqrt_h = |key: &str, x: Option<f64>, unit: fn(f64) -> f64, markov: f64| {
            let Some(x) = x else {
                return Ok(0.0);
            };
            if markov != 0.0 {
                return Err(self.err(
                    key,
                    "one bias model per sensor: a Gauss-Markov process (`*_markov_sigma`) or a \
                     random walk, not both",
                ));
            }
            self.sigma(key, x, unit, z).map(|v| v / 60.0)
        };
        Ok(ImuSpec {
            gyro_arw: arw,
            gyro_bias_rw: per_sqrt_h(
                "imu.gyro_bias_rw",
                m.gyro_bias_rw,
                deg_per_h,
                m.gyro_markov_sigma,
            )?,
            accel_bias_rw: per_sqrt_h(
                "imu.accel_bias_rw",
                m.accel_bias_rw,
                ug,
                m.accel_markov_sigma,
            )?,
            gyro_markov_sigma: self.sigma(
                "imu.gyro_markov_sigma",
                m.gyro_markov_sigma,
                deg_per_h,
                z,
            )?,
            gyro_markov_tau: self.tau("imu.gyro_markov_tau", m.gyro_markov_tau)?,
            accel_vrw: vrw,
            accel_markov_sigma: self.sigma(
                "imu.accel_markov_sigma",
                m.accel_markov_sigma,
                ug,
                z,
            )?,
            accel_markov_tau: self.tau("imu.accel_markov_tau", m.accel_markov_tau)?,
            ..ImuSpec::perfect()
        })
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
            min_speed: self.positive("alignment.min_speed", a.min_speed.unwrap_or(3.0))?,
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
            lever_arm: self.vec("nhc.lever_arm", n.lever_arm, Self::finite, id)?,
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
            accel_std: self.positive("zupt.accel_std", z.accel_std)?,
            gyro_std: deg(self.positive("zupt.gyro_std", z.gyro_std)?),
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
            max_speed: self.positive("zupt.max_speed", z.max_speed.unwrap_or(0.5))?,
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
            lever_arm: self.vec("odometer.lever_arm", o.lever_arm, Self::finite, id)?,
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
