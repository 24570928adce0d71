//! The file as written: the tables and keys `process` reads, each table
//! refusing keys it does not know.

use super::*;
use crate::config::names::{EarthName, ErrorModelName};

pub(super) type V3 = Exact<3>;

/// An array of exactly `N` numbers: a longer or shorter one is an error at
/// its line and column, never truncated.
#[derive(Clone, Copy, Debug)]
pub(super) struct Exact<const N: usize>(pub(super) [f64; N]);

impl<const N: usize> Default for Exact<N> {
    fn default() -> Self {
        Self([0.0; N])
    }
}

impl<'de, const N: usize> Deserialize<'de> for Exact<N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Count(usize);
        impl serde::de::Expected for Count {
            fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of exactly {} numbers", self.0)
            }
        }
        let v = Vec::<f64>::deserialize(d)?;
        <[f64; N]>::try_from(v.as_slice())
            .map(Exact)
            .map_err(|_| serde::de::Error::invalid_length(v.len(), &Count(N)))
    }
}

/// A key `process` reads but cannot honour: any value is an error that
/// says what to use instead.
#[derive(Debug)]
pub(super) struct Refused;

impl<'de> Deserialize<'de> for Refused {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        serde::de::IgnoredAny::deserialize(d).map(|_| Refused)
    }
}

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct File {
    #[serde(default)]
    pub(super) earth: EarthName,
    pub(super) initial: Initial,
    #[serde(default)]
    pub(super) imu: Imu,
    #[serde(default)]
    pub(super) filter: Filter,
    #[serde(default)]
    pub(super) gnss: Gnss,
    pub(super) odometer: Option<Odometer>,
    pub(super) nhc: Option<Nhc>,
    pub(super) zupt: Option<Zupt>,
    pub(super) alignment: Option<Alignment>,
    #[serde(default)]
    pub(super) output: Output,
    pub(super) imu_file: Option<ImuFile>,
    pub(super) gnss_file: Option<GnssFile>,
    pub(super) truth_file: Option<TruthFile>,
}

/// `[truth_file]`: the reference's format and where it is.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TruthFile {
    pub(super) format: Option<String>,
    pub(super) quality: Option<Vec<u8>>,
    pub(super) at: Option<String>,
}

/// The reference's format.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum TruthFormat {
    /// The navigation format (position, velocity, attitude).
    #[default]
    Nav,
    /// RTKLIB `.pos` of a better receiver: position only.
    Rtklib {
        /// The accepted `Q` flags.
        quality: Vec<u8>,
    },
}

/// How the reference is read and compared.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TruthSettings {
    /// Its format.
    pub format: TruthFormat,
    /// Whether its positions are the GNSS antenna's (else the IMU's): the
    /// solution is then moved by the lever arm before comparing.
    pub at_antenna: bool,
}

/// `[gnss_file]`: the GNSS file's format.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GnssFile {
    pub(super) format: Option<String>,
    pub(super) quality: Option<Vec<u8>>,
}

/// The GNSS file's format.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum GnssFormat {
    /// The GINS text format (7 or 13 columns).
    #[default]
    Gins,
    /// RTKLIB `.pos`, keeping the fixes whose quality flag `Q` is listed.
    Rtklib {
        /// The accepted `Q` values (1 fix, 2 float, 3 SBAS, 4 DGPS, 5 single,
        /// 6 PPP).
        quality: Vec<u8>,
    },
}

/// `[imu_file]`: how the IMU file is laid out (default: the GINS format).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ImuFile {
    pub(super) delimiter: Option<String>,
    pub(super) header_lines: Option<usize>,
    pub(super) columns: Option<ImuColumns>,
    pub(super) time: Option<String>,
    pub(super) leap_seconds: Option<f64>,
    pub(super) measures: Option<String>,
    pub(super) gyro_unit: Option<String>,
    pub(super) accel_unit: Option<String>,
    pub(super) g: Option<f64>,
    pub(super) axes: Option<[String; 3]>,
    pub(super) mounting: Option<Exact<3>>,
}

/// `[imu_file.columns]`, 1-based.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ImuColumns {
    pub(super) time: usize,
    pub(super) week: Option<usize>,
    pub(super) gyro: [usize; 3],
    pub(super) accel: [usize; 3],
    pub(super) odometer: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Initial {
    #[serde(default)]
    pub(super) week: u32,
    pub(super) time: f64,
    pub(super) position: Option<V3>,
    pub(super) velocity: Option<V3>,
    pub(super) attitude: Option<V3>,
    /// Known sensor errors at the start (values, not σ): removed from the
    /// readings from the first sample; the filter estimates what is left.
    pub(super) gyro_bias: Option<V3>,
    pub(super) accel_bias: Option<V3>,
    pub(super) gyro_scale: Option<V3>,
    pub(super) accel_scale: Option<V3>,
    pub(super) std: InitialStd,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InitialStd {
    pub(super) attitude: V3,
    pub(super) velocity: V3,
    pub(super) position: V3,
    #[serde(default)]
    pub(super) gyro_bias: V3,
    #[serde(default)]
    pub(super) gyro_markov: V3,
    #[serde(default)]
    pub(super) accel_bias: V3,
    #[serde(default)]
    pub(super) odometer_scale: f64,
    #[serde(default)]
    pub(super) gyro_scale: V3,
    #[serde(default)]
    pub(super) accel_scale: V3,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Imu {
    pub(super) gyro_arw: Option<f64>,
    pub(super) gyro_arw_deg_per_s_per_sqrt_hz: Option<f64>,
    pub(super) gyro_bias_rw: Option<f64>,
    pub(super) accel_bias_rw: Option<f64>,
    pub(super) accel_vrw: Option<f64>,
    pub(super) accel_vrw_ug_per_sqrt_hz: Option<f64>,
    pub(super) gyro_bias: Option<Refused>,
    pub(super) accel_bias: Option<Refused>,
    #[serde(default)]
    pub(super) gyro_markov_sigma: f64,
    pub(super) gyro_markov_tau: Option<f64>,
    #[serde(default)]
    pub(super) accel_markov_sigma: f64,
    pub(super) accel_markov_tau: Option<f64>,
    pub(super) gyro_scale: Option<Refused>,
    pub(super) accel_scale: Option<Refused>,
    pub(super) scale_tau: Option<f64>,
    pub(super) gyro_scale_sigma: Option<f64>,
    pub(super) accel_scale_sigma: Option<f64>,
    pub(super) max_gap: Option<f64>,
    pub(super) long_gap: Option<String>,
}

/// `[filter]`: the error model, the covariance interval and the lever arm;
/// every other key is the filter kind's ([`read_kind`]). Read key by key
/// (not with `serde(flatten)`), so a wrong type keeps its line and column.
#[derive(Debug, Default)]
pub(super) struct Filter {
    pub(super) error_model: ErrorModelName,
    pub(super) covariance_interval: Option<f64>,
    pub(super) lever_arm: V3,
    pub(super) kind: Keys,
}

impl<'de> Deserialize<'de> for Filter {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Table;
        impl<'de> serde::de::Visitor<'de> for Table {
            type Value = Filter;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("the [filter] table")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Filter, A::Error> {
                let mut out = Filter::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "error_model" => out.error_model = map.next_value()?,
                        "covariance_interval" => out.covariance_interval = Some(map.next_value()?),
                        "lever_arm" => out.lever_arm = map.next_value()?,
                        _ => {
                            let value = map.next_value()?;
                            out.kind.insert(key, value);
                        }
                    }
                }
                Ok(out)
            }
        }
        d.deserialize_map(Table)
    }
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Gnss {
    #[serde(default)]
    pub(super) noise: GnssNoiseSource,
    pub(super) position_std: Option<V3>,
    pub(super) velocity_std: Option<V3>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Odometer {
    pub(super) rate: f64,
    pub(super) speed_std: f64,
    pub(super) nhc_std: f64,
    #[serde(default)]
    pub(super) mounting: Exact<2>,
    #[serde(default)]
    pub(super) lever_arm: V3,
    pub(super) scale_tau: f64,
    pub(super) scale_sigma: f64,
}

/// The highest pseudo-measurement rate accepted, Hz (an update per IMU
/// sample of a 10 kHz IMU).
pub(super) const MAX_RATE: f64 = 10_000.0;

/// `[alignment]`: the initial attitude from the data.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Alignment {
    pub(super) static_time: f64,
    pub(super) yaw: String,
    pub(super) min_speed: Option<f64>,
    pub(super) gyro_bias: Option<bool>,
    pub(super) max_accel_std: Option<f64>,
}

/// `[nhc]`: the non-holonomic constraint without an odometer.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Nhc {
    pub(super) rate: f64,
    pub(super) std: Exact<2>,
    #[serde(default)]
    pub(super) mounting: Exact<2>,
    #[serde(default)]
    pub(super) lever_arm: V3,
}

/// `[zupt]`: zero-velocity (and zero-angular-rate) updates at detected
/// standstill.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Zupt {
    pub(super) window: Option<f64>,
    pub(super) accel_std: f64,
    pub(super) gyro_std: f64,
    pub(super) rate: f64,
    pub(super) velocity_std: f64,
    #[serde(default)]
    pub(super) angular_rate_std: f64,
    pub(super) max_speed: Option<f64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Output {
    pub(super) interval: Option<f64>,
    #[serde(default)]
    pub(super) position_axes: PositionAxes,
}

/// `[gnss] noise`: where R comes from.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(super) enum GnssNoiseSource {
    /// The σ on each line of the GNSS file.
    #[default]
    File,
    /// `position_std` and `velocity_std`.
    Fixed,
}
