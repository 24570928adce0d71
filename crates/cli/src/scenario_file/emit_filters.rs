//! The estimation tables of a written scenario file: `[filter]` and
//! `[[filters]]`.

use kestrel::nav::scenario::{ErrorModelKind, FadeBlock, FilterKind, MeasurementKind, Scenario};
use kestrel::nav::sim::ImuErrors;

use super::emit::{number, Writer};
use super::emit_sections::decimal_deg;
use super::emit_sensors::imu_errors;
use super::units::{ACCEL, ANGLE, GYRO_RATE, RATIO, SI};

pub(super) fn filter(w: &mut Writer, s: &Scenario) {
    let f = &s.filter;
    w.table("filter", false, "What every filter shares.");
    let (model, tau) = match f.error_model {
        ErrorModelKind::Ins15 => ("ins15", None),
        ErrorModelKind::Ins18 => ("ins18", None),
        ErrorModelKind::Odometer16 { scale_tau } => ("odometer16", Some(scale_tau)),
    };
    w.string(
        "error_model",
        model,
        "\"ins15\", \"ins18\" (+ gyro Markov) or \"odometer16\" (+ odometer scale)",
    );
    if let Some(t) = tau {
        w.num(
            "odometer_scale_tau_s",
            t,
            "odometer scale-error correlation time, s",
        );
    }
    let m = match f.measurement {
        MeasurementKind::GnssPositionVelocity => "gnss-position-velocity",
        MeasurementKind::AttitudeVelocityPosition => "attitude-velocity-position",
        MeasurementKind::OdometerVelocity => "odometer-velocity",
    };
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

    let p = &f.p0;
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

    let r = &f.r;
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
    match *f {
        FilterKind::Standard => w.string("kind", "standard", "no adaptation"),
        FilterKind::SageHusaFading {
            forgetting,
            reserve,
            lambda_max,
            fade_states,
        } => {
            w.string("kind", "sage-husa-fading", "Sage-Husa R + fading memory");
            fading(w, forgetting, reserve, lambda_max);
            fade(w, fade_states);
        }
        FilterKind::ImprovedAdaptive {
            forgetting,
            reserve,
            lambda_max,
            significance,
            fade_states,
        } => {
            w.string(
                "kind",
                "improved-adaptive",
                "Sage-Husa + fading + χ² compression",
            );
            fading(w, forgetting, reserve, lambda_max);
            w.num(
                "significance",
                significance,
                "α of the χ² compression threshold, (0, 0.5)",
            );
            fade(w, fade_states);
        }
        FilterKind::FederatedUkf { alpha, beta, kappa } => {
            w.string(
                "kind",
                "federated-ukf",
                "federated: local GNSS KF + local UKF",
            );
            sigma_points(w, alpha, beta, kappa);
        }
        FilterKind::FederatedSrUkf { alpha, beta, kappa } => {
            w.string(
                "kind",
                "federated-sr-ukf",
                "federated with the square-root UKF",
            );
            sigma_points(w, alpha, beta, kappa);
        }
        FilterKind::IctErekf { significance } => {
            w.string(
                "kind",
                "ict-erekf",
                "innovation χ² tests + robust R inflation",
            );
            w.num("significance", significance, "α of the tests, (0, 0.5)");
        }
        FilterKind::MaxThreshold { threshold } => {
            w.string(
                "kind",
                "max-threshold",
                "isolate the odometer on a speed mismatch",
            );
            w.num(
                "threshold_m_s",
                threshold,
                "|v_INS − v_odometer| limit, m/s, > 0",
            );
        }
        FilterKind::FuzzyAdaptive { window } => {
            w.string("kind", "fuzzy-adaptive", "fuzzy odometer gain + windowed R");
            w.raw(
                "window",
                &window.to_string(),
                "innovations in the R window: 10, 20 or 50",
            );
        }
        FilterKind::StrongTrackingFading {
            rho,
            softening,
            lambda_max,
            fade_states,
        } => {
            w.string("kind", "strong-tracking-fading", "suboptimal fading factor");
            w.num(
                "rho",
                rho,
                "forgetting factor ρ of the innovation covariance, (0, 1]",
            );
            w.num("softening", softening, "softening β on R, ≥ 1");
            w.num(
                "lambda_max",
                lambda_max,
                "upper clamp of λ, ≥ 1 (inf: none)",
            );
            fade(w, fade_states);
        }
    }
}

fn fading(w: &mut Writer, forgetting: f64, reserve: f64, lambda_max: f64) {
    w.num(
        "forgetting",
        forgetting,
        "Sage-Husa forgetting factor b, (0, 1]",
    );
    w.num(
        "reserve",
        reserve,
        "reserve coefficient γ of the divergence test, ≥ 1",
    );
    w.num(
        "lambda_max",
        lambda_max,
        "upper clamp of the fading factor λ, ≥ 1 (inf: none)",
    );
}

fn fade(w: &mut Writer, states: FadeBlock) {
    let name = match states {
        FadeBlock::All => "all",
        FadeBlock::VelocityPosition => "velocity-position",
        FadeBlock::AttitudeVelocityPosition => "attitude-velocity-position",
    };
    w.string(
        "fade_states",
        name,
        "states the fade scales: \"all\" (papers), \"velocity-position\", \"attitude-velocity-position\"",
    );
}

fn sigma_points(w: &mut Writer, alpha: f64, beta: f64, kappa: f64) {
    w.num("alpha", alpha, "sigma-point spread α, (0, 1]");
    w.num("beta", beta, "prior-knowledge β (2: Gaussian), ≥ 0");
    w.num("kappa", kappa, "secondary scaling κ");
}
