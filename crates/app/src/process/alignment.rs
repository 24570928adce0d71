//! The automatic initial alignment (`[alignment]`): levelling over a static
//! window at the start, the initial gyro bias from it, and the yaw from the
//! GNSS course once moving or by gyrocompassing.
//!
//! - **Levelling.** Standing still, the accelerometers measure `−g` turned
//!   into the body: `f = g (sin θ, −sin φ cos θ, −cos φ cos θ)` (body
//!   forward-right-down), so `θ = atan2(f_x, √(f_y² + f_z²))` and
//!   `φ = atan2(−f_y, −f_z)` from the window's mean specific force. An
//!   accelerometer bias `b` tilts the result by about `b / g` (1 mg:
//!   0.06°); `[initial.std] attitude` should allow for it.
//! - **GNSS course** (`yaw = "gnss-course"`): the first fix after the
//!   window whose horizontal speed reaches `min_speed` gives the yaw
//!   `atan2(v_E, v_N)` (the vehicle moves along its forward axis: no side
//!   slip, no mounting yaw), its position (moved from the antenna to the
//!   IMU by the lever arm) and its velocity; the run starts at the last IMU
//!   sample at or before that fix, the samples in between are not
//!   processed. The course's error is about `σ_v / speed`; allow for slip.
//! - **Gyrocompassing** (`yaw = "gyrocompass"`): levelled, the gyros
//!   measure the Earth rate's horizontal part, `Ω cos L` towards north:
//!   `ψ = atan2(−ω_y, ω_x)` in the levelled frame. Only a gyro whose bias is
//!   well below `Ω cos L` (≈ 15 °/h · cos L) can do it; a measured
//!   horizontal rate outside 0.5–1.5 × `Ω cos L` is refused.
//! - **Initial gyro bias** (course alignment, `gyro_bias = true`): the
//!   window's mean rate less the Earth rate in the body axes (with the
//!   aligned attitude), added to `initial.gyro_bias`.

use std::path::Path;

use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::{Euler, ImuIncrement, NavState};

use super::pipeline::GnssInput;
use crate::config::process::{AlignmentSettings, Settings, YawSource};
use crate::{Error, InputError};
use kestrel_io::gins::ImuReader;

/// What the alignment found.
#[derive(Clone, Debug, PartialEq)]
pub struct AlignmentReport {
    /// The static window, s of week, and its IMU samples.
    pub window: (f64, f64),
    /// IMU samples in the window.
    pub samples: usize,
    /// Spread of the specific force over the window, m/s².
    pub accel_spread: f64,
    /// Roll, pitch and yaw, deg.
    pub attitude: [f64; 3],
    /// Where the yaw came from.
    pub yaw: YawSource,
    /// With the GNSS course: the fix's time and horizontal speed.
    pub course_fix: Option<(f64, f64)>,
    /// The initial gyro bias estimated, °/h, if any.
    pub gyro_bias: Option<[f64; 3]>,
    /// Where the run starts, s of week.
    pub start: f64,
}

/// Aligns `settings.start` from the IMU file (and the GNSS file for the
/// course) before the run.
pub(crate) fn align(
    imu: &Path,
    gnss: Option<&Path>,
    a: &AlignmentSettings,
    settings: &mut Settings,
) -> Result<AlignmentReport, Error> {
    let start = settings.start.time;
    let end = start + a.static_time;
    let mut reader = ImuReader::open_with_format(imu, &settings.imu_format, settings.week, start)?;
    // The static window: mean rate and specific force, and the spread.
    let (mut dtheta, mut dvel, mut seconds) = (Vector3::zeros(), Vector3::zeros(), 0.0);
    let (mut sum, mut squares) = (Vector3::<f64>::zeros(), Vector3::<f64>::zeros());
    let (mut samples, mut previous, mut last_line) = (0usize, start, 0usize);
    let mut after = None;
    for record in reader.by_ref() {
        let record = record?;
        if record.time <= start {
            continue;
        }
        if record.time > end + 1e-9 {
            after = Some(record);
            break;
        }
        let inc: ImuIncrement = record.increment(previous);
        if inc.dt > 0.0 {
            let f = inc.dvel / inc.dt;
            sum += f;
            squares += f.component_mul(&f);
            dtheta += inc.dtheta;
            dvel += inc.dvel;
            seconds += inc.dt;
            samples += 1;
        }
        previous = record.time;
        last_line = record.line;
    }
    if samples < 2 || seconds < 0.5 * a.static_time {
        return Err(InputError::file(
            imu,
            format!(
                "alignment: the IMU file has {samples} samples covering {seconds} s of the \
                 static window from initial.time {start} s (alignment.static_time = {} s): \
                 too little to level",
                a.static_time
            ),
        )
        .into());
    }
    let n = samples as f64;
    let variance = (squares - sum.component_mul(&sum) / n) / (n - 1.0);
    let spread = variance.map(|v| v.max(0.0)).sum().sqrt();
    if spread > a.max_accel_std {
        return Err(InputError::at(
            imu,
            last_line,
            1,
            format!(
                "alignment: the vehicle is not standing still from {start} s to {previous} s \
                 (specific-force spread {spread:.3} m/s² > alignment.max_accel_std = {} m/s²)",
                a.max_accel_std
            ),
        )
        .into());
    }
    let f = dvel / seconds;
    let w = dtheta / seconds;
    let roll = (-f.y).atan2(-f.z);
    let pitch = f.x.atan2((f.y * f.y + f.z * f.z).sqrt());
    let earth = settings.earth;
    let mut report = AlignmentReport {
        window: (start, previous),
        samples,
        accel_spread: spread,
        attitude: [0.0; 3],
        yaw: a.yaw,
        course_fix: None,
        gyro_bias: None,
        start: previous,
    };
    let new_start = match a.yaw {
        YawSource::Gyrocompass => {
            let lat = settings.start.pos.lat;
            let level = Euler::new(roll, pitch, 0.0).to_quaternion();
            let wl = level * w;
            let expected = earth.omega_ie * lat.cos();
            let measured = wl.x.hypot(wl.y);
            if !(0.5 * expected..=1.5 * expected).contains(&measured) {
                let dph = |x: f64| x.to_degrees() * 3600.0;
                return Err(InputError::file(
                    imu,
                    format!(
                        "alignment: gyrocompassing measured a horizontal rate of {:.2} °/h where \
                         the Earth's is {:.2} °/h at this latitude: the gyro biases are too large \
                         for it; use yaw = \"gnss-course\"",
                        dph(measured),
                        dph(expected)
                    ),
                )
                .into());
            }
            let yaw = (-wl.y).atan2(wl.x);
            NavState::new(
                previous,
                settings.start.pos,
                Vector3::zeros(),
                Euler::new(roll, pitch, yaw),
            )
        }
        YawSource::GnssCourse => {
            let Some(gnss) = gnss else {
                return Err(Error::Failed(
                    "alignment: yaw = \"gnss-course\" needs a GNSS file (--gnss)".into(),
                ));
            };
            let mut fixes = GnssInput::open(gnss, &settings.gnss_format, settings.week)?;
            let fix = loop {
                let Some(fix) = fixes.next().transpose()? else {
                    return Err(InputError::file(
                        gnss,
                        format!(
                            "alignment: no fix after {previous} s with a horizontal speed of \
                             alignment.min_speed = {} m/s or more (and a velocity)",
                            a.min_speed
                        ),
                    )
                    .into());
                };
                let Some(v) = fix.vel else {
                    if fix.time > previous {
                        return Err(InputError::file(
                            gnss,
                            "alignment: yaw = \"gnss-course\" needs GNSS velocity (13-column \
                             lines)",
                        )
                        .into());
                    }
                    continue;
                };
                if fix.time > previous && v.x.hypot(v.y) >= a.min_speed {
                    break fix;
                }
            };
            let v = fix.vel.unwrap_or_default();
            // The last IMU sample at or before the fix.
            let mut t = previous;
            let mut next = after;
            loop {
                match next {
                    Some(r) if r.time <= fix.time => t = r.time,
                    _ => break,
                }
                next = reader.next().transpose()?;
            }
            let yaw = v.y.atan2(v.x);
            let att = Euler::new(roll, pitch, yaw);
            let at_antenna = earth.displace(&fix.pos, &(-v * (fix.time - t)));
            let state = NavState::new(t, at_antenna, v, att);
            let lever = state.att * settings.lever_arm;
            let pos = earth.displace(&at_antenna, &(-lever));
            report.course_fix = Some((fix.time, v.x.hypot(v.y)));
            NavState { pos, ..state }
        }
    };
    if a.gyro_bias && a.yaw == YawSource::GnssCourse {
        let w_ie = earth.earth_rate_ned(new_start.pos.lat);
        let bias = w - new_start.att.inverse() * w_ie;
        settings.initial_imu.gyro += bias;
        let dph = |x: f64| x.to_degrees() * 3600.0;
        report.gyro_bias = Some([dph(bias.x), dph(bias.y), dph(bias.z)]);
    }
    let e = Euler::from_quaternion(&new_start.att);
    report.attitude = [e.roll, e.pitch, e.yaw].map(f64::to_degrees);
    report.start = new_start.time;
    settings.start = new_start;
    Ok(report)
}
