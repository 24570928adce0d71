//! Schuler oscillation of a stationary INS with an initial velocity error.

use crate::common_ins;

use common_ins::stationary_increment;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown};

/// A 1 mm/s north velocity error on a perfect stationary INS at 34°N makes
/// the north position error oscillate with the Schuler period
/// `2π √(R/g) ≈ 84.4 min`. The vertical channel is held at the true height
/// (it is unstable and would otherwise grow from rounding over six hours).
/// The period is measured from the zero crossings of the north error over
/// six hours (eight half periods) at 10 Hz.
#[test]
fn schuler_period_is_84_4_minutes() {
    let earth = Ellipsoid::wgs84();
    let truth = NavState::new(
        0.0,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        Vector3::zeros(),
        Euler::from_degrees(0.0, 0.0, -90.0),
    );
    let dt = 0.1;
    let mut imu = stationary_increment(&earth, &truth, dt);
    let mut ins = Strapdown::new(
        earth,
        NavState {
            vel: Vector3::new(1e-3, 0.0, 0.0),
            ..truth
        },
    );
    let rm = earth.meridian_radius(truth.pos.lat) + truth.pos.h;
    let steps = (6.0 * 3600.0 / dt) as usize;
    let mut crossings = Vec::new();
    let mut peak = 0.0_f64;
    let mut prev = 0.0_f64;
    for k in 1..=steps {
        imu.time = k as f64 * dt;
        ins.step(&imu);
        let s = ins.state_mut();
        s.pos.h = truth.pos.h;
        s.vel.z = 0.0;
        let north = (s.pos.lat - truth.pos.lat) * rm;
        peak = peak.max(north.abs());
        if k > 1 && prev != 0.0 && prev.signum() != north.signum() {
            // Linear interpolation of the crossing inside the step.
            crossings.push(imu.time - dt * north / (north - prev));
        }
        prev = north;
    }
    // Least-squares slope of crossing time against index = half period.
    let n = crossings.len() as f64;
    assert!(crossings.len() >= 7, "{} crossings", crossings.len());
    let mean_i = (n - 1.0) / 2.0;
    let mean_t = crossings.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, t) in crossings.iter().enumerate() {
        let di = i as f64 - mean_i;
        sxy += di * (t - mean_t);
        sxx += di * di;
    }
    let period_min = 2.0 * sxy / sxx / 60.0;
    // Expected from the local radius and gravity: ω_s = √(g / R).
    let g = earth.gravity(truth.pos.lat, truth.pos.h);
    let omega_s = (g / rm).sqrt();
    let expected_min = std::f64::consts::TAU / omega_s / 60.0;
    println!(
        "Schuler period {period_min:.3} min (√(R_M/g) gives {expected_min:.3} min), \
         {} crossings, peak north error {peak:.4} m (v₀/ω_s = {:.4} m)",
        crossings.len(),
        1e-3 / omega_s
    );
    assert!(
        (period_min - 84.4).abs() < 0.01 * 84.4,
        "period {period_min} min"
    );
    // The amplitude of the north error is v₀ / ω_s (Earth-rate coupling
    // rotates a little of it into east over six hours: 2 % allowance).
    assert!((peak - 1e-3 / omega_s).abs() < 0.02 * 1e-3 / omega_s);
}
