//! The sensor tables of a written scenario file.

use crate::scenario::Scenario;
use kestrel::nalgebra::Vector3;
use kestrel::sim::{
    GnssConfig, ImuErrors, MultipathBursts, OdometerConfig, OdometerFaultKind, OutlierKind,
    ReportedStd, TimeWindow,
};

use crate::config::units::{ACCEL, ACCEL_NOISE, GYRO_NOISE, GYRO_RATE, RATIO, SI};
use crate::config::write::{number, Writer};

pub(super) fn imu(w: &mut Writer, s: &Scenario) {
    w.table(
        "imu",
        false,
        "The simulated IMU's true errors, datasheet units, one number for all axes or\n[x, y, z] (body: forward, right, down). Constant terms are the actual values.",
    );
    w.num("rate_hz", s.imu_rate, "sampling rate, Hz");
    imu_errors(w, &s.imu_errors);
}

/// The error keys shared by `[imu]` and `[filter.imu]`.
pub(super) fn imu_errors(w: &mut Writer, e: &ImuErrors) {
    w.quantity(
        "gyro_bias",
        &GYRO_RATE,
        e.gyro_bias,
        "gyro constant bias, °/h",
    );
    w.quantity(
        "gyro_arw",
        &GYRO_NOISE,
        e.gyro_arw,
        "gyro white noise: °/√h or °/h/√Hz",
    );
    w.quantity(
        "gyro_markov",
        &GYRO_RATE,
        e.gyro_markov_sigma,
        "gyro Gauss-Markov drift σ, °/h",
    );
    w.quantity(
        "gyro_markov_tau_s",
        &[&SI],
        e.gyro_markov_tau,
        "its correlation time, s (inf: none)",
    );
    w.quantity(
        "gyro_scale",
        &RATIO,
        e.gyro_scale,
        "gyro scale-factor error: ppm or %",
    );
    w.quantity(
        "accel_bias",
        &ACCEL,
        e.accel_bias,
        "accelerometer constant bias: µg or mg",
    );
    w.quantity(
        "accel_vrw",
        &ACCEL_NOISE,
        e.accel_vrw,
        "accelerometer white noise: µg/√Hz or m/s/√h",
    );
    w.quantity(
        "accel_markov",
        &ACCEL,
        e.accel_markov_sigma,
        "accelerometer Gauss-Markov bias σ: µg or mg",
    );
    w.quantity(
        "accel_markov_tau_s",
        &[&SI],
        e.accel_markov_tau,
        "its correlation time, s (inf: none)",
    );
    w.quantity(
        "accel_scale",
        &RATIO,
        e.accel_scale,
        "accelerometer scale-factor error: ppm or %",
    );
}

fn window_keys(w: &mut Writer, win: &TimeWindow) {
    w.num("start_s", win.start, "window start, s");
    w.num("end_s", win.end, "window end, s (exclusive; or duration_s)");
}

pub(super) fn gnss(w: &mut Writer, g: &GnssConfig) {
    w.table(
        "gnss",
        false,
        "GNSS receiver: fixes of the antenna position (and velocity), NED σ.",
    );
    w.num("rate_hz", g.rate, "fix rate, Hz");
    w.quantity(
        "position_std_m",
        &[&SI],
        g.position_std,
        "white position noise σ north, east, down, m",
    );
    if let Some(v) = g.velocity_std {
        w.quantity(
            "velocity_std_m_s",
            &[&SI],
            v,
            "white velocity noise σ, m/s (omit: no velocity)",
        );
    }
    w.quantity(
        "lever_arm_m",
        &[&SI],
        g.lever_arm,
        "antenna from the IMU, body axes, m",
    );
    let reported = match g.reported_std {
        ReportedStd::Nominal => "nominal",
        ReportedStd::Actual => "actual",
    };
    w.string(
        "reported_std",
        reported,
        "σ in the fixes: \"nominal\" (base) or \"actual\" (in effect)",
    );
    noise_windows(w, g);
    outliers(w, g);
    outages(w, g);
}

/// `[[gnss.noise_window]]`: noise changes.
fn noise_windows(w: &mut Writer, g: &GnssConfig) {
    for (i, n) in g.noise_windows.iter().enumerate() {
        let c = if i == 0 {
            "Noise changes (the first matching window applies)."
        } else {
            ""
        };
        w.table("gnss.noise_window", true, c);
        window_keys(w, &n.window);
        if let Some(p) = n.position_std {
            w.quantity("position_std_m", &[&SI], p, "position σ in the window, m");
        }
        if let Some(v) = n.velocity_std {
            w.quantity(
                "velocity_std_m_s",
                &[&SI],
                v,
                "velocity σ in the window, m/s",
            );
        }
    }
}

/// `[[gnss.outlier]]`: faults, one table each.
fn outliers(w: &mut Writer, g: &GnssConfig) {
    for (i, o) in g.outliers.iter().enumerate() {
        let c = if i == 0 {
            "Outliers: type = \"patch\" (every fix: offset + uniform ±amplitude, NED) or\n\"spikes\" (each fix with a probability: random direction, size uniform in [min, max])."
        } else {
            ""
        };
        w.table("gnss.outlier", true, c);
        match o.kind {
            OutlierKind::Patch {
                position_offset,
                position_amplitude,
                velocity_offset,
                velocity_amplitude,
            } => patch(
                w,
                &o.window,
                [
                    position_offset,
                    position_amplitude,
                    velocity_offset,
                    velocity_amplitude,
                ],
            ),
            OutlierKind::Spikes {
                probability,
                position,
                velocity,
            } => spikes(w, &o.window, probability, position, velocity),
            OutlierKind::Multipath(m) => multipath(w, &o.window, &m),
        }
    }
}

/// A patch: every fix in the window offset plus a uniform error.
fn patch(w: &mut Writer, window: &TimeWindow, v: [Vector3<f64>; 4]) {
    let [position_offset, position_amplitude, velocity_offset, velocity_amplitude] = v;
    w.string("type", "patch", "every fix corrupted");
    window_keys(w, window);
    w.quantity(
        "position_offset_m",
        &[&SI],
        position_offset,
        "constant position error, m",
    );
    w.quantity(
        "position_amplitude_m",
        &[&SI],
        position_amplitude,
        "uniform position error half-width, m",
    );
    w.quantity(
        "velocity_offset_m_s",
        &[&SI],
        velocity_offset,
        "constant velocity error, m/s",
    );
    w.quantity(
        "velocity_amplitude_m_s",
        &[&SI],
        velocity_amplitude,
        "uniform velocity error half-width, m/s",
    );
}

/// Spikes: isolated gross errors with a probability per fix.
fn spikes(
    w: &mut Writer,
    window: &TimeWindow,
    probability: f64,
    position: (f64, f64),
    velocity: (f64, f64),
) {
    w.string("type", "spikes", "isolated gross errors");
    window_keys(w, window);
    w.num("probability", probability, "chance per fix, [0, 1]");
    let pair = |(a, b): (f64, f64)| format!("[{}, {}]", number(a), number(b));
    w.raw(
        "position_error_m",
        &pair(position),
        "size range [min, max], m",
    );
    w.raw(
        "velocity_error_m_s",
        &pair(velocity),
        "size range [min, max], m/s",
    );
}

/// Multipath / NLOS bursts at random times.
fn multipath(w: &mut Writer, window: &TimeWindow, m: &MultipathBursts) {
    w.string(
        "type",
        "multipath",
        "randomly timed multipath / NLOS bursts",
    );
    window_keys(w, window);
    let pair = |(a, b): (f64, f64)| format!("[{}, {}]", number(a), number(b));
    w.num(
        "onset_probability",
        m.onset_probability,
        "chance per fix that a burst starts, [0, 1]",
    );
    w.raw(
        "burst_duration_s",
        &pair(m.duration),
        "burst length range [min, max], s",
    );
    w.num(
        "rise_s",
        m.rise,
        "bias build-up and fall-off time, s (0: a step)",
    );
    w.quantity(
        "position_bias_m",
        &[&SI],
        m.position,
        "largest per-burst bias ± per axis, m",
    );
    w.quantity(
        "position_jitter_m",
        &[&SI],
        m.position_jitter,
        "per-fix error half-width, m",
    );
    w.quantity(
        "velocity_bias_m_s",
        &[&SI],
        m.velocity_bias,
        "largest per-burst velocity bias ±, m/s",
    );
    w.quantity(
        "velocity_jitter_m_s",
        &[&SI],
        m.velocity,
        "per-fix velocity error half-width, m/s",
    );
}

/// `[[gnss.outage]]`: no fixes in these windows.
fn outages(w: &mut Writer, g: &GnssConfig) {
    for (i, o) in g.outages.iter().enumerate() {
        w.table(
            "gnss.outage",
            true,
            if i == 0 {
                "No fixes inside these windows."
            } else {
                ""
            },
        );
        window_keys(w, o);
    }
}

pub(super) fn odometer(w: &mut Writer, o: &OdometerConfig) {
    w.table(
        "odometer",
        false,
        "Odometer: speed along the vehicle's forward axis.",
    );
    w.num("rate_hz", o.rate, "reading rate, Hz");
    w.scalar(
        "scale_error",
        &RATIO,
        o.scale_error,
        "constant scale-factor error: ppm or %",
    );
    w.scalar(
        "scale_markov",
        &RATIO,
        o.scale_markov_sigma,
        "Gauss-Markov scale error σ: ppm or %",
    );
    w.num(
        "scale_markov_tau_s",
        o.scale_markov_tau,
        "its correlation time, s (inf: none)",
    );
    w.num(
        "noise_std_m_s",
        o.noise_std,
        "white noise σ per reading, m/s",
    );
    w.quantity(
        "lever_arm_m",
        &[&SI],
        o.lever_arm,
        "measuring wheel from the IMU, body axes, m",
    );
    for (i, f) in o.faults.iter().enumerate() {
        let c = if i == 0 {
            "Faults (the first matching one applies): type = \"factor\" (reads factor × true:\nspin > 1, skid < 1), \"random_factor\" (uniform in [min_factor, max_factor]),\n\"offset\" (adds offset_m_s)."
        } else {
            ""
        };
        w.table("odometer.fault", true, c);
        match f.kind {
            OdometerFaultKind::Factor(x) => {
                w.string("type", "factor", "reads a fixed multiple of the speed");
                window_keys(w, &f.window);
                w.num("factor", x, "reading / true speed");
            }
            OdometerFaultKind::RandomFactor { min, max } => {
                w.string(
                    "type",
                    "random_factor",
                    "reads a random multiple of the speed",
                );
                window_keys(w, &f.window);
                w.num("min_factor", min, "smallest factor");
                w.num("max_factor", max, "largest factor");
            }
            OdometerFaultKind::Offset(x) => {
                w.string("type", "offset", "reads the speed plus an offset");
                window_keys(w, &f.window);
                w.num("offset_m_s", x, "added to the reading, m/s");
            }
        }
    }
}
