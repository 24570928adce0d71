//! Accuracy of the strapdown mechanisation with a perfect IMU: every
//! Earth-related term is second-order accurate (the errors fall fourfold
//! when the rate doubles), and latitude and longitude do not accumulate
//! rounding on a steady course.

use kestrel::nav::{Ellipsoid, Geodetic, Strapdown};
use kestrel::sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
use kestrel_app::scenario::scenario_000;

/// Largest position (m) and velocity (m/s) errors of a perfect-IMU run of
/// `traj` at `rate` Hz.
fn max_errors(traj: &Trajectory, rate: f64) -> (f64, f64) {
    let earth = *traj.earth();
    let mut ins = Strapdown::new(earth, traj.initial_state());
    let (mut dp, mut dv) = (0.0f64, 0.0f64);
    for (truth, imu) in traj.stream(rate).unwrap() {
        ins.step(&imu);
        let s = ins.state();
        dp = dp.max(earth.ned_offset(&truth.pos, &s.pos).norm());
        dv = dv.max((s.vel - truth.vel).norm());
    }
    (dp, dv)
}

/// Scenario 000's flight (climbs, turns, 150 m/s, 500 s) and half an hour
/// due north at 20 m/s, at 100 and 200 Hz: a first-order term (e.g. a
/// mid-interval velocity without the Coriolis acceleration, or a
/// mid-interval latitude extrapolated with the equatorial radius, which
/// biases gravity and so the vertical channel) would make the ratios 2.
#[test]
fn errors_are_second_order_in_the_step() {
    let north = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        0.0,
        20.0,
    )
    .then(Segment::Cruise { duration: 1800.0 });
    let cases = [
        ("000", scenario_000().trajectory().unwrap(), 1e-4, 1e-7),
        (
            "north",
            Trajectory::new(&north, Ellipsoid::wgs84()).unwrap(),
            1e-6,
            1e-8,
        ),
    ];
    for (name, traj, pos_max, vel_max) in cases {
        let (p1, v1) = max_errors(&traj, 100.0);
        let (p2, v2) = max_errors(&traj, 200.0);
        println!(
            "{name}: 100 Hz {p1:.3e} m, {v1:.3e} m/s; 200 Hz {p2:.3e} m, {v2:.3e} m/s; \
             ratios {:.2}, {:.2}",
            p1 / p2,
            v1 / v2
        );
        assert!(p1 / p2 > 3.5 && v1 / v2 > 3.5, "{name}");
        assert!(p2 < pos_max && v2 < vel_max, "{name}: {p2} {v2}");
    }
}

/// Half an hour due east at 20 m/s and 200 Hz: the longitude increment is
/// the same every step, so plain summation rounds the same way every time
/// (about 30 µm here); the compensated summation keeps the whole error
/// below a few µm.
#[test]
fn steady_course_accumulates_no_rounding() {
    let spec = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        90f64.to_radians(),
        20.0,
    )
    .then(Segment::Cruise { duration: 1800.0 });
    let traj = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    let (dp, dv) = max_errors(&traj, 200.0);
    println!("due east, 30 min: {dp:.3e} m, {dv:.3e} m/s");
    assert!(dp < 5e-6, "{dp} m");
}
