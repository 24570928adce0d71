//! `[gnss]` to the simulated receiver's configuration, with its noise
//! windows, outliers and outages.

use kestrel::nav::nalgebra::Vector3;
use kestrel::sim::{GnssConfig, MultipathBursts, NoiseWindow, Outlier, OutlierKind, ReportedStd};

use super::convert_sensors::{bare_window, window};
use super::schema_sensors::{
    GnssSection, NoiseWindowEntry, OutlierEntry, OutlierType, ReportedName,
};
use crate::config::check::{bad, join, lever_arm, need, num, reject, vec3, Range, Res};
use crate::config::vec3::V3;

/// `[gnss]`.
pub(super) fn gnss(s: &GnssSection) -> Res<GnssConfig> {
    let p = "gnss";
    let nn = Range::NonNegative;
    let rate = num(&join(p, "rate_hz"), s.rate_hz, Range::Positive)?;
    let pos = vec3(&join(p, "position_std_m"), s.position_std_m, nn)?;
    let vel = s
        .velocity_std_m_s
        .map(|v| vec3(&join(p, "velocity_std_m_s"), v, nn))
        .transpose()?;
    let mut c = GnssConfig::new(rate, pos, vel);
    if let Some(l) = s.lever_arm_m {
        c.lever_arm = lever_arm(&join(p, "lever_arm_m"), l)?;
    }
    c.reported_std = match s.reported_std {
        ReportedName::Nominal => ReportedStd::Nominal,
        ReportedName::Actual => ReportedStd::Actual,
    };
    c.noise_windows = s
        .noise_window
        .iter()
        .enumerate()
        .map(|(i, w)| noise_window(&format!("{p}.noise_window[{i}]"), w))
        .collect::<Res<_>>()?;
    c.outliers = s
        .outlier
        .iter()
        .enumerate()
        .map(|(i, o)| outlier(&format!("{p}.outlier[{i}]"), o))
        .collect::<Res<_>>()?;
    c.outages = s
        .outage
        .iter()
        .enumerate()
        .map(|(i, w)| bare_window(&format!("{p}.outage[{i}]"), w))
        .collect::<Res<_>>()?;
    Ok(c)
}

fn noise_window(p: &str, w: &NoiseWindowEntry) -> Res<NoiseWindow> {
    let nn = Range::NonNegative;
    Ok(NoiseWindow {
        window: window(p, w.start_s, w.end_s, w.duration_s)?,
        position_std: w
            .position_std_m
            .map(|v| vec3(&join(p, "position_std_m"), v, nn))
            .transpose()?,
        velocity_std: w
            .velocity_std_m_s
            .map(|v| vec3(&join(p, "velocity_std_m_s"), v, nn))
            .transpose()?,
    })
}

/// A `[min, max]` size range.
pub(super) fn size_range(key: &str, r: [f64; 2]) -> Res<(f64, f64)> {
    let lo = num(&format!("{key}[0]"), r[0], Range::NonNegative)?;
    let hi = num(&format!("{key}[1]"), r[1], Range::NonNegative)?;
    if hi < lo {
        return Err(bad(key, format!("needs min ≤ max, found [{lo}, {hi}]")));
    }
    Ok((lo, hi))
}

fn outlier(p: &str, o: &OutlierEntry) -> Res<Outlier> {
    let window = window(p, o.start_s, o.end_s, o.duration_s)?;
    let patch_keys = [
        ("position_offset_m", o.position_offset_m.is_some()),
        ("position_amplitude_m", o.position_amplitude_m.is_some()),
        ("velocity_offset_m_s", o.velocity_offset_m_s.is_some()),
        ("velocity_amplitude_m_s", o.velocity_amplitude_m_s.is_some()),
    ];
    let spike_keys = [
        ("probability", o.probability.is_some()),
        ("position_error_m", o.position_error_m.is_some()),
        ("velocity_error_m_s", o.velocity_error_m_s.is_some()),
    ];
    let burst_keys = [
        ("onset_probability", o.onset_probability.is_some()),
        ("burst_duration_s", o.burst_duration_s.is_some()),
        ("rise_s", o.rise_s.is_some()),
        ("position_bias_m", o.position_bias_m.is_some()),
        ("position_jitter_m", o.position_jitter_m.is_some()),
        ("velocity_bias_m_s", o.velocity_bias_m_s.is_some()),
        ("velocity_jitter_m_s", o.velocity_jitter_m_s.is_some()),
    ];
    let others = |a: &[(&'static str, bool)],
                  b: &[(&'static str, bool)]|
     -> Vec<(&'static str, bool)> { a.iter().chain(b).copied().collect() };
    let v = |k: &str, x: Option<V3>, r: Range| -> Res<Vector3<f64>> {
        x.map_or(Ok(Vector3::zeros()), |x| vec3(&join(p, k), x, r))
    };
    let kind = match o.kind {
        OutlierType::Patch => {
            reject(
                p,
                &others(&spike_keys, &burst_keys),
                "a `patch` outlier",
                "offsets and amplitudes",
            )?;
            OutlierKind::Patch {
                position_offset: v("position_offset_m", o.position_offset_m, Range::Any)?,
                position_amplitude: v(
                    "position_amplitude_m",
                    o.position_amplitude_m,
                    Range::NonNegative,
                )?,
                velocity_offset: v("velocity_offset_m_s", o.velocity_offset_m_s, Range::Any)?,
                velocity_amplitude: v(
                    "velocity_amplitude_m_s",
                    o.velocity_amplitude_m_s,
                    Range::NonNegative,
                )?,
            }
        }
        OutlierType::Spikes => {
            reject(
                p,
                &others(&patch_keys, &burst_keys),
                "a `spikes` outlier",
                "`probability`, `position_error_m`, `velocity_error_m_s`",
            )?;
            let key = join(p, "probability");
            let probability = num(
                &key,
                need(&key, o.probability, "a `spikes` outlier needs it")?,
                Range::Interval(0.0, 1.0, false, false),
            )?;
            OutlierKind::Spikes {
                probability,
                position: o.position_error_m.map_or(Ok((0.0, 0.0)), |r| {
                    size_range(&join(p, "position_error_m"), r)
                })?,
                velocity: o.velocity_error_m_s.map_or(Ok((0.0, 0.0)), |r| {
                    size_range(&join(p, "velocity_error_m_s"), r)
                })?,
            }
        }
        OutlierType::Multipath => {
            reject(
                p,
                &others(&patch_keys, &spike_keys),
                "a `multipath` outlier",
                "`onset_probability`, `burst_duration_s`, `rise_s`, biases and jitters",
            )?;
            let key = join(p, "onset_probability");
            let onset = num(
                &key,
                need(&key, o.onset_probability, "a `multipath` outlier needs it")?,
                Range::Interval(0.0, 1.0, false, false),
            )?;
            let key = join(p, "burst_duration_s");
            let duration = size_range(
                &key,
                need(&key, o.burst_duration_s, "a `multipath` outlier needs it")?,
            )?;
            let nn = Range::NonNegative;
            OutlierKind::Multipath(MultipathBursts {
                onset_probability: onset,
                duration,
                rise: num(&join(p, "rise_s"), o.rise_s.unwrap_or(0.0), nn)?,
                position: v("position_bias_m", o.position_bias_m, nn)?,
                position_jitter: v("position_jitter_m", o.position_jitter_m, nn)?,
                velocity_bias: v("velocity_bias_m_s", o.velocity_bias_m_s, nn)?,
                velocity: v("velocity_jitter_m_s", o.velocity_jitter_m_s, nn)?,
            })
        }
    };
    Ok(Outlier { window, kind })
}
