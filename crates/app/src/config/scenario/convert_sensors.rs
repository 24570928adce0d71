//! The IMU, odometer and attitude tables to the simulator's configurations
//! (GNSS in its own file), and the time windows they share.

use kestrel::nav::ImuSpec;
use kestrel::sim::{
    AttitudeConfig, ImuErrors, OdometerConfig, OdometerFault, OdometerFaultKind, TimeWindow,
};

use super::schema_sensors::{AttitudeSection, FaultEntry, FaultType, OdometerSection, WindowEntry};
use crate::config::check::{
    bad, join, lever_arm, need, num, quantity, reject, scalar_quantity, Range, Res,
};
use crate::config::imu::ImuTable;
use crate::config::units::{ANGLE, RATIO};

/// `[imu]`: the rate and the true errors.
pub(super) fn imu(s: &ImuTable) -> Res<(f64, ImuErrors)> {
    let mut foreign = s.process_keys().to_vec();
    foreign.extend(s.random_walk_keys());
    reject(
        "imu",
        &foreign,
        "the simulated IMU",
        "constant biases, noise, Gauss-Markov biases and scale factors per axis",
    )?;
    let rate = need("imu.rate_hz", s.rate_hz, "the IMU rate is required")?;
    Ok((num("imu.rate_hz", rate, Range::Positive)?, s.errors("imu")?))
}

/// `[filter.imu]`: the IMU model the filter assumes.
pub(super) fn imu_spec(s: &ImuTable) -> Res<ImuSpec> {
    let p = "filter.imu";
    let mut foreign = vec![("rate_hz", s.rate_hz.is_some())];
    foreign.extend(s.process_keys());
    reject(
        p,
        &foreign,
        "the assumed IMU",
        "error magnitudes only (the rate is in [imu])",
    )?;
    s.model(p)
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
                    format!("expected a time after start_s = {start}, found {end}"),
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
        c.lever_arm = lever_arm(&join(p, "lever_arm_m"), l)?;
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
                    format!("expected a factor ≥ min_factor = {min}, found {max}"),
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
