//! The `kestrel process` configuration matching a scenario's filter set-up.

use std::fmt::Write;

use crate::experiment::PositionAxes;
use crate::scenario::{ErrorModelKind, FilterKind, Scenario};
use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::NavState;

use crate::config::names::EarthName;
use crate::config::units::{DEG_PER_H, DEG_PER_SQRT_H, M_S_PER_SQRT_H, UG};
use kestrel_io::gins::{degrees_exact, invert_exact};

/// `x` in a unit whose conversion to SI is `to_si` (by the factor `per`),
/// chosen so that the conversion gives back exactly `x` where possible.
fn inv(x: f64, per: f64, to_si: fn(f64) -> f64) -> f64 {
    invert_exact(x, x / per, to_si)
}

/// A TOML float (`{:?}` keeps a decimal point and round-trips).
fn f(x: f64) -> String {
    format!("{x:?}")
}

fn v3(v: &Vector3<f64>, each: impl Fn(f64) -> f64) -> String {
    format!("[{}, {}, {}]", f(each(v.x)), f(each(v.y)), f(each(v.z)))
}

/// The `[filter]` lines of `kind` (`None` if `process` does not run it).
fn filter_lines(kind: &FilterKind) -> Option<String> {
    if kind.is_federated() {
        return None;
    }
    let mut lines = format!("kind = \"{}\"\n", kind.name());
    for p in kind.params() {
        let _ = writeln!(lines, "{} = {}", p.key, p.value);
    }
    Some(lines)
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
    let sc = scenario;
    let fs = &sc.filter;
    let mut t = String::new();
    let w = &mut t;
    let _ = writeln!(
        w,
        "# `kestrel process` configuration for scenario {}:",
        sc.name
    );
    let _ = writeln!(w, "# {}", sc.description);
    let _ = writeln!(
        w,
        "# Every key is explained in crates/app/configs/process-example.toml."
    );
    let _ = writeln!(
        w,
        "earth = \"{}\"\n",
        EarthName::of(&sc.earth).unwrap_or_default().name()
    );

    let e = start.euler();
    let _ = writeln!(w, "[initial]\nweek = 0\ntime = {}", f(start.time));
    let _ = writeln!(
        w,
        "position = [{}, {}, {}]",
        f(degrees_exact(start.pos.lat)),
        f(degrees_exact(start.pos.lon)),
        f(start.pos.h)
    );
    let _ = writeln!(w, "velocity = {}", v3(&start.vel, |x| x));
    let _ = writeln!(
        w,
        "attitude = {}\n",
        v3(&Vector3::new(e.roll, e.pitch, e.yaw), degrees_exact)
    );
    let p = &fs.p0;
    let dph = |x| inv(x, DEG_PER_H.si(1.0), DEG_PER_H.to_si);
    let _ = writeln!(w, "[initial.std]");
    let _ = writeln!(w, "attitude = {}", v3(&p.attitude, degrees_exact));
    let _ = writeln!(w, "velocity = {}", v3(&p.velocity, |x| x));
    let _ = writeln!(w, "position = {}", v3(&p.position, |x| x));
    let _ = writeln!(w, "gyro_bias = {}", v3(&p.gyro_bias, dph));
    let _ = writeln!(w, "gyro_markov = {}", v3(&p.gyro_markov, dph));
    let _ = writeln!(
        w,
        "accel_bias = {}",
        v3(&p.accel_bias, |x| inv(x, UG.si(1.0), UG.to_si))
    );
    let _ = writeln!(w, "odometer_scale = {}", f(p.odometer_scale));
    if let ErrorModelKind::Ins21 { .. } = fs.error_model {
        let _ = writeln!(w, "gyro_scale = {}", v3(&p.gyro_scale, |x| x * 1e6));
        let _ = writeln!(w, "accel_scale = {}", v3(&p.accel_scale, |x| x * 1e6));
    }
    let _ = writeln!(w);

    let m = &fs.imu_model;
    let _ = writeln!(w, "[imu]");
    let _ = writeln!(
        w,
        "gyro_arw = {}",
        f(inv(
            m.gyro_arw,
            DEG_PER_SQRT_H.si(1.0),
            DEG_PER_SQRT_H.to_si
        ))
    );
    let _ = writeln!(
        w,
        "accel_vrw = {}",
        f(inv(
            m.accel_vrw,
            M_S_PER_SQRT_H.si(1.0),
            M_S_PER_SQRT_H.to_si
        ))
    );
    let _ = writeln!(w, "gyro_markov_sigma = {}", f(dph(m.gyro_markov_sigma)));
    let _ = writeln!(w, "gyro_markov_tau = {}", f(m.gyro_markov_tau));
    let _ = writeln!(
        w,
        "accel_markov_sigma = {}",
        f(inv(m.accel_markov_sigma, UG.si(1.0), UG.to_si))
    );
    let _ = writeln!(w, "accel_markov_tau = {}", f(m.accel_markov_tau));
    if let ErrorModelKind::Ins21 { scale_tau } = fs.error_model
        && scale_tau.is_finite()
    {
        let _ = writeln!(w, "scale_tau = {}", f(scale_tau));
        let _ = writeln!(w, "gyro_scale_sigma = {}", f(m.gyro_scale * 1e6));
        let _ = writeln!(w, "accel_scale_sigma = {}", f(m.accel_scale * 1e6));
    }
    let _ = writeln!(w);

    let _ = writeln!(w, "[filter]");
    let lines = filter_lines(kind).unwrap_or_else(|| {
        format!(
            "# `process` does not run the {}; the standard EKF instead.\nkind = \"ekf\"\n",
            kind.label()
        )
    });
    let _ = write!(w, "{lines}");
    let model = match fs.error_model {
        ErrorModelKind::Ins15 => "ins15",
        ErrorModelKind::Ins18 => "ins18",
        ErrorModelKind::Ins21 { .. } => "ins21",
        ErrorModelKind::Odometer16 { .. } => "odometer16",
    };
    let _ = writeln!(w, "error_model = \"{model}\"\ncovariance_interval = 0.1");
    let _ = writeln!(w, "lever_arm = {}\n", v3(&fs.lever_arm, |x| x));

    let _ = writeln!(w, "[gnss]");
    match (fs.r.position, fs.r.velocity) {
        (Some(pos), Some(vel)) => {
            let _ = writeln!(w, "noise = \"fixed\"");
            let _ = writeln!(w, "position_std = {}", v3(&pos, |x| x));
            let _ = writeln!(w, "velocity_std = {}\n", v3(&vel, |x| x));
        }
        _ => {
            let _ = writeln!(w, "noise = \"file\"\n");
        }
    }

    if let (Some(o), Some(r), ErrorModelKind::Odometer16 { scale_tau }) =
        (&sc.odometer, fs.r.odometer, fs.error_model)
    {
        let [pitch, yaw] = fs.odometer_mounting;
        let _ = writeln!(w, "[odometer]\nrate = {}", f(o.rate));
        let _ = writeln!(w, "speed_std = {}\nnhc_std = {}", f(r.x), f(r.y));
        let _ = writeln!(
            w,
            "mounting = [{}, {}]",
            f(degrees_exact(pitch)),
            f(degrees_exact(yaw))
        );
        let _ = writeln!(
            w,
            "scale_tau = {}\nscale_sigma = {}\n",
            f(scale_tau),
            f(o.scale_markov_sigma)
        );
    }

    let axes = match PositionAxes::for_scenario(&sc.name) {
        PositionAxes::EastNorthUp => "enu",
        PositionAxes::NorthEastDown => "ned",
    };
    let _ = writeln!(w, "[output]\ninterval = 0.0\nposition_axes = \"{axes}\"");
    t
}
