//! The sensor tables of the file: `[imu]` (also `[filter.imu]`), `[gnss]`,
//! `[odometer]`, `[attitude]`.

use serde::Deserialize;

use crate::config::vec3::V3;

pub(super) use crate::config::imu::ImuTable as ImuSection;

/// What the receiver reports as σ.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(super) enum ReportedName {
    Nominal,
    #[default]
    Actual,
}

/// `[gnss]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GnssSection {
    pub rate_hz: f64,
    pub position_std_m: V3,
    pub velocity_std_m_s: Option<V3>,
    pub lever_arm_m: Option<V3>,
    #[serde(default)]
    pub reported_std: ReportedName,
    #[serde(default)]
    pub noise_window: Vec<NoiseWindowEntry>,
    #[serde(default)]
    pub outlier: Vec<OutlierEntry>,
    #[serde(default)]
    pub outage: Vec<WindowEntry>,
}

/// A bare time window: `start_s` and `end_s` or `duration_s`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct WindowEntry {
    pub start_s: f64,
    pub end_s: Option<f64>,
    pub duration_s: Option<f64>,
}

/// `[[gnss.noise_window]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct NoiseWindowEntry {
    pub start_s: f64,
    pub end_s: Option<f64>,
    pub duration_s: Option<f64>,
    pub position_std_m: Option<V3>,
    pub velocity_std_m_s: Option<V3>,
}

/// Outlier types.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum OutlierType {
    Patch,
    Spikes,
    Multipath,
}

/// `[[gnss.outlier]]`: the keys a type takes are checked when converting.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OutlierEntry {
    #[serde(rename = "type")]
    pub kind: OutlierType,
    pub start_s: f64,
    pub end_s: Option<f64>,
    pub duration_s: Option<f64>,
    pub position_offset_m: Option<V3>,
    pub position_amplitude_m: Option<V3>,
    pub velocity_offset_m_s: Option<V3>,
    pub velocity_amplitude_m_s: Option<V3>,
    pub probability: Option<f64>,
    pub position_error_m: Option<[f64; 2]>,
    pub velocity_error_m_s: Option<[f64; 2]>,
    pub onset_probability: Option<f64>,
    pub burst_duration_s: Option<[f64; 2]>,
    pub rise_s: Option<f64>,
    pub position_bias_m: Option<V3>,
    pub position_jitter_m: Option<V3>,
    pub velocity_bias_m_s: Option<V3>,
    pub velocity_jitter_m_s: Option<V3>,
}

/// `[odometer]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OdometerSection {
    pub rate_hz: f64,
    pub scale_error_ppm: Option<f64>,
    pub scale_error_percent: Option<f64>,
    pub scale_markov_ppm: Option<f64>,
    pub scale_markov_percent: Option<f64>,
    pub scale_markov_tau_s: Option<f64>,
    #[serde(default)]
    pub noise_std_m_s: f64,
    pub lever_arm_m: Option<V3>,
    #[serde(default)]
    pub fault: Vec<FaultEntry>,
}

/// Odometer fault types.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum FaultType {
    Factor,
    RandomFactor,
    Offset,
}

/// `[[odometer.fault]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FaultEntry {
    #[serde(rename = "type")]
    pub kind: FaultType,
    pub start_s: f64,
    pub end_s: Option<f64>,
    pub duration_s: Option<f64>,
    pub factor: Option<f64>,
    pub min_factor: Option<f64>,
    pub max_factor: Option<f64>,
    pub offset_m_s: Option<f64>,
}

/// `[attitude]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AttitudeSection {
    pub rate_hz: f64,
    pub std_deg: Option<V3>,
    pub std_arcmin: Option<V3>,
    pub std_arcsec: Option<V3>,
}
