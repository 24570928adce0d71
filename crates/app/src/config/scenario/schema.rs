//! The file's layout: mirror structs of the scenario with unit-explicit
//! keys. Every table rejects keys it does not know.

use serde::Deserialize;

use super::schema_filter::FilterSection;
use super::schema_sensors::{AttitudeSection, GnssSection, ImuSection, OdometerSection};
use crate::config::filter::Keys;
use crate::config::names::EarthName;
use crate::config::vec3::V3;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ScenarioFile {
    pub scenario: Header,
    pub trajectory: TrajectorySection,
    pub imu: ImuSection,
    pub gnss: Option<GnssSection>,
    pub odometer: Option<OdometerSection>,
    pub attitude: Option<AttitudeSection>,
    #[serde(default)]
    pub initial_errors: InitialErrorsSection,
    pub filter: FilterSection,
    pub filters: Vec<Keys>,
}

/// `[scenario]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Header {
    pub name: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub seed: u64,
    #[serde(default)]
    pub earth: EarthName,
    pub earth_a_m: Option<f64>,
    pub earth_flattening: Option<f64>,
    pub earth_omega_rad_s: Option<f64>,
    pub earth_gm_m3_s2: Option<f64>,
}

/// The vehicle kinds.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(super) enum VehicleName {
    Aircraft,
    Ground,
}

/// `[trajectory]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TrajectorySection {
    pub vehicle: VehicleName,
    pub start_lat_deg: f64,
    pub start_lon_deg: f64,
    pub start_height_m: f64,
    #[serde(default)]
    pub heading_deg: f64,
    #[serde(default)]
    pub speed_m_s: f64,
    pub edge_s: Option<f64>,
    pub pitch_transition_s: Option<f64>,
    pub mounting_deg: Option<[f64; 3]>,
    #[serde(default)]
    pub segment: Vec<SegmentEntry>,
}

/// The segment types.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum SegmentType {
    Cruise,
    CruiseUntil,
    Stationary,
    Accelerate,
    AccelerateTo,
    Stop,
    Climb,
    Turn,
    SideSlip,
    Parallel,
}

/// One `[[trajectory.segment]]` (or one of a parallel segment's `parts`):
/// the keys a type takes are checked when converting.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SegmentEntry {
    #[serde(rename = "type")]
    pub kind: SegmentType,
    pub duration_s: Option<f64>,
    pub time_s: Option<f64>,
    pub accel_m_s2: Option<f64>,
    pub speed_m_s: Option<f64>,
    pub decel_m_s2: Option<f64>,
    pub pitch_deg: Option<f64>,
    pub vertical_speed_m_s: Option<f64>,
    pub rate_deg_s: Option<f64>,
    pub radius_m: Option<f64>,
    pub angle_deg: Option<f64>,
    pub parts: Option<Vec<SegmentEntry>>,
}

/// `[initial_errors]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InitialErrorsSection {
    pub attitude_deg: Option<V3>,
    pub attitude_arcmin: Option<V3>,
    pub attitude_arcsec: Option<V3>,
    pub velocity_m_s: Option<V3>,
    pub position_m: Option<V3>,
}
