//! The `kestrel process` configuration matching a scenario's filter set-up,
//! filled in as the configuration file's own types and written by the TOML
//! library.

use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::NavState;

use crate::config::filter::Keys;
use crate::config::names::{EarthName, ErrorModelName};
use crate::config::process::schema::{
    Exact, File, Filter, Gnss, GnssNoiseSource, ImuTable, Initial, Odometer, Output, P0Table, V3,
};
use crate::config::units::{Unit, DEG_PER_H, DEG_PER_SQRT_H, M_S_PER_SQRT_H, PPM, UG};
use crate::config::vec3::V3 as ConfigV3;
use crate::config::write::commented_toml;
use crate::experiment::PositionAxes;
use crate::scenario::{ErrorModelKind, FilterKind, FilterSetup, InitialUncertainty, Scenario};
use kestrel_io::gins::degrees_exact;

/// Three numbers as a table value (written as one number when they are
/// equal).
fn one_or_three(v: [f64; 3]) -> ConfigV3 {
    ConfigV3(v)
}

/// `v` (SI) in `unit`, each value the one that converts back exactly.
fn v3(v: &Vector3<f64>, unit: &Unit) -> V3 {
    Exact([unit.exact(v.x), unit.exact(v.y), unit.exact(v.z)])
}

/// The `[filter]` keys of `kind` (the standard EKF's if `process` does not
/// run it).
fn kind_keys(kind: &FilterKind) -> Keys {
    let kind = if kind.is_federated() {
        &FilterKind::Standard
    } else {
        kind
    };
    let mut keys = Keys::new();
    keys.insert("kind".into(), toml::Value::String(kind.name().into()));
    for p in kind.params() {
        let value = match p.value {
            crate::scenario::ParamValue::Number(x) => toml::Value::Float(x),
            crate::scenario::ParamValue::Window(w) => toml::Value::Integer(w as i64),
            crate::scenario::ParamValue::Fade(b) => toml::Value::String(b.name().into()),
        };
        keys.insert(p.key.into(), value);
    }
    keys
}

/// The configuration text for `scenario` starting from `start` (the
/// scenario's initial state with its initial errors), running `kind`
/// (the standard EKF if `process` does not run `kind`).
///
/// ```
/// use kestrel_app::simulate::process_config;
/// let s = kestrel_app::scenario::by_name("002").unwrap();
/// let truth = s.trajectory().unwrap().initial_state();
/// let text = process_config(&s, &s.initial_state(&truth), &s.filters[1]);
/// let set = kestrel_app::config::process::parse(&text, "p.toml".as_ref()).unwrap();
/// // The filter's noise model; the turn-on biases go to P0 and scale
/// // factors are not states, so `process` has no keys for them.
/// let m = s.filter.imu_model;
/// assert_eq!(set.imu, kestrel::nav::ImuSpec { gyro_bias: 0.0, accel_bias: 0.0,
///     gyro_scale: 0.0, accel_scale: 0.0, ..m });
/// assert_eq!(set.start.pos, s.initial_state(&truth).pos);
/// ```
pub fn process_config(scenario: &Scenario, start: &NavState, kind: &FilterKind) -> String {
    let fs = &scenario.filter;
    let file = File {
        earth: EarthName::of(&scenario.earth).unwrap_or_default(),
        initial: initial(start, &fs.p0, fs),
        imu: imu(fs),
        filter: Filter {
            error_model: ErrorModelName::of(&fs.error_model),
            covariance_interval: Some(0.1),
            lever_arm: v3(&fs.lever_arm, &crate::config::units::SI),
            kind: kind_keys(kind),
        },
        gnss: gnss(fs),
        odometer: odometer(scenario),
        nhc: None,
        zupt: None,
        alignment: None,
        output: Output {
            interval: Some(0.0),
            position_axes: PositionAxes::for_scenario(&scenario.name),
        },
        imu_file: None,
        gnss_file: None,
        truth_file: None,
    };
    let mut header = vec![
        format!(
            "`kestrel process` configuration for scenario {}:",
            scenario.name
        ),
        scenario.description.clone(),
        "Every key is explained in crates/app/configs/process-example.toml.".to_string(),
    ];
    if kind.is_federated() {
        header.push(format!(
            "`process` does not run the {}; the standard EKF instead.",
            kind.label()
        ));
    }
    commented_toml(&file, &header, &[]).unwrap_or_else(|e| format!("# cannot write: {e}\n"))
}

/// `[initial]` and `[initial.std]`: the start and P0.
fn initial(start: &NavState, p: &InitialUncertainty, fs: &FilterSetup) -> Initial {
    let e = start.euler();
    let ins21 = matches!(fs.error_model, ErrorModelKind::Ins21 { .. });
    Initial {
        week: 0,
        time: start.time,
        position: Some(Exact([
            degrees_exact(start.pos.lat),
            degrees_exact(start.pos.lon),
            start.pos.h,
        ])),
        velocity: Some(Exact(start.vel.into())),
        attitude: Some(Exact([e.roll, e.pitch, e.yaw].map(degrees_exact))),
        gyro_bias: None,
        accel_bias: None,
        gyro_scale: None,
        accel_scale: None,
        std: P0Table {
            attitude: Some(one_or_three(
                [p.attitude.x, p.attitude.y, p.attitude.z].map(degrees_exact),
            )),
            velocity: Some(one_or_three(p.velocity.into())),
            position: Some(one_or_three(p.position.into())),
            gyro_bias: Some(one_or_three(v3(&p.gyro_bias, &DEG_PER_H).0)),
            gyro_markov: Some(one_or_three(v3(&p.gyro_markov, &DEG_PER_H).0)),
            accel_bias: Some(one_or_three(v3(&p.accel_bias, &UG).0)),
            odometer_scale: Some(p.odometer_scale),
            gyro_scale: ins21.then(|| one_or_three(v3(&p.gyro_scale, &PPM).0)),
            accel_scale: ins21.then(|| one_or_three(v3(&p.accel_scale, &PPM).0)),
            ..P0Table::default()
        },
    }
}

/// `[imu]`: the filter's noise model (the turn-on biases are P0; scale
/// factors are states of `ins21` only).
fn imu(fs: &FilterSetup) -> ImuTable {
    let m = &fs.imu_model;
    let one = |x: f64| Some(ConfigV3([x; 3]));
    let mut imu = ImuTable {
        gyro_arw: one(DEG_PER_SQRT_H.exact(m.gyro_arw)),
        accel_vrw: one(M_S_PER_SQRT_H.exact(m.accel_vrw)),
        gyro_markov_sigma: one(DEG_PER_H.exact(m.gyro_markov_sigma)),
        gyro_markov_tau: one(m.gyro_markov_tau),
        accel_markov_sigma: one(UG.exact(m.accel_markov_sigma)),
        accel_markov_tau: one(m.accel_markov_tau),
        ..ImuTable::default()
    };
    if let ErrorModelKind::Ins21 { scale_tau } = fs.error_model
        && scale_tau.is_finite()
    {
        imu.scale_tau = Some(scale_tau);
        imu.gyro_scale_sigma = Some(PPM.exact(m.gyro_scale));
        imu.accel_scale_sigma = Some(PPM.exact(m.accel_scale));
    }
    imu
}

/// `[gnss]`: the scenario's R, or each fix's σ without one.
fn gnss(fs: &FilterSetup) -> Gnss {
    match (fs.r.position, fs.r.velocity) {
        (Some(pos), Some(vel)) => Gnss {
            noise: GnssNoiseSource::Fixed,
            position_std: Some(Exact(pos.into())),
            velocity_std: Some(Exact(vel.into())),
        },
        _ => Gnss::default(),
    }
}

/// `[odometer]` of the 16-state model.
fn odometer(sc: &Scenario) -> Option<Odometer> {
    let fs = &sc.filter;
    let (Some(o), Some(r), ErrorModelKind::Odometer16 { scale_tau }) =
        (&sc.odometer, fs.r.odometer, fs.error_model)
    else {
        return None;
    };
    Some(Odometer {
        rate: o.rate,
        speed_std: r.x,
        nhc_std: r.y,
        mounting: Exact(fs.odometer_mounting.map(degrees_exact)),
        lever_arm: Exact::default(),
        scale_tau,
        scale_sigma: o.scale_markov_sigma,
    })
}
