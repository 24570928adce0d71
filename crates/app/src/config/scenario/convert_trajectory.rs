//! `[trajectory]` and its segments to a [`TrajectorySpec`].

use kestrel::nav::{Euler, Geodetic};
use kestrel::sim::{ClimbRate, Segment, TrajectorySpec, TurnRate, Vehicle};

use super::schema::{SegmentEntry, SegmentType, TrajectorySection, VehicleName};
use crate::config::check::{bad, join, need, num, reject, Range, Res};

/// `[trajectory]` with its `[[trajectory.segment]]`s.
pub(super) fn trajectory(t: &TrajectorySection) -> Res<TrajectorySpec> {
    let p = "trajectory";
    let lat = num(
        &join(p, "start_lat_deg"),
        t.start_lat_deg,
        Range::Interval(-90.0, 90.0, false, false),
    )?;
    let lon = num(&join(p, "start_lon_deg"), t.start_lon_deg, Range::Any)?;
    let h = num(&join(p, "start_height_m"), t.start_height_m, Range::Any)?;
    let heading = num(&join(p, "heading_deg"), t.heading_deg, Range::Any)?;
    let speed = num(&join(p, "speed_m_s"), t.speed_m_s, Range::NonNegative)?;
    let vehicle = match t.vehicle {
        VehicleName::Aircraft => Vehicle::Aircraft,
        VehicleName::Ground => Vehicle::Ground,
    };
    let mut spec = TrajectorySpec::new(
        vehicle,
        Geodetic::from_degrees(lat, lon, h),
        heading.to_radians(),
        speed,
    );
    if let Some(e) = t.edge_s {
        spec.edge = num(&join(p, "edge_s"), e, Range::NonNegative)?;
    }
    if let Some(e) = t.pitch_transition_s {
        spec.pitch_transition = num(&join(p, "pitch_transition_s"), e, Range::NonNegative)?;
    }
    if let Some(m) = t.mounting_deg {
        for (i, &x) in m.iter().enumerate() {
            num(&format!("{p}.mounting_deg[{i}]"), x, Range::Any)?;
        }
        spec.mounting = Euler::new(m[0].to_radians(), m[1].to_radians(), m[2].to_radians());
    }
    if t.segment.is_empty() {
        return Err(bad(
            join(p, "segment"),
            "at least one [[trajectory.segment]] is needed",
        ));
    }
    for (i, s) in t.segment.iter().enumerate() {
        spec.segments
            .push(segment(&format!("{p}.segment[{i}]"), s)?);
    }
    Ok(spec)
}

/// Which keys each segment type takes.
fn takes(kind: SegmentType) -> &'static [&'static str] {
    match kind {
        SegmentType::Cruise | SegmentType::Stationary => &["duration_s"],
        SegmentType::CruiseUntil => &["time_s"],
        SegmentType::Accelerate => &["accel_m_s2", "duration_s"],
        SegmentType::AccelerateTo => &["speed_m_s", "accel_m_s2"],
        SegmentType::Stop => &["decel_m_s2"],
        SegmentType::Climb => &["pitch_deg", "vertical_speed_m_s", "duration_s"],
        SegmentType::Turn => &["rate_deg_s", "radius_m", "angle_deg"],
        SegmentType::SideSlip => &["angle_deg", "duration_s"],
        SegmentType::Parallel => &["parts"],
    }
}

fn segment(p: &str, s: &SegmentEntry) -> Res<Segment> {
    let allowed = takes(s.kind);
    let present = [
        ("duration_s", s.duration_s.is_some()),
        ("time_s", s.time_s.is_some()),
        ("accel_m_s2", s.accel_m_s2.is_some()),
        ("speed_m_s", s.speed_m_s.is_some()),
        ("decel_m_s2", s.decel_m_s2.is_some()),
        ("pitch_deg", s.pitch_deg.is_some()),
        ("vertical_speed_m_s", s.vertical_speed_m_s.is_some()),
        ("rate_deg_s", s.rate_deg_s.is_some()),
        ("radius_m", s.radius_m.is_some()),
        ("angle_deg", s.angle_deg.is_some()),
        ("parts", s.parts.is_some()),
    ];
    let foreign: Vec<(&str, bool)> = present
        .into_iter()
        .filter(|(k, _)| !allowed.contains(k))
        .collect();
    let what = format!("a `{}` segment", type_name(s.kind));
    reject(p, &foreign, &what, &format!("`{}`", allowed.join("`, `")))?;
    let need_num = |k: &str, x: Option<f64>, r: Range| -> Res<f64> {
        let key = join(p, k);
        num(&key, need(&key, x, &format!("{what} needs it"))?, r)
    };
    let duration = || need_num("duration_s", s.duration_s, Range::Positive);
    Ok(match s.kind {
        SegmentType::Cruise => Segment::Cruise {
            duration: duration()?,
        },
        SegmentType::Stationary => Segment::Stationary {
            duration: duration()?,
        },
        SegmentType::CruiseUntil => Segment::CruiseUntil {
            time: need_num("time_s", s.time_s, Range::Positive)?,
        },
        SegmentType::Accelerate => Segment::Accelerate {
            accel: need_num("accel_m_s2", s.accel_m_s2, Range::Any)?,
            duration: duration()?,
        },
        SegmentType::AccelerateTo => Segment::AccelerateTo {
            speed: need_num("speed_m_s", s.speed_m_s, Range::NonNegative)?,
            accel: need_num("accel_m_s2", s.accel_m_s2, Range::Positive)?,
        },
        SegmentType::Stop => Segment::Stop {
            decel: need_num("decel_m_s2", s.decel_m_s2, Range::Positive)?,
        },
        SegmentType::Climb => Segment::Climb {
            climb: climb(p, s)?,
            duration: duration()?,
        },
        SegmentType::Turn => Segment::Turn {
            turn: turn(p, s)?,
            angle: need_num("angle_deg", s.angle_deg, Range::Any)?.to_radians(),
        },
        SegmentType::SideSlip => Segment::SideSlip {
            angle: need_num(
                "angle_deg",
                s.angle_deg,
                Range::Interval(-90.0, 90.0, true, true),
            )?
            .to_radians(),
            duration: duration()?,
        },
        SegmentType::Parallel => Segment::Parallel(parts(p, s)?),
    })
}

/// A climb's pitch (deg) or vertical speed (m/s): exactly one.
fn climb(p: &str, s: &SegmentEntry) -> Res<ClimbRate> {
    match (s.pitch_deg, s.vertical_speed_m_s) {
        (Some(d), None) => Ok(ClimbRate::Pitch(
            num(
                &join(p, "pitch_deg"),
                d,
                Range::Interval(-90.0, 90.0, true, true),
            )?
            .to_radians(),
        )),
        (None, Some(v)) => Ok(ClimbRate::Vertical(num(
            &join(p, "vertical_speed_m_s"),
            v,
            Range::Any,
        )?)),
        _ => Err(bad(
            p,
            "a `climb` segment needs exactly one of `pitch_deg`, `vertical_speed_m_s`",
        )),
    }
}

/// A turn's rate (deg/s) or radius (m): exactly one.
fn turn(p: &str, s: &SegmentEntry) -> Res<TurnRate> {
    match (s.rate_deg_s, s.radius_m) {
        (Some(r), None) => Ok(TurnRate::Rate(
            num(&join(p, "rate_deg_s"), r, Range::Positive)?.to_radians(),
        )),
        (None, Some(r)) => Ok(TurnRate::Radius(num(
            &join(p, "radius_m"),
            r,
            Range::Positive,
        )?)),
        _ => Err(bad(
            p,
            "a `turn` segment needs exactly one of `rate_deg_s`, `radius_m`",
        )),
    }
}

/// A parallel segment's parts: at least two, each a segment.
fn parts(p: &str, s: &SegmentEntry) -> Res<Vec<Segment>> {
    let parts = need(
        &join(p, "parts"),
        s.parts.as_ref(),
        "a `parallel` segment needs its `parts`",
    )?;
    if parts.len() < 2 {
        return Err(bad(join(p, "parts"), "needs at least 2 segments"));
    }
    parts
        .iter()
        .enumerate()
        .map(|(i, q)| segment(&format!("{p}.parts[{i}]"), q))
        .collect()
}

/// The file's name of a segment type.
pub(super) fn type_name(kind: SegmentType) -> &'static str {
    match kind {
        SegmentType::Cruise => "cruise",
        SegmentType::CruiseUntil => "cruise_until",
        SegmentType::Stationary => "stationary",
        SegmentType::Accelerate => "accelerate",
        SegmentType::AccelerateTo => "accelerate_to",
        SegmentType::Stop => "stop",
        SegmentType::Climb => "climb",
        SegmentType::Turn => "turn",
        SegmentType::SideSlip => "side_slip",
        SegmentType::Parallel => "parallel",
    }
}
