//! The file as written: the tables and keys `process` reads, each table
//! refusing keys it does not know. The same types are what the writers of
//! `process` configurations fill in (`simulate`, the importers), so a
//! written file has exactly the keys a read file may have.

use super::*;
pub(crate) use crate::config::imu::ImuTable;
use crate::config::names::{EarthName, ErrorModelName};
pub(crate) use crate::config::p0::P0Table;
use serde::Serialize;

pub(crate) type V3 = Exact<3>;

/// An array of exactly `N` numbers: a longer or shorter one is an error at
/// its line and column, never truncated.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Exact<const N: usize>(pub(crate) [f64; N]);

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

impl<const N: usize> Serialize for Exact<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

/// The file as written.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct File {
    #[serde(default)]
    pub(crate) earth: EarthName,
    pub(crate) initial: Initial,
    #[serde(default)]
    pub(crate) imu: ImuTable,
    #[serde(default)]
    pub(crate) filter: Filter,
    #[serde(default)]
    pub(crate) gnss: Gnss,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) odometer: Option<Odometer>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) nhc: Option<Nhc>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) zupt: Option<Zupt>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) alignment: Option<Alignment>,
    #[serde(default)]
    pub(crate) output: Output,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) imu_file: Option<ImuFile>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gnss_file: Option<GnssFile>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) truth_file: Option<TruthFile>,
}

/// `[truth_file]`: the reference's format and where it is.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TruthFile {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) format: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) quality: Option<Vec<u8>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) at: Option<String>,
}

/// `[gnss_file]`: the GNSS file's format.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GnssFile {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) format: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) quality: Option<Vec<u8>>,
}

/// `[imu_file]`: how the IMU file is laid out (default: the GINS format).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ImuFile {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) delimiter: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) header_lines: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) columns: Option<ImuColumns>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) time: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) leap_seconds: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) measures: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gyro_unit: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) accel_unit: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) g: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) axes: Option<[String; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) mounting: Option<Exact<3>>,
}

/// `[imu_file.columns]`, 1-based.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ImuColumns {
    pub(crate) time: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) week: Option<usize>,
    pub(crate) gyro: [usize; 3],
    pub(crate) accel: [usize; 3],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) odometer: Option<usize>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Initial {
    #[serde(default)]
    pub(crate) week: u32,
    pub(crate) time: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) position: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) velocity: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) attitude: Option<V3>,
    /// Known sensor errors at the start (values, not σ): removed from the
    /// readings from the first sample; the filter estimates what is left.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gyro_bias: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) accel_bias: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gyro_scale: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) accel_scale: Option<V3>,
    pub(crate) std: P0Table,
}

/// `[filter]`: the error model, the covariance interval and the lever arm;
/// every other key is the filter kind's ([`read_kind`]). Read key by key
/// (not with `serde(flatten)`), so a wrong type keeps its line and column.
#[derive(Debug, Default)]
pub(crate) struct Filter {
    pub(crate) error_model: ErrorModelName,
    pub(crate) covariance_interval: Option<f64>,
    pub(crate) lever_arm: V3,
    pub(crate) kind: Keys,
}

impl Serialize for Filter {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(None)?;
        for (key, value) in &self.kind {
            map.serialize_entry(key, value)?;
        }
        map.serialize_entry("error_model", &self.error_model)?;
        if let Some(c) = self.covariance_interval {
            map.serialize_entry("covariance_interval", &c)?;
        }
        map.serialize_entry("lever_arm", &self.lever_arm)?;
        map.end()
    }
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

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Gnss {
    #[serde(default)]
    pub(crate) noise: GnssNoiseSource,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) position_std: Option<V3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) velocity_std: Option<V3>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Odometer {
    pub(crate) rate: f64,
    pub(crate) speed_std: f64,
    pub(crate) nhc_std: f64,
    #[serde(default)]
    pub(crate) mounting: Exact<2>,
    #[serde(default)]
    pub(crate) lever_arm: V3,
    pub(crate) scale_tau: f64,
    pub(crate) scale_sigma: f64,
}

/// The highest pseudo-measurement rate accepted, Hz (an update per IMU
/// sample of a 10 kHz IMU).
pub(crate) const MAX_RATE: f64 = 10_000.0;

/// `[alignment]`: the initial attitude from the data.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Alignment {
    pub(crate) static_time: f64,
    pub(crate) yaw: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) min_speed: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gyro_bias: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) max_accel_std: Option<f64>,
}

/// `[nhc]`: the non-holonomic constraint without an odometer.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Nhc {
    pub(crate) rate: f64,
    pub(crate) std: Exact<2>,
    #[serde(default)]
    pub(crate) mounting: Exact<2>,
    #[serde(default)]
    pub(crate) lever_arm: V3,
}

/// `[zupt]`: zero-velocity (and zero-angular-rate) updates at detected
/// standstill.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Zupt {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) window: Option<f64>,
    pub(crate) accel_std: f64,
    pub(crate) gyro_std: f64,
    pub(crate) rate: f64,
    pub(crate) velocity_std: f64,
    #[serde(default)]
    pub(crate) angular_rate_std: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) max_speed: Option<f64>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Output {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) interval: Option<f64>,
    #[serde(default)]
    pub(crate) position_axes: PositionAxes,
}

/// `[gnss] noise`: where R comes from.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum GnssNoiseSource {
    /// The σ on each line of the GNSS file.
    #[default]
    File,
    /// `position_std` and `velocity_std`.
    Fixed,
}
