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

use kestrel_io::input::Input as In;
use std::path::Path;

use kestrel::nav::measurement::GnssFix;
use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::{Euler, ImuIncrement, NavState};

use super::outage::Outage;
use super::pipeline::GnssSource;
use super::setup::Readers;
use crate::config::process::{AlignmentSettings, Settings, YawSource};
use crate::{Error, InputError};
use kestrel_io::gins::{ImuReader, ImuRecord};

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

/// Aligns `settings.start` from the IMU stream (and the GNSS stream for the
/// course) before the run, in the run's own readers: the IMU samples read
/// past the new start go back into `readers.imu_ahead`, the GNSS fixes it
/// looked at stay buffered for the pass, and fixes in `outages` are never
/// used (as if those lines were deleted).
pub(crate) fn align(
    readers: &mut Readers,
    outages: &[Outage],
    a: &AlignmentSettings,
    settings: &mut Settings,
) -> Result<AlignmentReport, Error> {
    let start = settings.start.time;
    let imu = readers.imu.path().to_path_buf();
    let imu = imu.as_path();
    let window = StaticWindow::read(&mut readers.imu, start, start + a.static_time)?;
    let spread = window.spread(imu, a, start)?;
    let level = window.level();
    let mut report = AlignmentReport {
        window: (start, window.end),
        samples: window.samples,
        accel_spread: spread,
        attitude: [0.0; 3],
        yaw: a.yaw,
        course_fix: None,
        gyro_bias: None,
        start: window.end,
    };
    let new_start = match a.yaw {
        YawSource::Gyrocompass => {
            readers.imu_ahead.extend(window.after);
            gyrocompass(imu, &window, level, settings)?
        }
        YawSource::GnssCourse => {
            let Some(gnss) = readers.gnss.as_mut() else {
                return Err(Error::Failed(
                    "alignment: yaw = \"gnss-course\" needs a GNSS file (--gnss)".into(),
                ));
            };
            let course = Course { a, outages };
            let (state, course_fix, next) =
                gnss_course(gnss, &mut readers.imu, &window, level, &course, settings)?;
            readers.imu_ahead.extend(next);
            report.course_fix = Some(course_fix);
            state
        }
    };
    if a.gyro_bias && a.yaw == YawSource::GnssCourse {
        let w_ie = settings.earth.earth_rate_ned(new_start.pos.lat);
        let bias = window.rate() - new_start.att.inverse() * w_ie;
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

/// The static window at the start: the sums over its IMU samples.
struct StaticWindow {
    /// The summed angle and velocity increments and their time span, s.
    dtheta: Vector3<f64>,
    dvel: Vector3<f64>,
    seconds: f64,
    /// The sum and the sum of squares of the specific force, per sample
    /// (for its spread).
    sum: Vector3<f64>,
    squares: Vector3<f64>,
    /// Samples summed.
    samples: usize,
    /// The time and line of the last sample in the window (its start
    /// before any).
    end: f64,
    last_line: usize,
    /// The first sample after the window.
    after: Option<ImuRecord>,
}

impl StaticWindow {
    /// Sums the samples of `reader` after `start` up to `end`.
    fn read(reader: &mut ImuReader<In>, start: f64, end: f64) -> Result<Self, Error> {
        let mut w = Self {
            dtheta: Vector3::zeros(),
            dvel: Vector3::zeros(),
            seconds: 0.0,
            sum: Vector3::zeros(),
            squares: Vector3::zeros(),
            samples: 0,
            end: start,
            last_line: 0,
            after: None,
        };
        for record in reader.by_ref() {
            let record = record?;
            if record.time <= start {
                continue;
            }
            if record.time > end + 1e-9 {
                w.after = Some(record);
                break;
            }
            let inc: ImuIncrement = record.increment(w.end);
            if inc.dt > 0.0 {
                let f = inc.dvel / inc.dt;
                w.sum += f;
                w.squares += f.component_mul(&f);
                w.dtheta += inc.dtheta;
                w.dvel += inc.dvel;
                w.seconds += inc.dt;
                w.samples += 1;
            }
            w.end = record.time;
            w.last_line = record.line;
        }
        Ok(w)
    }

    /// The spread of the specific force over the window, m/s²; an error
    /// when the window is too short to level or the vehicle moved.
    fn spread(&self, imu: &Path, a: &AlignmentSettings, start: f64) -> Result<f64, Error> {
        let (samples, seconds) = (self.samples, self.seconds);
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
        let variance = (self.squares - self.sum.component_mul(&self.sum) / n) / (n - 1.0);
        let spread = variance.map(|v| v.max(0.0)).sum().sqrt();
        if spread > a.max_accel_std {
            return Err(InputError::at(
                imu,
                self.last_line,
                1,
                format!(
                    "alignment: the vehicle is not standing still from {start} s to {} s \
                     (specific-force spread {spread:.3} m/s² > alignment.max_accel_std = {} m/s²)",
                    self.end, a.max_accel_std
                ),
            )
            .into());
        }
        Ok(spread)
    }

    /// The mean angular rate over the window, rad/s.
    fn rate(&self) -> Vector3<f64> {
        self.dtheta / self.seconds
    }

    /// Roll and pitch from the mean specific force, rad.
    fn level(&self) -> (f64, f64) {
        let f = self.dvel / self.seconds;
        let roll = (-f.y).atan2(-f.z);
        let pitch = f.x.atan2((f.y * f.y + f.z * f.z).sqrt());
        (roll, pitch)
    }
}

/// The start at the window's end, levelled by `(roll, pitch)`, its yaw
/// from the Earth rate the gyros measured; an error when the measured
/// horizontal rate is not the Earth's (gyro biases too large for it).
fn gyrocompass(
    imu: &Path,
    window: &StaticWindow,
    (roll, pitch): (f64, f64),
    settings: &Settings,
) -> Result<NavState, Error> {
    let lat = settings.start.pos.lat;
    let level = Euler::new(roll, pitch, 0.0).to_quaternion();
    let wl = level * window.rate();
    let expected = settings.earth.omega_ie * lat.cos();
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
    Ok(NavState::new(
        window.end,
        settings.start.pos,
        Vector3::zeros(),
        Euler::new(roll, pitch, yaw),
    ))
}

/// What the course alignment looks for: the settings and the outages it
/// must skip.
struct Course<'a> {
    a: &'a AlignmentSettings,
    outages: &'a [Outage],
}

/// The start a GNSS course gives: the state, the fix's (time, horizontal
/// speed), and the first IMU sample after the start (read ahead).
type CourseStart = (NavState, (f64, f64), Option<ImuRecord>);

/// The start at the last IMU sample at or before the first fix after the
/// window fast enough for a course: levelled by `(roll, pitch)`, the yaw
/// from the course, the fix's velocity and its position moved back to
/// that sample and from the antenna to the IMU. Also the fix's time and
/// horizontal speed, and the first IMU sample after the start (read ahead).
fn gnss_course(
    gnss: &mut GnssSource,
    reader: &mut ImuReader<In>,
    window: &StaticWindow,
    (roll, pitch): (f64, f64),
    course: &Course<'_>,
    settings: &Settings,
) -> Result<CourseStart, Error> {
    let fix = moving_fix(gnss, window.end, course)?;
    let v = fix.vel.unwrap_or_default();
    // The last IMU sample at or before the fix.
    let mut t = window.end;
    let mut next = window.after;
    loop {
        match next {
            Some(r) if r.time <= fix.time => t = r.time,
            _ => break,
        }
        next = reader.next().transpose()?;
    }
    let earth = settings.earth;
    let yaw = v.y.atan2(v.x);
    let att = Euler::new(roll, pitch, yaw);
    let at_antenna = earth.displace(&fix.pos, &(-v * (fix.time - t)));
    let state = NavState::new(t, at_antenna, v, att);
    let lever = state.att * settings.lever_arm;
    let pos = earth.displace(&at_antenna, &(-lever));
    Ok((NavState { pos, ..state }, (fix.time, v.x.hypot(v.y)), next))
}

/// The first fix after `after` outside the outages whose horizontal speed
/// reaches `min_speed`, looked at ahead in the pass's GNSS stream; an
/// error when there is none or the fixes have no velocity.
fn moving_fix(gnss: &mut GnssSource, after: f64, course: &Course<'_>) -> Result<GnssFix, Error> {
    let a = course.a;
    let mut i = 0;
    loop {
        let fix = if i < MAX_LOOKAHEAD {
            gnss.ahead(i)?.copied()
        } else {
            None
        };
        i += 1;
        let Some(fix) = fix else {
            if let Some(e) = gnss.take_failure() {
                return Err(e.into());
            }
            return Err(InputError::file(
                gnss.path(),
                format!(
                    "alignment: no fix after {after} s outside the outages with a horizontal \
                     speed of alignment.min_speed = {} m/s or more (and a velocity){}",
                    a.min_speed,
                    if i > MAX_LOOKAHEAD {
                        format!(" in the first {MAX_LOOKAHEAD} fixes")
                    } else {
                        String::new()
                    }
                ),
            )
            .into());
        };
        if course.outages.iter().any(|o| o.contains(fix.time)) {
            continue;
        }
        let Some(v) = fix.vel else {
            if fix.time > after {
                return Err(InputError::file(
                    gnss.path(),
                    "alignment: yaw = \"gnss-course\" needs GNSS velocity (13-column lines)",
                )
                .into());
            }
            continue;
        };
        if fix.time > after && v.x.hypot(v.y) >= a.min_speed {
            return Ok(fix);
        }
    }
}

/// The most GNSS fixes the course alignment looks ahead for a moving one
/// (they stay in memory for the pass: about 100 MB at most).
const MAX_LOOKAHEAD: usize = 1_000_000;
