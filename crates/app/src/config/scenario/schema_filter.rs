//! The estimation tables of the file: `[filter]` (shared set-up) and
//! `[[filters]]` (the filters compared).

use serde::Deserialize;

pub(super) use crate::config::names::ErrorModelName;
use crate::config::p0::P0Table;
use crate::scenario::MeasurementKind;

use super::schema_sensors::ImuSection;
use crate::config::vec3::V3;

/// `[filter]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FilterSection {
    pub error_model: ErrorModelName,
    pub odometer_scale_tau_s: Option<f64>,
    pub scale_tau_s: Option<f64>,
    pub measurement: MeasurementKind,
    pub lever_arm_m: Option<V3>,
    pub odometer_mounting_deg: Option<[f64; 2]>,
    #[serde(default)]
    pub imu: ImuSection,
    #[serde(default)]
    pub p0: P0Table,
    #[serde(default)]
    pub r: RSection,
}

/// `[filter.r]`: measurement standard deviations.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RSection {
    pub position_m: Option<V3>,
    pub velocity_m_s: Option<V3>,
    pub attitude_deg: Option<V3>,
    pub attitude_arcmin: Option<V3>,
    pub attitude_arcsec: Option<V3>,
    pub odometer_m_s: Option<V3>,
}
