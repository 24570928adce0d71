//! `[filter]` and `[[filters]]` to the scenario's filter set-up and kinds.

use crate::scenario::{ErrorModelKind, FilterKind, FilterSetup, MeasurementNoise};
use kestrel::nav::nalgebra::Vector3;

use super::convert_sensors::imu_spec;
use super::schema_filter::{ErrorModelName, FilterSection, RSection};
use crate::config::check::{bad, join, lever_arm, need, num, quantity, Range, Res};
use crate::config::filter::{read_kind, Keys, Kinds};
use crate::config::units::{ANGLE, SI};

/// `[filter]`.
pub(super) fn setup(f: &FilterSection) -> Res<FilterSetup> {
    let p = "filter";
    let tau_key = join(p, "odometer_scale_tau_s");
    let scale_key = join(p, "scale_tau_s");
    let tau = match f.error_model {
        ErrorModelName::Ins21 => match f.scale_tau_s {
            Some(t) => num(&scale_key, t, Range::Tau)?,
            None => f64::INFINITY,
        },
        ErrorModelName::Odometer16 => {
            let tau = need(
                &tau_key,
                f.odometer_scale_tau_s,
                "the `odometer16` model needs it",
            )?;
            num(&tau_key, tau, Range::Tau)?
        }
        ErrorModelName::Ins15 | ErrorModelName::Ins18 => f64::INFINITY,
    };
    let error_model = f.error_model.model(tau);
    if !matches!(error_model, ErrorModelKind::Odometer16 { .. }) && f.odometer_scale_tau_s.is_some()
    {
        return Err(bad(tau_key, "applies only to error_model = \"odometer16\""));
    }
    let ins21 = matches!(error_model, ErrorModelKind::Ins21 { .. });
    if !ins21 && f.scale_tau_s.is_some() {
        return Err(bad(scale_key, "applies only to error_model = \"ins21\""));
    }
    let p0 = f.p0.uncertainty("filter.p0")?;
    if !ins21 && (p0.gyro_scale != Vector3::zeros() || p0.accel_scale != Vector3::zeros()) {
        return Err(bad(
            "filter.p0.gyro_scale / accel_scale".to_owned(),
            "scale-factor states exist in error_model = \"ins21\" only",
        ));
    }
    let mounting = match f.odometer_mounting_deg {
        Some(m) => {
            for (i, &x) in m.iter().enumerate() {
                num(&format!("{p}.odometer_mounting_deg[{i}]"), x, Range::Any)?;
            }
            m.map(f64::to_radians)
        }
        None => [0.0; 2],
    };
    Ok(FilterSetup {
        error_model,
        measurement: f.measurement,
        imu_model: imu_spec(&f.imu)?,
        p0,
        r: r(&f.r)?,
        lever_arm: f.lever_arm_m.map_or(Ok(Vector3::zeros()), |l| {
            lever_arm(&join(p, "lever_arm_m"), l)
        })?,
        odometer_mounting: mounting,
    })
}

fn r(s: &RSection) -> Res<MeasurementNoise> {
    let p = "filter.r";
    let nn = Range::NonNegative;
    let [deg, arcmin, arcsec] = ANGLE;
    Ok(MeasurementNoise {
        position: quantity(p, "position_m", &[(&SI, s.position_m)], nn)?,
        velocity: quantity(p, "velocity_m_s", &[(&SI, s.velocity_m_s)], nn)?,
        attitude: quantity(
            p,
            "attitude",
            &[
                (deg, s.attitude_deg),
                (arcmin, s.attitude_arcmin),
                (arcsec, s.attitude_arcsec),
            ],
            nn,
        )?,
        odometer: quantity(p, "odometer_m_s", &[(&SI, s.odometer_m_s)], nn)?,
    })
}

/// One `[[filters]]` entry at key path `p`.
pub(super) fn filter(p: &str, e: &Keys) -> Res<FilterKind> {
    read_kind(e, p, None, Kinds::All)
}
