//! Shared set-up of the navigation benchmarks: a starting solution, an IMU
//! specification and a deterministic stream of IMU increments of a
//! manoeuvring vehicle at 200 Hz.
#![allow(dead_code)]

use kestrel::nav::nalgebra::Vector3;
use kestrel::nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState};

/// IMU sample interval, s (200 Hz).
pub const IMU_DT: f64 = 0.005;

/// The Earth model of the benchmarks.
pub fn earth() -> Ellipsoid {
    Ellipsoid::wgs84()
}

/// A vehicle at 30°N moving north-east at 20 m/s.
pub fn start_state() -> NavState {
    NavState::new(
        0.0,
        Geodetic::from_degrees(30.0, 114.0, 20.0),
        Vector3::new(15.0, 13.0, 0.0),
        Euler::from_degrees(1.0, -2.0, 41.0),
    )
}

/// A tactical-grade IMU (paper 002's SPAN-FSAS figures).
pub fn spec() -> ImuSpec {
    ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(0.75)
        .with_gyro_arw_deg_per_sqrt_h(0.1)
        .with_gyro_markov_deg_per_h(0.75, 3600.0)
        .with_accel_bias_mg(1.0)
        .with_accel_vrw_ug_per_sqrt_hz(50.0)
        .with_accel_markov_ug(1000.0, 3600.0)
}

/// `n` increments of a turning, accelerating vehicle (bounded motion, so
/// the solution stays finite however long a benchmark cycles them).
pub fn increments(n: usize) -> Vec<ImuIncrement> {
    let g = earth().gravity(30f64.to_radians(), 20.0);
    (1..=n)
        .map(|k| {
            let t = (k as f64 - 0.5) * IMU_DT;
            let w = Vector3::new(0.02 * (0.7 * t).sin(), 0.01 * (0.4 * t).cos(), 0.1);
            let f = Vector3::new(0.3 * (0.2 * t).sin(), 2.0 * (0.1 * t).cos(), -g);
            ImuIncrement::from_rates(k as f64 * IMU_DT, IMU_DT, w, f)
        })
        .collect()
}
