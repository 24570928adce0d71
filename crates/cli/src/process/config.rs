//! The process configuration file (TOML): what the filter is told about
//! the start, the IMU, the GNSS antenna and receiver, the odometer and the
//! output. `crates/cli/configs/process-example.toml` documents every key.

use std::path::Path;

use kestrel::nav::experiment::PositionAxes;
use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::scenario::{ErrorModelKind, FadeBlock, FilterKind, InitialUncertainty};
use kestrel::nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
use serde::Deserialize;

use super::timing::{LongGap, TimingRule};
use super::units::{deg, deg_per_h, deg_per_sqrt_h, m_s_per_sqrt_h, ppm, ug};
use crate::{CliError, InputError};

type V3 = [f64; 3];

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    earth: Option<String>,
    initial: Initial,
    #[serde(default)]
    imu: Imu,
    #[serde(default)]
    filter: Filter,
    #[serde(default)]
    gnss: Gnss,
    odometer: Option<Odometer>,
    #[serde(default)]
    output: Output,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Initial {
    #[serde(default)]
    week: u32,
    time: f64,
    position: V3,
    #[serde(default)]
    velocity: V3,
    attitude: V3,
    std: InitialStd,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct InitialStd {
    attitude: V3,
    velocity: V3,
    position: V3,
    #[serde(default)]
    gyro_bias: V3,
    #[serde(default)]
    gyro_markov: V3,
    #[serde(default)]
    accel_bias: V3,
    #[serde(default)]
    odometer_scale: f64,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Imu {
    #[serde(default)]
    gyro_arw: f64,
    accel_vrw: Option<f64>,
    accel_vrw_ug_per_sqrt_hz: Option<f64>,
    #[serde(default)]
    gyro_bias: f64,
    #[serde(default)]
    accel_bias: f64,
    #[serde(default)]
    gyro_markov_sigma: f64,
    gyro_markov_tau: Option<f64>,
    #[serde(default)]
    accel_markov_sigma: f64,
    accel_markov_tau: Option<f64>,
    #[serde(default)]
    gyro_scale: f64,
    #[serde(default)]
    accel_scale: f64,
    max_gap: Option<f64>,
    long_gap: Option<String>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Filter {
    kind: Option<String>,
    error_model: Option<String>,
    covariance_interval: Option<f64>,
    #[serde(default)]
    lever_arm: V3,
    significance: Option<f64>,
    forgetting: Option<f64>,
    reserve: Option<f64>,
    lambda_max: Option<f64>,
    rho: Option<f64>,
    softening: Option<f64>,
    threshold: Option<f64>,
    window: Option<usize>,
    fade_states: Option<String>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Gnss {
    noise: Option<String>,
    position_std: Option<V3>,
    velocity_std: Option<V3>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Odometer {
    rate: f64,
    speed_std: f64,
    nhc_std: f64,
    #[serde(default)]
    mounting: [f64; 2],
    scale_tau: f64,
    scale_sigma: f64,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Output {
    interval: Option<f64>,
    position_axes: Option<String>,
}

/// Where the GNSS `R` comes from: `Reported` is `noise = "file"` (the σ
/// each line of the GNSS file reports).
pub use kestrel::nav::experiment::GnssNoise;

/// Odometer aiding (the IMU file's 8th column).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometerSettings {
    /// Update rate, Hz: updates at the IMU samples reaching `k / rate` s.
    pub rate: f64,
    /// σ of the forward speed, m/s.
    pub speed_std: f64,
    /// σ of the non-holonomic constraints, m/s.
    pub nhc_std: f64,
    /// Mounting pitch and yaw of the odometer against the IMU, rad.
    pub mounting: [f64; 2],
    /// Steady-state σ of the scale-factor Markov process (ratio).
    pub scale_sigma: f64,
}

/// A validated configuration in SI units.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The Earth model.
    pub earth: Ellipsoid,
    /// GNSS week of the output.
    pub week: u32,
    /// The initial navigation state (time in seconds of week).
    pub start: NavState,
    /// P0 as standard deviations.
    pub p0: InitialUncertainty,
    /// The filter's IMU error model.
    pub imu: ImuSpec,
    /// The error-state model.
    pub error_model: ErrorModelKind,
    /// The filter (adapter or odometer processing).
    pub kind: FilterKind,
    /// Covariance propagation interval, s.
    pub covariance_interval: f64,
    /// GNSS antenna lever arm, body forward-right-down, m.
    pub lever_arm: Vector3<f64>,
    /// GNSS `R`.
    pub gnss_noise: GnssNoise,
    /// Odometer aiding, if configured.
    pub odometer: Option<OdometerSettings>,
    /// Output interval, s (0: every IMU sample).
    pub output_interval: f64,
    /// Axes of the position errors.
    pub axes: PositionAxes,
    /// The treatment of gaps in the IMU data.
    pub timing: TimingRule,
}

/// Reads and validates the configuration at `path`.
///
/// # Errors
/// [`CliError::Input`] naming the file and the line and column (syntax,
/// unknown or missing key, wrong type) or the key (value out of range).
pub fn load(path: &Path) -> Result<Settings, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::file(path, format!("cannot read the file: {e}")))?;
    parse(&text, path)
}

/// As [`load`] from the text of the file.
///
/// # Errors
/// As [`load`].
///
/// ```
/// let text = "[initial]\ntime = 0\nposition = [30, 114, 20]\nattitude = [0, 0, 0]\n\
///     [initial.std]\nattitude = [1, 1, 1]\nvelocity = [1, 1, 1]\nposition = [1, 1, 1]\n\
///     [filter]\nkind = \"ekf\"\nrho = 0.5\n";
/// let e = kestrel_cli::process::config::parse(text, "p.toml".as_ref()).unwrap_err();
/// assert_eq!(e.to_string(), "p.toml: key `filter.rho`: not a parameter of kind `ekf`");
/// ```
pub fn parse(text: &str, path: &Path) -> Result<Settings, CliError> {
    let file: File = toml::from_str(text).map_err(|e| syntax(text, path, &e))?;
    Check { path }.settings(file).map_err(CliError::from)
}

/// A TOML error with its line and column.
fn syntax(text: &str, path: &Path, e: &toml::de::Error) -> CliError {
    let msg = e.message().trim().replace('\n', " ");
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            InputError::at(path, line, column, msg).into()
        }
        None => InputError::file(path, msg).into(),
    }
}

struct Check<'a> {
    path: &'a Path,
}

impl Check<'_> {
    fn err(&self, key: &str, msg: impl Into<String>) -> InputError {
        InputError::file(self.path, msg).with_key(key)
    }

    fn finite(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite number, found {x}")))
        }
    }

    fn non_negative(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() && x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value ≥ 0, found {x}")))
        }
    }

    fn positive(&self, key: &str, x: f64) -> Result<f64, InputError> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value > 0, found {x}")))
        }
    }

    fn range(&self, key: &str, x: f64, lo: f64, hi: f64) -> Result<f64, InputError> {
        if x > lo && x < hi {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a value in ({lo}, {hi}), found {x}")))
        }
    }

    fn at_least(&self, key: &str, x: f64, lo: f64) -> Result<f64, InputError> {
        if x.is_finite() && x >= lo {
            Ok(x)
        } else {
            Err(self.err(key, format!("expected a finite value ≥ {lo}, found {x}")))
        }
    }

    /// A correlation time: positive, `inf` (or absent) for none.
    fn tau(&self, key: &str, x: Option<f64>) -> Result<f64, InputError> {
        match x {
            None => Ok(f64::INFINITY),
            Some(t) if t > 0.0 => Ok(t),
            Some(t) => Err(self.err(key, format!("expected a time > 0 s (or inf), found {t}"))),
        }
    }

    fn vec(
        &self,
        key: &str,
        v: V3,
        each: impl Fn(&Self, &str, f64) -> Result<f64, InputError>,
        unit: impl Fn(f64) -> f64,
    ) -> Result<Vector3<f64>, InputError> {
        let mut out = Vector3::zeros();
        for (i, x) in v.iter().enumerate() {
            out[i] = unit(each(self, &format!("{key}[{i}]"), *x)?);
        }
        Ok(out)
    }

    fn settings(&self, f: File) -> Result<Settings, InputError> {
        let id = |x: f64| x;
        let i = &f.initial;
        let [lat, lon, h] = i.position;
        if lat.is_nan() || lat.abs() > 90.0 {
            return Err(self.err(
                "initial.position[0]",
                format!("expected a latitude in [-90, 90] deg, found {lat}"),
            ));
        }
        self.finite("initial.position[1]", lon)?;
        self.finite("initial.position[2]", h)?;
        let att = self.vec("initial.attitude", i.attitude, Self::finite, deg)?;
        let start = NavState::new(
            self.non_negative("initial.time", i.time)?,
            Geodetic::new(deg(lat), deg(lon), h),
            self.vec("initial.velocity", i.velocity, Self::finite, id)?,
            Euler::new(att.x, att.y, att.z),
        );
        let s = &i.std;
        let p0 = InitialUncertainty {
            attitude: self.vec("initial.std.attitude", s.attitude, Self::positive, deg)?,
            velocity: self.vec("initial.std.velocity", s.velocity, Self::positive, id)?,
            position: self.vec("initial.std.position", s.position, Self::positive, id)?,
            gyro_bias: self.vec(
                "initial.std.gyro_bias",
                s.gyro_bias,
                Self::non_negative,
                deg_per_h,
            )?,
            gyro_markov: self.vec(
                "initial.std.gyro_markov",
                s.gyro_markov,
                Self::non_negative,
                deg_per_h,
            )?,
            accel_bias: self.vec(
                "initial.std.accel_bias",
                s.accel_bias,
                Self::non_negative,
                ug,
            )?,
            odometer_scale: self.non_negative("initial.std.odometer_scale", s.odometer_scale)?,
        };
        let imu = self.imu(&f.imu)?;
        let odometer = f.odometer.as_ref().map(|o| self.odometer(o)).transpose()?;
        let error_model = match f.filter.error_model.as_deref().unwrap_or("ins15") {
            "ins15" => ErrorModelKind::Ins15,
            "ins18" => ErrorModelKind::Ins18,
            "odometer16" => match &f.odometer {
                Some(o) => ErrorModelKind::Odometer16 {
                    scale_tau: self.positive("odometer.scale_tau", o.scale_tau)?,
                },
                None => {
                    return Err(self.err(
                        "filter.error_model",
                        "`odometer16` needs an [odometer] table",
                    ))
                }
            },
            other => {
                return Err(self.err(
                    "filter.error_model",
                    format!("expected `ins15`, `ins18` or `odometer16`, found `{other}`"),
                ))
            }
        };
        if odometer.is_some() && !matches!(error_model, ErrorModelKind::Odometer16 { .. }) {
            return Err(self.err(
                "filter.error_model",
                "odometer aiding needs error_model = `odometer16`",
            ));
        }
        let kind = self.kind(&f.filter, error_model)?;
        let gnss_noise = match f.gnss.noise.as_deref().unwrap_or("file") {
            "file" => {
                if f.gnss.position_std.is_some() || f.gnss.velocity_std.is_some() {
                    return Err(self.err("gnss.noise", "fixed σ given but noise = `file`"));
                }
                GnssNoise::Reported
            }
            "fixed" => {
                let (Some(p), Some(v)) = (f.gnss.position_std, f.gnss.velocity_std) else {
                    return Err(
                        self.err("gnss.noise", "`fixed` needs position_std and velocity_std")
                    );
                };
                GnssNoise::Fixed {
                    position: self.vec("gnss.position_std", p, Self::positive, id)?,
                    velocity: self.vec("gnss.velocity_std", v, Self::positive, id)?,
                }
            }
            other => {
                return Err(self.err(
                    "gnss.noise",
                    format!("expected `file` or `fixed`, found `{other}`"),
                ))
            }
        };
        let axes = match f.output.position_axes.as_deref().unwrap_or("ned") {
            "ned" => PositionAxes::NorthEastDown,
            "enu" => PositionAxes::EastNorthUp,
            other => {
                return Err(self.err(
                    "output.position_axes",
                    format!("expected `ned` or `enu`, found `{other}`"),
                ))
            }
        };
        let earth = match f.earth.as_deref().unwrap_or("wgs84") {
            "wgs84" => Ellipsoid::wgs84(),
            "grs80" => Ellipsoid::grs80(),
            "krasovsky" => Ellipsoid::krasovsky(),
            other => {
                return Err(self.err(
                    "earth",
                    format!("expected `wgs84`, `grs80` or `krasovsky`, found `{other}`"),
                ))
            }
        };
        Ok(Settings {
            earth,
            week: i.week,
            start,
            p0,
            imu,
            error_model,
            kind,
            covariance_interval: self.non_negative(
                "filter.covariance_interval",
                f.filter.covariance_interval.unwrap_or(0.1),
            )?,
            lever_arm: self.vec("filter.lever_arm", f.filter.lever_arm, Self::finite, id)?,
            gnss_noise,
            odometer,
            output_interval: self
                .non_negative("output.interval", f.output.interval.unwrap_or(0.0))?,
            axes,
            timing: self.timing(&f.imu)?,
        })
    }

    /// `[imu] max_gap` (s, > 0, default 1) and `long_gap` (`"error"`,
    /// the default, or `"coast"`).
    fn timing(&self, m: &Imu) -> Result<TimingRule, InputError> {
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

    fn imu(&self, m: &Imu) -> Result<ImuSpec, InputError> {
        let vrw = match (m.accel_vrw, m.accel_vrw_ug_per_sqrt_hz) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    "imu.accel_vrw_ug_per_sqrt_hz",
                    "give either accel_vrw or accel_vrw_ug_per_sqrt_hz",
                ))
            }
            (Some(x), None) => m_s_per_sqrt_h(self.non_negative("imu.accel_vrw", x)?),
            (None, Some(x)) => ug(self.non_negative("imu.accel_vrw_ug_per_sqrt_hz", x)?),
            (None, None) => 0.0,
        };
        Ok(ImuSpec {
            gyro_bias: deg_per_h(self.non_negative("imu.gyro_bias", m.gyro_bias)?),
            gyro_arw: deg_per_sqrt_h(self.non_negative("imu.gyro_arw", m.gyro_arw)?),
            gyro_markov_sigma: deg_per_h(
                self.non_negative("imu.gyro_markov_sigma", m.gyro_markov_sigma)?,
            ),
            gyro_markov_tau: self.tau("imu.gyro_markov_tau", m.gyro_markov_tau)?,
            accel_bias: ug(self.non_negative("imu.accel_bias", m.accel_bias)?),
            accel_vrw: vrw,
            accel_markov_sigma: ug(
                self.non_negative("imu.accel_markov_sigma", m.accel_markov_sigma)?
            ),
            accel_markov_tau: self.tau("imu.accel_markov_tau", m.accel_markov_tau)?,
            gyro_scale: ppm(self.finite("imu.gyro_scale", m.gyro_scale)?),
            accel_scale: ppm(self.finite("imu.accel_scale", m.accel_scale)?),
        })
    }

    fn odometer(&self, o: &Odometer) -> Result<OdometerSettings, InputError> {
        Ok(OdometerSettings {
            rate: self.positive("odometer.rate", o.rate)?,
            speed_std: self.positive("odometer.speed_std", o.speed_std)?,
            nhc_std: self.positive("odometer.nhc_std", o.nhc_std)?,
            mounting: [
                deg(self.finite("odometer.mounting[0]", o.mounting[0])?),
                deg(self.finite("odometer.mounting[1]", o.mounting[1])?),
            ],
            scale_sigma: self.non_negative("odometer.scale_sigma", o.scale_sigma)?,
        })
    }

    fn kind(&self, f: &Filter, model: ErrorModelKind) -> Result<FilterKind, InputError> {
        let name = f.kind.as_deref().unwrap_or("ekf");
        let odometer = matches!(model, ErrorModelKind::Odometer16 { .. });
        // Which optional parameters each kind takes.
        let takes: &[&str] = match name {
            "ekf" => &[],
            "ict-erekf" => &["significance"],
            "sage-husa-fading" => &["forgetting", "reserve", "lambda_max", "fade_states"],
            "improved-adaptive" => &[
                "forgetting",
                "reserve",
                "lambda_max",
                "significance",
                "fade_states",
            ],
            "fading" => &["rho", "softening", "lambda_max", "fade_states"],
            "max-threshold" => &["threshold"],
            "fuzzy-adaptive" => &["window"],
            other => {
                return Err(self.err(
                    "filter.kind",
                    format!(
                        "expected `ekf`, `ict-erekf`, `sage-husa-fading`, `improved-adaptive`, \
                         `fading`, `max-threshold` or `fuzzy-adaptive`, found `{other}`"
                    ),
                ))
            }
        };
        let given = [
            ("significance", f.significance.is_some()),
            ("forgetting", f.forgetting.is_some()),
            ("reserve", f.reserve.is_some()),
            ("lambda_max", f.lambda_max.is_some()),
            ("rho", f.rho.is_some()),
            ("softening", f.softening.is_some()),
            ("threshold", f.threshold.is_some()),
            ("window", f.window.is_some()),
            ("fade_states", f.fade_states.is_some()),
        ];
        if let Some((k, _)) = given.iter().find(|(k, g)| *g && !takes.contains(k)) {
            return Err(self.err(
                &format!("filter.{k}"),
                format!("not a parameter of kind `{name}`"),
            ));
        }
        let odometer_kind = matches!(name, "max-threshold" | "fuzzy-adaptive");
        if odometer_kind && !odometer {
            return Err(self.err(
                "filter.kind",
                format!("`{name}` needs error_model = `odometer16`"),
            ));
        }
        if odometer && !matches!(name, "ekf" | "max-threshold" | "fuzzy-adaptive") {
            return Err(self.err(
                "filter.kind",
                format!(
                    "`odometer16` runs `ekf`, `max-threshold` or `fuzzy-adaptive`, not `{name}`"
                ),
            ));
        }
        let sig = |d| self.range("filter.significance", f.significance.unwrap_or(d), 0.0, 1.0);
        let forgetting = || self.range("filter.forgetting", f.forgetting.unwrap_or(0.97), 0.0, 1.0);
        let reserve = || self.at_least("filter.reserve", f.reserve.unwrap_or(1.0), 1.0);
        let lambda_max = || self.at_least("filter.lambda_max", f.lambda_max.unwrap_or(10.0), 1.0);
        let fade_name = f.fade_states.as_deref().unwrap_or("all");
        let Some(fade_states) = FadeBlock::from_name(fade_name) else {
            return Err(self.err(
                "filter.fade_states",
                format!(
                    "expected `all`, `velocity-position` or `attitude-velocity-position`, \
                     found `{fade_name}`"
                ),
            ));
        };
        Ok(match name {
            "ict-erekf" => FilterKind::IctErekf {
                significance: sig(0.05)?,
            },
            "sage-husa-fading" => FilterKind::SageHusaFading {
                forgetting: forgetting()?,
                reserve: reserve()?,
                lambda_max: lambda_max()?,
                fade_states,
            },
            "improved-adaptive" => FilterKind::ImprovedAdaptive {
                forgetting: forgetting()?,
                reserve: reserve()?,
                lambda_max: lambda_max()?,
                significance: sig(0.05)?,
                fade_states,
            },
            "fading" => {
                let rho = f.rho.unwrap_or(0.95);
                if !(rho > 0.0 && rho <= 1.0) {
                    return Err(self.err(
                        "filter.rho",
                        format!("expected a value in (0, 1], found {rho}"),
                    ));
                }
                FilterKind::StrongTrackingFading {
                    rho,
                    softening: self.at_least(
                        "filter.softening",
                        f.softening.unwrap_or(1.0),
                        1.0,
                    )?,
                    lambda_max: match f.lambda_max {
                        None => f64::INFINITY,
                        Some(l) if l >= 1.0 => l,
                        Some(l) => {
                            return Err(self.err(
                                "filter.lambda_max",
                                format!("expected a value ≥ 1 (or inf), found {l}"),
                            ))
                        }
                    },
                    fade_states,
                }
            }
            "max-threshold" => FilterKind::MaxThreshold {
                threshold: self.positive("filter.threshold", f.threshold.unwrap_or(1.0))?,
            },
            "fuzzy-adaptive" => {
                let window = f.window.unwrap_or(20);
                if ![10, 20, 50].contains(&window) {
                    return Err(self.err(
                        "filter.window",
                        format!("expected 10, 20 or 50, found {window}"),
                    ));
                }
                FilterKind::FuzzyAdaptive { window }
            }
            _ => FilterKind::Standard,
        })
    }
}
