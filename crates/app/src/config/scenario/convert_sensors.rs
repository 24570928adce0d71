//! The IMU, odometer and attitude tables to the simulator's configurations
//! (GNSS in its own file), and the time windows they share.

use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::ImuSpec;
use kestrel::sim::{
    AttitudeConfig, ImuErrors, OdometerConfig, OdometerFault, OdometerFaultKind, TimeWindow,
};

use super::schema_sensors::{
    AttitudeSection, FaultEntry, FaultType, ImuSection, OdometerSection, WindowEntry,
};
use crate::config::check::{
    bad, join, need, num, quantity, reject, scalar_quantity, vec3, Range, Res,
};
use crate::config::units::{ACCEL, ACCEL_NOISE, ANGLE, GYRO_NOISE, GYRO_RATE, RATIO};
use crate::config::vec3::V3;

/// The per-axis IMU errors of `s`, SI; absent keys are zero (τ: ∞).
fn imu_axes(p: &str, s: &ImuSection) -> Res<ImuErrors> {
    let [ppm, percent] = RATIO;
    let [ug, mg] = ACCEL;
    let [dph] = GYRO_RATE;
    let [arw, arw_hz] = GYRO_NOISE;
    let [vrw_hz, vrw_h] = ACCEL_NOISE;
    let zero = |v: Option<Vector3<f64>>| v.unwrap_or_else(Vector3::zeros);
    let tau = |k: &str, v: Option<V3>| -> Res<Vector3<f64>> {
        Ok(match v {
            Some(v) => vec3(&join(p, k), v, Range::Tau)?,
            None => Vector3::repeat(f64::INFINITY),
        })
    };
    let nn = Range::NonNegative;
    Ok(ImuErrors {
        gyro_bias: zero(quantity(
            p,
            "gyro_bias",
            &[(dph, s.gyro_bias_deg_per_h)],
            Range::Any,
        )?),
        gyro_arw: zero(quantity(
            p,
            "gyro_arw",
            &[
                (arw, s.gyro_arw_deg_per_sqrt_h),
                (arw_hz, s.gyro_arw_deg_per_h_per_sqrt_hz),
            ],
            nn,
        )?),
        gyro_markov_sigma: zero(quantity(
            p,
            "gyro_markov",
            &[(dph, s.gyro_markov_deg_per_h)],
            nn,
        )?),
        gyro_markov_tau: tau("gyro_markov_tau_s", s.gyro_markov_tau_s)?,
        gyro_scale: zero(quantity(
            p,
            "gyro_scale",
            &[(ppm, s.gyro_scale_ppm), (percent, s.gyro_scale_percent)],
            Range::Any,
        )?),
        accel_bias: zero(quantity(
            p,
            "accel_bias",
            &[(ug, s.accel_bias_ug), (mg, s.accel_bias_mg)],
            Range::Any,
        )?),
        accel_vrw: zero(quantity(
            p,
            "accel_vrw",
            &[
                (vrw_hz, s.accel_vrw_ug_per_sqrt_hz),
                (vrw_h, s.accel_vrw_m_s_per_sqrt_h),
            ],
            nn,
        )?),
        accel_markov_sigma: zero(quantity(
            p,
            "accel_markov",
            &[(ug, s.accel_markov_ug), (mg, s.accel_markov_mg)],
            nn,
        )?),
        accel_markov_tau: tau("accel_markov_tau_s", s.accel_markov_tau_s)?,
        accel_scale: zero(quantity(
            p,
            "accel_scale",
            &[(ppm, s.accel_scale_ppm), (percent, s.accel_scale_percent)],
            Range::Any,
        )?),
    })
}

/// `[imu]`: the rate and the true errors.
pub(super) fn imu(s: &ImuSection) -> Res<(f64, ImuErrors)> {
    let rate = need("imu.rate_hz", s.rate_hz, "the IMU rate is required")?;
    Ok((
        num("imu.rate_hz", rate, Range::Positive)?,
        imu_axes("imu", s)?,
    ))
}

/// `[filter.imu]`: the errors the filter assumes, the same on every axis.
pub(super) fn imu_spec(s: &ImuSection) -> Res<ImuSpec> {
    let p = "filter.imu";
    reject(
        p,
        &[("rate_hz", s.rate_hz.is_some())],
        "the assumed IMU",
        "error magnitudes only (the rate is in [imu])",
    )?;
    let e = imu_axes(p, s)?;
    let axes = [
        ("gyro_bias", e.gyro_bias),
        ("gyro_arw", e.gyro_arw),
        ("gyro_markov", e.gyro_markov_sigma),
        ("gyro_markov_tau_s", e.gyro_markov_tau),
        ("gyro_scale", e.gyro_scale),
        ("accel_bias", e.accel_bias),
        ("accel_vrw", e.accel_vrw),
        ("accel_markov", e.accel_markov_sigma),
        ("accel_markov_tau_s", e.accel_markov_tau),
        ("accel_scale", e.accel_scale),
    ];
    if let Some((k, _)) = axes.iter().find(|(_, v)| !(v.x == v.y && v.y == v.z)) {
        return Err(bad(
            join(p, k),
            "the assumed IMU model is the same on every axis: give one number",
        ));
    }
    Ok(ImuSpec {
        gyro_bias: e.gyro_bias.x,
        gyro_arw: e.gyro_arw.x,
        gyro_markov_sigma: e.gyro_markov_sigma.x,
        gyro_markov_tau: e.gyro_markov_tau.x,
        accel_bias: e.accel_bias.x,
        accel_vrw: e.accel_vrw.x,
        accel_markov_sigma: e.accel_markov_sigma.x,
        accel_markov_tau: e.accel_markov_tau.x,
        gyro_scale: e.gyro_scale.x,
        accel_scale: e.accel_scale.x,
        gyro_bias_rw: 0.0,
        accel_bias_rw: 0.0,
    })
}
/// A window from `start_s` and `end_s` or `duration_s`.
pub(super) fn window(
    p: &str,
    start: f64,
    end: Option<f64>,
    duration: Option<f64>,
) -> Res<TimeWindow> {
    let start = num(&join(p, "start_s"), start, Range::NonNegative)?;
    match (end, duration) {
        (Some(end), None) => {
            let end = num(&join(p, "end_s"), end, Range::Any)?;
            if end <= start {
                return Err(bad(
                    join(p, "end_s"),
                    format!("must be after start_s = {start}, found {end}"),
                ));
            }
            Ok(TimeWindow::new(start, end))
        }
        (None, Some(d)) => Ok(TimeWindow::starting(
            start,
            num(&join(p, "duration_s"), d, Range::Positive)?,
        )),
        _ => Err(bad(p, "needs exactly one of `end_s`, `duration_s`")),
    }
}

pub(super) fn bare_window(p: &str, w: &WindowEntry) -> Res<TimeWindow> {
    window(p, w.start_s, w.end_s, w.duration_s)
}
/// `[odometer]`.
pub(super) fn odometer(s: &OdometerSection) -> Res<OdometerConfig> {
    let p = "odometer";
    let [ppm, percent] = RATIO;
    let mut c = OdometerConfig::new(num(&join(p, "rate_hz"), s.rate_hz, Range::Positive)?);
    c.scale_error = scalar_quantity(
        p,
        "scale_error",
        &[(ppm, s.scale_error_ppm), (percent, s.scale_error_percent)],
        Range::Any,
    )?
    .unwrap_or(0.0);
    c.scale_markov_sigma = scalar_quantity(
        p,
        "scale_markov",
        &[(ppm, s.scale_markov_ppm), (percent, s.scale_markov_percent)],
        Range::NonNegative,
    )?
    .unwrap_or(0.0);
    if let Some(t) = s.scale_markov_tau_s {
        c.scale_markov_tau = num(&join(p, "scale_markov_tau_s"), t, Range::Tau)?;
    }
    c.noise_std = num(
        &join(p, "noise_std_m_s"),
        s.noise_std_m_s,
        Range::NonNegative,
    )?;
    if let Some(l) = s.lever_arm_m {
        c.lever_arm = vec3(&join(p, "lever_arm_m"), l, Range::Any)?;
    }
    c.faults = s
        .fault
        .iter()
        .enumerate()
        .map(|(i, f)| fault(&format!("{p}.fault[{i}]"), f))
        .collect::<Res<_>>()?;
    Ok(c)
}

fn fault(p: &str, f: &FaultEntry) -> Res<OdometerFault> {
    let window = window(p, f.start_s, f.end_s, f.duration_s)?;
    let keys = [
        ("factor", f.factor.is_some()),
        ("min_factor", f.min_factor.is_some()),
        ("max_factor", f.max_factor.is_some()),
        ("offset_m_s", f.offset_m_s.is_some()),
    ];
    let (what, takes): (&str, &[&str]) = match f.kind {
        FaultType::Factor => ("a `factor` fault", &["factor"]),
        FaultType::RandomFactor => ("a `random_factor` fault", &["min_factor", "max_factor"]),
        FaultType::Offset => ("an `offset` fault", &["offset_m_s"]),
    };
    let foreign: Vec<(&str, bool)> = keys
        .into_iter()
        .filter(|(k, _)| !takes.contains(k))
        .collect();
    reject(p, &foreign, what, &format!("`{}`", takes.join("`, `")))?;
    let get = |k: &str, x: Option<f64>, r: Range| -> Res<f64> {
        let key = join(p, k);
        num(&key, need(&key, x, &format!("{what} needs it"))?, r)
    };
    let kind = match f.kind {
        FaultType::Factor => {
            OdometerFaultKind::Factor(get("factor", f.factor, Range::NonNegative)?)
        }
        FaultType::RandomFactor => {
            let min = get("min_factor", f.min_factor, Range::NonNegative)?;
            let max = get("max_factor", f.max_factor, Range::NonNegative)?;
            if max < min {
                return Err(bad(
                    join(p, "max_factor"),
                    format!("must be ≥ min_factor = {min}, found {max}"),
                ));
            }
            OdometerFaultKind::RandomFactor { min, max }
        }
        FaultType::Offset => {
            OdometerFaultKind::Offset(get("offset_m_s", f.offset_m_s, Range::Any)?)
        }
    };
    Ok(OdometerFault { window, kind })
}

/// `[attitude]`.
pub(super) fn attitude(s: &AttitudeSection) -> Res<AttitudeConfig> {
    let p = "attitude";
    let [deg, arcmin, arcsec] = ANGLE;
    let std = quantity(
        p,
        "std",
        &[
            (deg, s.std_deg),
            (arcmin, s.std_arcmin),
            (arcsec, s.std_arcsec),
        ],
        Range::NonNegative,
    )?;
    Ok(AttitudeConfig {
        rate: num(&join(p, "rate_hz"), s.rate_hz, Range::Positive)?,
        std: need(
            &join(p, "std_deg"),
            std,
            "the attitude noise σ is required (`std_deg`, `std_arcmin` or `std_arcsec`)",
        )?,
    })
}
