//! The estimation tables of a written scenario file: `[filter]` and
//! `[[filters]]`.

use crate::config::names::ErrorModelName;
use crate::scenario::{ErrorModelKind, FilterKind, InitialUncertainty, MeasurementNoise, Scenario};
use kestrel::sim::ImuErrors;

use super::emit_sections::decimal_deg;
use super::emit_sensors::imu_errors;
use crate::config::units::{ACCEL, ANGLE, GYRO_RATE, RATIO, SI};
use crate::config::write::{number, Writer};

pub(super) fn filter(w: &mut Writer, s: &Scenario) {
    let f = &s.filter;
    w.table("filter", false, "What every filter shares.");
    let model = ErrorModelName::of(&f.error_model).name();
    let tau = match f.error_model {
        ErrorModelKind::Odometer16 { scale_tau } => Some(scale_tau),
        _ => None,
    };
    w.string(
        "error_model",
        model,
        "\"ins15\", \"ins18\" (+ gyro Markov), \"ins21\" (+ IMU scale factors) or \
         \"odometer16\" (+ odometer scale)",
    );
    if let Some(t) = tau {
        w.num(
            "odometer_scale_tau_s",
            t,
            "odometer scale-error correlation time, s",
        );
    }
    if let ErrorModelKind::Ins21 { scale_tau } = f.error_model
        && scale_tau.is_finite()
    {
        w.num(
            "scale_tau_s",
            scale_tau,
            "IMU scale-factor correlation time, s (omit: random constants)",
        );
    }
    let m = f.measurement.name();
    w.string(
        "measurement",
        m,
        "\"gnss-position-velocity\", \"attitude-velocity-position\", \"odometer-velocity\"",
    );
    w.quantity(
        "lever_arm_m",
        &[&SI],
        f.lever_arm,
        "GNSS lever arm the filter uses, body, m",
    );
    let mount = f.odometer_mounting.map(|a| number(decimal_deg(a)));
    w.raw(
        "odometer_mounting_deg",
        &format!("[{}, {}]", mount[0], mount[1]),
        "odometer mounting pitch, yaw the filter uses, °",
    );

    w.table(
        "filter.imu",
        false,
        "The IMU model the filter assumes (its Q), one number per quantity.",
    );
    imu_errors(w, &ImuErrors::from_spec(&f.imu_model));
    p0(w, &f.p0, &f.error_model);
    measurement_noise(w, &f.r);
}

/// `[filter.p0]`: the initial standard deviations.
fn p0(w: &mut Writer, p: &InitialUncertainty, model: &ErrorModelKind) {
    w.table(
        "filter.p0",
        false,
        "Initial standard deviations (P0 is diagonal).",
    );
    w.quantity(
        "attitude",
        &ANGLE,
        p.attitude,
        "attitude σ: deg, arcmin or arcsec",
    );
    w.quantity("velocity_m_s", &[&SI], p.velocity, "velocity σ, m/s");
    w.quantity("position_m", &[&SI], p.position, "position σ, m");
    w.quantity(
        "gyro_bias",
        &GYRO_RATE,
        p.gyro_bias,
        "gyro (constant) bias σ, °/h",
    );
    w.quantity(
        "gyro_markov",
        &GYRO_RATE,
        p.gyro_markov,
        "gyro Markov drift σ (ins18), °/h",
    );
    w.quantity(
        "accel_bias",
        &ACCEL,
        p.accel_bias,
        "accelerometer bias σ: µg or mg",
    );
    w.scalar(
        "odometer_scale",
        &RATIO,
        p.odometer_scale,
        "odometer scale σ (odometer16): ppm or %",
    );
    if matches!(model, ErrorModelKind::Ins21 { .. }) {
        w.quantity(
            "gyro_scale",
            &RATIO,
            p.gyro_scale,
            "gyro scale-factor σ (ins21): ppm or %",
        );
        w.quantity(
            "accel_scale",
            &RATIO,
            p.accel_scale,
            "accelerometer scale-factor σ (ins21): ppm or %",
        );
    }
}

/// `[filter.r]`: the measurement noise the filters assume.
fn measurement_noise(w: &mut Writer, r: &MeasurementNoise) {
    w.table(
        "filter.r",
        false,
        "Measurement noise σ the filters assume (R; omit what is not measured).",
    );
    if let Some(v) = r.position {
        w.quantity("position_m", &[&SI], v, "position σ north, east, down, m");
    }
    if let Some(v) = r.velocity {
        w.quantity("velocity_m_s", &[&SI], v, "velocity σ, m/s");
    }
    if let Some(v) = r.attitude {
        w.quantity("attitude", &ANGLE, v, "attitude σ: deg, arcmin or arcsec");
    }
    if let Some(v) = r.odometer {
        w.quantity(
            "odometer_m_s",
            &[&SI],
            v,
            "odometer velocity-matching σ, m/s",
        );
    }
}

pub(super) fn filter_entry(w: &mut Writer, f: &FilterKind) {
    w.table("filters", true, &format!("Filter \"{}\".", f.label()));
    w.string("kind", f.name(), f.summary());
    for p in f.params() {
        w.raw(p.key, &p.value.to_string(), p.comment);
    }
}
