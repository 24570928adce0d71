//! A perfect IMU at rest: the mechanisation must hold the solution.

use crate::common_ins;

use common_ins::stationary_increment;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavError, NavState, Strapdown};

/// One hour at 100 Hz with perfect increments: position within 1 mm,
/// velocity within 1 µm/s, attitude within 1 nrad (rounding only).
#[test]
fn stationary_one_hour_holds_position_to_a_millimetre() {
    let earth = Ellipsoid::wgs84();
    let start = NavState::new(
        0.0,
        Geodetic::from_degrees(40.1, 118.6, 100.0),
        Vector3::zeros(),
        Euler::from_degrees(2.0, -3.0, 135.0),
    );
    let dt = 0.01;
    let mut imu = stationary_increment(&earth, &start, dt);
    let mut ins = Strapdown::new(earth, start);
    let steps = 360_000;
    let mut worst = 0.0_f64;
    for k in 1..=steps {
        imu.time = k as f64 * dt;
        ins.step(&imu);
        if k % 1000 == 0 {
            let e = NavError::between(&earth, ins.state(), &start);
            worst = worst.max(e.dr.norm());
        }
    }
    let e = NavError::between(&earth, ins.state(), &start);
    println!(
        "after 1 h: |δr| = {:.3e} m (worst {:.3e}), |δv| = {:.3e} m/s, |φ| = {:.3e} rad",
        e.dr.norm(),
        worst,
        e.dv.norm(),
        e.phi.norm()
    );
    assert!((ins.state().time - 3600.0).abs() < 1e-6);
    assert!(worst < 1e-3, "position drifted {worst} m");
    assert!(e.dv.norm() < 1e-6);
    assert!(e.phi.norm() < 1e-9);
}

/// The same on the Krasovsky ellipsoid at the equator with a level body,
/// and at 200 Hz for ten minutes.
#[test]
fn stationary_krasovsky_200_hz() {
    let earth = Ellipsoid::krasovsky();
    let start = NavState::new(
        0.0,
        Geodetic::from_degrees(0.0, -70.0, 0.0),
        Vector3::zeros(),
        Euler::default(),
    );
    let dt = 0.005;
    let mut imu = stationary_increment(&earth, &start, dt);
    let mut ins = Strapdown::new(earth, start);
    for k in 1..=120_000 {
        imu.time = k as f64 * dt;
        ins.step(&imu);
    }
    let e = NavError::between(&earth, ins.state(), &start);
    assert!(e.dr.norm() < 1e-4, "position drifted {} m", e.dr.norm());
    assert!(e.dv.norm() < 1e-7);
}
