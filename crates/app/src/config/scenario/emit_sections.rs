//! The tables of a written scenario file, in reading order.

use crate::scenario::Scenario;
use kestrel::nav::nalgebra::Vector3;
use kestrel::sim::{ClimbRate, Segment, TurnRate, Vehicle};

use super::emit_filters::{filter, filter_entry};
use super::emit_sensors::{gnss, imu, odometer};
use crate::config::names::EarthName;
use crate::config::units::{ANGLE, DEG, SI};
use crate::config::write::{number, Writer};

/// Writes every table of `s`.
pub(super) fn write(w: &mut Writer, s: &Scenario) {
    header(w, s);
    trajectory(w, s);
    imu(w, s);
    if let Some(g) = &s.gnss {
        gnss(w, g);
    }
    if let Some(o) = &s.odometer {
        odometer(w, o);
    }
    if let Some(a) = &s.attitude {
        w.table(
            "attitude",
            false,
            "Attitude reference (e.g. a multi-antenna receiver).",
        );
        w.num("rate_hz", a.rate, "measurement rate, Hz");
        w.quantity(
            "std",
            &ANGLE,
            a.std,
            "white attitude error σ about north, east, down",
        );
    }
    initial_errors(w, s);
    filter(w, s);
    for f in &s.filters {
        filter_entry(w, f);
    }
}

fn header(w: &mut Writer, s: &Scenario) {
    w.table("scenario", false, "What the scenario is.");
    w.string("name", &s.name, "short name (tables, plots, output files)");
    w.string("description", &s.description, "one line");
    w.raw(
        "seed",
        &s.seed.to_string(),
        "default random seed (--seed overrides)",
    );
    let name = EarthName::of(&s.earth).unwrap_or_default();
    let base = name.ellipsoid();
    w.string(
        "earth",
        name.name(),
        "ellipsoid: \"wgs84\", \"grs80\" or \"krasovsky\"",
    );
    // Another ellipsoid: its constants as overrides of WGS 84's.
    let e = &s.earth;
    let overrides = [
        ("earth_a_m", e.a, base.a, "semi-major axis, m"),
        ("earth_flattening", e.f, base.f, "flattening"),
        (
            "earth_omega_rad_s",
            e.omega_ie,
            base.omega_ie,
            "rotation rate, rad/s",
        ),
        (
            "earth_gm_m3_s2",
            e.gm,
            base.gm,
            "gravitational constant GM, m³/s²",
        ),
    ];
    for (key, value, named_value, comment) in overrides {
        if value.to_bits() != named_value.to_bits() {
            w.num(key, value, comment);
        }
    }
}

fn trajectory(w: &mut Writer, s: &Scenario) {
    let t = &s.trajectory;
    w.table(
        "trajectory",
        false,
        "The motion: a start, then manoeuvres in order.",
    );
    let vehicle = match t.vehicle {
        Vehicle::Aircraft => "aircraft",
        Vehicle::Ground => "ground",
    };
    w.string(
        "vehicle",
        vehicle,
        "\"aircraft\" banks into turns, \"ground\" stays level",
    );
    w.quantity(
        "start_lat",
        &[&DEG],
        Vector3::repeat(t.start.lat),
        "start latitude",
    );
    w.quantity(
        "start_lon",
        &[&DEG],
        Vector3::repeat(t.start.lon),
        "start longitude",
    );
    w.num("start_height_m", t.start.h, "start ellipsoidal height, m");
    w.quantity(
        "heading",
        &[&DEG],
        Vector3::repeat(t.heading),
        "initial track, from north towards east",
    );
    w.num(
        "speed_m_s",
        t.speed,
        "initial speed, m/s (level, along the heading)",
    );
    w.num(
        "edge_s",
        t.edge,
        "raised-cosine edge of speed and turn-rate changes, s",
    );
    w.num(
        "pitch_transition_s",
        t.pitch_transition,
        "pitch transition into and out of climbs, s",
    );
    let m = &t.mounting;
    let m_deg = [m.roll, m.pitch, m.yaw].map(|a| number(decimal_deg(a)));
    w.raw(
        "mounting_deg",
        &format!("[{}, {}, {}]", m_deg[0], m_deg[1], m_deg[2]),
        "vehicle frame in IMU axes: roll, pitch, yaw, °",
    );
    for (i, seg) in t.segments.iter().enumerate() {
        let comment = if i == 0 {
            "Segments. type = cruise (duration_s) | cruise_until (time_s, absolute) |\nstationary (duration_s) | accelerate (accel_m_s2, duration_s) |\naccelerate_to (speed_m_s, accel_m_s2) | stop (decel_m_s2) |\nclimb (pitch_deg or vertical_speed_m_s, duration_s) |\nturn (rate_deg_s or radius_m, angle_deg: + right) | side_slip (angle_deg, duration_s) |\nparallel (parts = [ {…}, {…} ], flown together)."
        } else {
            ""
        };
        w.table("trajectory.segment", true, comment);
        let (kind, fields) = segment(seg);
        w.raw("type", &format!("\"{kind}\""), type_comment(kind));
        for (k, v) in fields {
            w.raw(&k, &v, key_comment(kind, &k));
        }
    }
}

/// What a segment type does, in a few words.
fn type_comment(kind: &str) -> &'static str {
    match kind {
        "cruise" => "constant velocity",
        "cruise_until" => "constant velocity until an absolute time",
        "stationary" => "at rest",
        "accelerate" => "speed change at a mean acceleration",
        "accelerate_to" => "speed change to a target speed",
        "stop" => "decelerate to rest",
        "climb" => "climb or descend (a road grade on the ground)",
        "turn" => "heading change",
        "side_slip" => "yaw away from the track and back",
        _ => "manoeuvres flown together",
    }
}

/// What a segment key means, with its unit.
fn key_comment(kind: &str, key: &str) -> &'static str {
    match key {
        "duration_s" => "length, s",
        "time_s" => "end time from the start, s",
        "accel_m_s2" if kind == "accelerate_to" => "mean acceleration magnitude, m/s²",
        "accel_m_s2" => "mean acceleration, m/s² (negative slows down)",
        "speed_m_s" => "target speed, m/s",
        "decel_m_s2" => "mean deceleration, m/s²",
        "pitch_deg" => "flight-path angle, ° (negative descends)",
        "vertical_speed_m_s" => "vertical speed, m/s (negative descends)",
        "rate_deg_s" => "turn rate, °/s",
        "radius_m" => "turn radius, m",
        "angle_deg" if kind == "side_slip" => "peak slip angle, °",
        "angle_deg" => "heading change, ° (positive turns right)",
        _ => "each { type = …, … } as a segment of its own",
    }
}

/// A radian angle as the shortest exact number of degrees.
pub(super) fn decimal_deg(a: f64) -> f64 {
    let mut w = Writer::default();
    w.quantity("x", &[&DEG], Vector3::repeat(a), "");
    w.out
        .trim()
        .trim_start_matches("x_deg = ")
        .parse()
        .unwrap_or_else(|_| a.to_degrees())
}

/// A segment's type and its keys with values in TOML syntax.
fn segment(s: &Segment) -> (&'static str, Vec<(String, String)>) {
    let n = |k: &str, x: f64| (k.to_string(), number(x));
    let deg = |k: &str, x: f64| (k.to_string(), number(decimal_deg(x)));
    match s {
        Segment::Cruise { duration } => ("cruise", vec![n("duration_s", *duration)]),
        Segment::CruiseUntil { time } => ("cruise_until", vec![n("time_s", *time)]),
        Segment::Stationary { duration } => ("stationary", vec![n("duration_s", *duration)]),
        Segment::Accelerate { accel, duration } => (
            "accelerate",
            vec![n("accel_m_s2", *accel), n("duration_s", *duration)],
        ),
        Segment::AccelerateTo { speed, accel } => (
            "accelerate_to",
            vec![n("speed_m_s", *speed), n("accel_m_s2", *accel)],
        ),
        Segment::Stop { decel } => ("stop", vec![n("decel_m_s2", *decel)]),
        Segment::Climb { climb, duration } => {
            let c = match climb {
                ClimbRate::Pitch(p) => deg("pitch_deg", *p),
                ClimbRate::Vertical(v) => n("vertical_speed_m_s", *v),
            };
            ("climb", vec![c, n("duration_s", *duration)])
        }
        Segment::Turn { turn, angle } => {
            let t = match turn {
                TurnRate::Rate(r) => deg("rate_deg_s", *r),
                TurnRate::Radius(r) => n("radius_m", *r),
            };
            ("turn", vec![t, deg("angle_deg", *angle)])
        }
        Segment::SideSlip { angle, duration } => (
            "side_slip",
            vec![deg("angle_deg", *angle), n("duration_s", *duration)],
        ),
        Segment::Parallel(parts) => {
            let inline: Vec<String> = parts
                .iter()
                .map(|p| {
                    let (kind, fields) = segment(p);
                    let body: Vec<String> = std::iter::once(format!("type = \"{kind}\""))
                        .chain(fields.into_iter().map(|(k, v)| format!("{k} = {v}")))
                        .collect();
                    format!("{{ {} }}", body.join(", "))
                })
                .collect();
            (
                "parallel",
                vec![("parts".into(), format!("[{}]", inline.join(", ")))],
            )
        }
    }
}

fn initial_errors(w: &mut Writer, s: &Scenario) {
    let e = &s.initial_errors;
    w.table(
        "initial_errors",
        false,
        "Where the navigation starts: truth plus these errors (NED).",
    );
    w.quantity(
        "attitude",
        &ANGLE,
        e.attitude,
        "attitude error φ north, east, down: deg, arcmin or arcsec",
    );
    w.quantity("velocity_m_s", &[&SI], e.velocity, "velocity error, m/s");
    w.quantity("position_m", &[&SI], e.position, "position error, m");
}
