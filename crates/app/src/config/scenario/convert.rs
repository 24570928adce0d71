//! From the file's tables to a [`Scenario`]: the header and the initial
//! errors here, the other tables in their own files.

use crate::scenario::{ErrorModelKind, FilterKind, InitialErrors, Scenario};
use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::Ellipsoid;

use super::convert_trajectory::trajectory;
use super::schema::{Header, InitialErrorsSection, ScenarioFile};
use super::{convert_filter, convert_gnss, convert_sensors};
use crate::config::check::{bad, earth_constant, join, num, quantity, Range, Res};
use crate::config::units::{ANGLE, SI};
use kestrel_io::gins::physical;

/// Checks every value and builds the scenario.
pub(super) fn scenario(f: ScenarioFile) -> Res<Scenario> {
    let earth = earth(&f.scenario)?;
    let trajectory = trajectory(&f.trajectory)?;
    let (imu_rate, imu_errors) = convert_sensors::imu(&f.imu)?;
    let gnss = f.gnss.as_ref().map(convert_gnss::gnss).transpose()?;
    let odometer = f
        .odometer
        .as_ref()
        .map(convert_sensors::odometer)
        .transpose()?;
    let attitude = f
        .attitude
        .as_ref()
        .map(convert_sensors::attitude)
        .transpose()?;
    if f.filters.is_empty() {
        return Err(bad("filters", "at least one [[filters]] entry is needed"));
    }
    let filters = f
        .filters
        .iter()
        .enumerate()
        .map(|(i, e)| convert_filter::filter(&format!("filters[{i}]"), e))
        .collect::<Res<Vec<_>>>()?;
    let setup = convert_filter::setup(&f.filter)?;
    let federated = filters.iter().position(FilterKind::is_federated);
    if let Some(i) = federated.filter(|_| !matches!(setup.error_model, ErrorModelKind::Ins15)) {
        return Err(bad(
            format!("filters[{i}].kind"),
            format!(
                "`{}` runs on the 15-state error model only; set filter.error_model = \"ins15\"",
                filters[i].name()
            ),
        ));
    }
    let s = Scenario {
        name: f.scenario.name,
        description: f.scenario.description,
        earth,
        trajectory,
        imu_rate,
        imu_errors,
        gnss,
        odometer,
        attitude,
        initial_errors: initial_errors(&f.initial_errors)?,
        filter: setup,
        filters,
        seed: f.scenario.seed,
    };
    // The trajectory compiler finds what single values cannot show
    // (`cruise_until` times going backwards, stops at zero speed, …).
    s.trajectory().map_err(|e| {
        if e.segment < s.trajectory.segments.len() {
            let what = e.to_string();
            // The message names the segment by index; the key says it.
            let what = what.split_once(": ").map_or(what.as_str(), |(_, w)| w);
            bad(
                format!("trajectory.segment[{}]", e.segment),
                format!("this segment cannot be flown: {what}"),
            )
        } else {
            bad("trajectory", format!("cannot be flown: {e}"))
        }
    })?;
    Ok(s)
}

/// The named ellipsoid with any of its constants overridden.
fn earth(h: &Header) -> Res<Ellipsoid> {
    let mut e = h.earth.ellipsoid();
    let p = "scenario";
    let wgs = Ellipsoid::wgs84();
    if let Some(a) = h.earth_a_m {
        e.a = earth_constant(&join(p, "earth_a_m"), a, wgs.a, "m")?;
    }
    if let Some(f) = h.earth_flattening {
        e.f = num(
            &join(p, "earth_flattening"),
            f,
            Range::Interval(0.0, physical::EARTH_FLATTENING_MAX, false, false),
        )?;
    }
    if let Some(w) = h.earth_omega_rad_s {
        e.omega_ie = earth_constant(&join(p, "earth_omega_rad_s"), w, wgs.omega_ie, "rad/s")?;
    }
    if let Some(gm) = h.earth_gm_m3_s2 {
        e.gm = earth_constant(&join(p, "earth_gm_m3_s2"), gm, wgs.gm, "m³/s²")?;
    }
    Ok(e)
}

fn initial_errors(e: &InitialErrorsSection) -> Res<InitialErrors> {
    let p = "initial_errors";
    let [deg, arcmin, arcsec] = ANGLE;
    let zero = Vector3::zeros();
    Ok(InitialErrors {
        attitude: quantity(
            p,
            "attitude",
            &[
                (deg, e.attitude_deg),
                (arcmin, e.attitude_arcmin),
                (arcsec, e.attitude_arcsec),
            ],
            Range::Any,
        )?
        .unwrap_or(zero),
        velocity: quantity(p, "velocity_m_s", &[(&SI, e.velocity_m_s)], Range::Any)?
            .unwrap_or(zero),
        position: quantity(p, "position_m", &[(&SI, e.position_m)], Range::Any)?.unwrap_or(zero),
    })
}
