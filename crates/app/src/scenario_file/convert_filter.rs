//! `[filter]` and `[[filters]]` to the scenario's filter set-up and kinds.

use crate::scenario::{
    ErrorModelKind, FadeBlock, FilterKind, FilterSetup, InitialUncertainty, MeasurementKind,
    MeasurementNoise,
};
use kestrel::nav::nalgebra::Vector3;

use super::check::{bad, join, need, num, quantity, reject, scalar_quantity, vec3, Range, Res};
use super::convert_sensors::imu_spec;
use super::schema_filter::{
    ErrorModelName, FadeName, FilterEntry, FilterName, FilterSection, MeasurementName, P0Section,
    RSection,
};
use super::units::{ACCEL, ANGLE, GYRO_RATE, RATIO, SI};

/// `[filter]`.
pub(super) fn setup(f: &FilterSection) -> Res<FilterSetup> {
    let p = "filter";
    let tau_key = join(p, "odometer_scale_tau_s");
    let scale_key = join(p, "scale_tau_s");
    let error_model = match f.error_model {
        ErrorModelName::Ins15 => ErrorModelKind::Ins15,
        ErrorModelName::Ins18 => ErrorModelKind::Ins18,
        ErrorModelName::Ins21 => ErrorModelKind::Ins21 {
            scale_tau: match f.scale_tau_s {
                Some(t) => num(&scale_key, t, Range::Tau)?,
                None => f64::INFINITY,
            },
        },
        ErrorModelName::Odometer16 => {
            let tau = need(
                &tau_key,
                f.odometer_scale_tau_s,
                "the `odometer16` model needs it",
            )?;
            ErrorModelKind::Odometer16 {
                scale_tau: num(&tau_key, tau, Range::Tau)?,
            }
        }
    };
    if !matches!(error_model, ErrorModelKind::Odometer16 { .. }) && f.odometer_scale_tau_s.is_some()
    {
        return Err(bad(tau_key, "applies only to error_model = \"odometer16\""));
    }
    let ins21 = matches!(error_model, ErrorModelKind::Ins21 { .. });
    if !ins21 && f.scale_tau_s.is_some() {
        return Err(bad(scale_key, "applies only to error_model = \"ins21\""));
    }
    let p0 = p0(&f.p0)?;
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
        measurement: match f.measurement {
            MeasurementName::GnssPositionVelocity => MeasurementKind::GnssPositionVelocity,
            MeasurementName::AttitudeVelocityPosition => MeasurementKind::AttitudeVelocityPosition,
            MeasurementName::OdometerVelocity => MeasurementKind::OdometerVelocity,
        },
        imu_model: imu_spec(&f.imu)?,
        p0,
        r: r(&f.r)?,
        lever_arm: f.lever_arm_m.map_or(Ok(Vector3::zeros()), |l| {
            vec3(&join(p, "lever_arm_m"), l, Range::Any)
        })?,
        odometer_mounting: mounting,
    })
}

fn p0(s: &P0Section) -> Res<InitialUncertainty> {
    let p = "filter.p0";
    let nn = Range::NonNegative;
    let [deg, arcmin, arcsec] = ANGLE;
    let [dph] = GYRO_RATE;
    let [ug, mg] = ACCEL;
    let [ppm, percent] = RATIO;
    let z = |v: Option<Vector3<f64>>| v.unwrap_or_else(Vector3::zeros);
    Ok(InitialUncertainty {
        attitude: z(quantity(
            p,
            "attitude",
            &[
                (deg, s.attitude_deg),
                (arcmin, s.attitude_arcmin),
                (arcsec, s.attitude_arcsec),
            ],
            nn,
        )?),
        velocity: z(quantity(p, "velocity_m_s", &[(&SI, s.velocity_m_s)], nn)?),
        position: z(quantity(p, "position_m", &[(&SI, s.position_m)], nn)?),
        gyro_bias: z(quantity(
            p,
            "gyro_bias",
            &[(dph, s.gyro_bias_deg_per_h)],
            nn,
        )?),
        gyro_markov: z(quantity(
            p,
            "gyro_markov",
            &[(dph, s.gyro_markov_deg_per_h)],
            nn,
        )?),
        accel_bias: z(quantity(
            p,
            "accel_bias",
            &[(ug, s.accel_bias_ug), (mg, s.accel_bias_mg)],
            nn,
        )?),
        gyro_scale: z(quantity(
            p,
            "gyro_scale",
            &[(ppm, s.gyro_scale_ppm), (percent, s.gyro_scale_percent)],
            nn,
        )?),
        accel_scale: z(quantity(
            p,
            "accel_scale",
            &[(ppm, s.accel_scale_ppm), (percent, s.accel_scale_percent)],
            nn,
        )?),
        odometer_scale: scalar_quantity(
            p,
            "odometer_scale",
            &[
                (ppm, s.odometer_scale_ppm),
                (percent, s.odometer_scale_percent),
            ],
            nn,
        )?
        .unwrap_or(0.0),
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

/// The file's name of a filter kind.
pub(super) fn kind_name(k: FilterName) -> &'static str {
    match k {
        FilterName::Standard => "standard",
        FilterName::SageHusaFading => "sage-husa-fading",
        FilterName::ImprovedAdaptive => "improved-adaptive",
        FilterName::FederatedUkf => "federated-ukf",
        FilterName::FederatedSrUkf => "federated-sr-ukf",
        FilterName::IctErekf => "ict-erekf",
        FilterName::MaxThreshold => "max-threshold",
        FilterName::FuzzyAdaptive => "fuzzy-adaptive",
        FilterName::StrongTrackingFading => "strong-tracking-fading",
    }
}

/// The parameters each kind takes.
fn takes(k: FilterName) -> &'static [&'static str] {
    match k {
        FilterName::Standard => &[],
        FilterName::SageHusaFading => &["forgetting", "reserve", "lambda_max", "fade_states"],
        FilterName::ImprovedAdaptive => &[
            "forgetting",
            "reserve",
            "lambda_max",
            "significance",
            "fade_states",
        ],
        FilterName::FederatedUkf | FilterName::FederatedSrUkf => &["alpha", "beta", "kappa"],
        FilterName::IctErekf => &["significance"],
        FilterName::MaxThreshold => &["threshold_m_s", "window"],
        FilterName::FuzzyAdaptive => &["window"],
        FilterName::StrongTrackingFading => &["rho", "softening", "lambda_max", "fade_states"],
    }
}

/// The R windows the filters support (compile-time lengths).
const R_WINDOWS: [i64; 3] = [10, 20, 50];

/// The R window `w` of the entry at key path `p`, checked.
fn r_window(p: &str, w: i64) -> Res<usize> {
    if R_WINDOWS.contains(&w) {
        Ok(w as usize)
    } else {
        Err(bad(
            join(p, "window"),
            format!("must be one of 10, 20, 50, found {w}"),
        ))
    }
}

/// One `[[filters]]` entry at key path `p`.
pub(super) fn filter(p: &str, e: &FilterEntry) -> Res<FilterKind> {
    let allowed = takes(e.kind);
    let present = [
        ("forgetting", e.forgetting.is_some()),
        ("reserve", e.reserve.is_some()),
        ("lambda_max", e.lambda_max.is_some()),
        ("significance", e.significance.is_some()),
        ("alpha", e.alpha.is_some()),
        ("beta", e.beta.is_some()),
        ("kappa", e.kappa.is_some()),
        ("threshold_m_s", e.threshold_m_s.is_some()),
        ("window", e.window.is_some()),
        ("rho", e.rho.is_some()),
        ("softening", e.softening.is_some()),
        ("fade_states", e.fade_states.is_some()),
    ];
    let foreign: Vec<(&str, bool)> = present
        .into_iter()
        .filter(|(k, _)| !allowed.contains(k))
        .collect();
    let what = format!("kind = \"{}\"", kind_name(e.kind));
    let list = if allowed.is_empty() {
        "no parameters".to_string()
    } else {
        format!("`{}`", allowed.join("`, `"))
    };
    reject(p, &foreign, &what, &list)?;
    let get = |k: &str, x: Option<f64>, r: Range| -> Res<f64> {
        let key = join(p, k);
        num(&key, need(&key, x, &format!("{what} needs it"))?, r)
    };
    let forgetting = || {
        get(
            "forgetting",
            e.forgetting,
            Range::Interval(0.0, 1.0, true, false),
        )
    };
    let reserve = || get("reserve", e.reserve, Range::AtLeast(1.0));
    // ∞: no clamp.
    let lambda_max = || {
        get(
            "lambda_max",
            e.lambda_max,
            Range::Interval(1.0, f64::INFINITY, false, false),
        )
    };
    let significance = || {
        get(
            "significance",
            e.significance,
            Range::Interval(0.0, 0.5, true, true),
        )
    };
    // The papers fade the whole covariance.
    let fade_states = match e.fade_states {
        None | Some(FadeName::All) => FadeBlock::All,
        Some(FadeName::VelocityPosition) => FadeBlock::VelocityPosition,
        Some(FadeName::AttitudeVelocityPosition) => FadeBlock::AttitudeVelocityPosition,
    };
    let sigma = || -> Res<(f64, f64, f64)> {
        Ok((
            get("alpha", e.alpha, Range::Interval(0.0, 1.0, true, false))?,
            get("beta", e.beta, Range::NonNegative)?,
            get("kappa", e.kappa, Range::Any)?,
        ))
    };
    Ok(match e.kind {
        FilterName::Standard => FilterKind::Standard,
        FilterName::SageHusaFading => FilterKind::SageHusaFading {
            forgetting: forgetting()?,
            reserve: reserve()?,
            lambda_max: lambda_max()?,
            fade_states,
        },
        FilterName::ImprovedAdaptive => FilterKind::ImprovedAdaptive {
            forgetting: forgetting()?,
            reserve: reserve()?,
            lambda_max: lambda_max()?,
            significance: significance()?,
            fade_states,
        },
        FilterName::FederatedUkf => {
            let (alpha, beta, kappa) = sigma()?;
            FilterKind::FederatedUkf { alpha, beta, kappa }
        }
        FilterName::FederatedSrUkf => {
            let (alpha, beta, kappa) = sigma()?;
            FilterKind::FederatedSrUkf { alpha, beta, kappa }
        }
        FilterName::IctErekf => FilterKind::IctErekf {
            significance: significance()?,
        },
        FilterName::MaxThreshold => FilterKind::MaxThreshold {
            threshold: get("threshold_m_s", e.threshold_m_s, Range::Positive)?,
            r_window: e.window.map(|w| r_window(p, w)).transpose()?,
        },
        FilterName::FuzzyAdaptive => {
            let key = join(p, "window");
            let w = need(&key, e.window, &format!("{what} needs it"))?;
            FilterKind::FuzzyAdaptive {
                window: r_window(p, w)?,
            }
        }
        FilterName::StrongTrackingFading => FilterKind::StrongTrackingFading {
            rho: get("rho", e.rho, Range::Interval(0.0, 1.0, true, false))?,
            softening: get("softening", e.softening, Range::AtLeast(1.0))?,
            lambda_max: lambda_max()?,
            fade_states,
        },
    })
}
