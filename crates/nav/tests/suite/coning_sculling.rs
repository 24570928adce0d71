//! Coning and sculling environments with the Earth rotation switched off
//! (so the navigation frame is inertial at rest and the motion is known in
//! closed form); the increments are integrals of the exact rates. The
//! two-sample coning and sculling corrections must keep the errors at the
//! level of the algorithm's residual terms, far below the uncorrected drift.

use kestrel_nav::nalgebra::{Quaternion, UnitQuaternion, Vector3};
use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavError, NavState, Strapdown};

/// Coning half-angle (rad) and angular frequency (rad/s).
const BETA: f64 = 0.02;
const OMEGA: f64 = std::f64::consts::TAU;

/// The coning attitude relative to the base attitude and its derivative.
fn cone(t: f64) -> (Quaternion<f64>, Quaternion<f64>) {
    let (s, c) = (OMEGA * t).sin_cos();
    let (sb, cb) = (0.5 * BETA).sin_cos();
    (
        Quaternion::new(cb, 0.0, sb * c, sb * s),
        Quaternion::new(0.0, 0.0, -OMEGA * sb * s, OMEGA * sb * c),
    )
}

/// Body rate `ω = 2 q* q̇` (vector part) at time `t`.
fn rate(t: f64) -> Vector3<f64> {
    let (q, dq) = cone(t);
    (q.conjugate() * dq).imag() * 2.0
}

/// Five-point Gauss–Legendre integral of `f` over `[a, b]`.
fn gauss(a: f64, b: f64, f: impl Fn(f64) -> Vector3<f64>) -> Vector3<f64> {
    const X: [f64; 5] = [
        0.0,
        -0.538_469_310_105_683,
        0.538_469_310_105_683,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
        0.236_926_885_056_189,
    ];
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    (0..5).map(|i| f(m + h * X[i]) * (W[i] * h)).sum()
}

/// Classical coning at rest: half-angle 0.02 rad, 1 Hz, 100 Hz samples.
#[test]
fn coning_at_100_hz() {
    let earth = Ellipsoid {
        omega_ie: 0.0,
        ..Ellipsoid::wgs84()
    };
    let base = Euler::from_degrees(0.0, 0.0, 30.0).to_quaternion();
    let attitude = |t: f64| base * UnitQuaternion::new_normalize(cone(t).0);
    let pos = Geodetic::from_degrees(45.0, 10.0, 0.0);
    let g = earth.gravity(pos.lat, pos.h);
    let start = NavState {
        time: 0.0,
        pos,
        vel: Vector3::zeros(),
        att: attitude(0.0),
    };
    let mut ins = Strapdown::new(earth, start);
    let dt = 0.01;
    let steps = 6000;
    for k in 1..=steps {
        let (t0, t1) = ((k - 1) as f64 * dt, k as f64 * dt);
        let imu = ImuIncrement {
            time: t1,
            dt,
            dtheta: gauss(t0, t1, rate),
            dvel: gauss(t0, t1, |t| {
                attitude(t).inverse() * Vector3::new(0.0, 0.0, -g)
            }),
        };
        ins.step(&imu);
    }
    let truth = NavState {
        att: attitude(steps as f64 * dt),
        ..start
    };
    let e = NavError::between(&earth, ins.state(), &truth);
    // Uncorrected, the coning drift rate is Ω β² (Ω Δt)² / 12 ≈ 8e-7 rad/s,
    // 5e-5 rad after 60 s; the two-sample residual is of order (Ω Δt)⁴
    // (measured: 4.7e-8 rad at 100 Hz, 3.5e-9 rad at 200 Hz).
    println!(
        "after 60 s of coning: |φ| = {:.3e} rad, |δv| = {:.3e} m/s, |δr| = {:.3e} m",
        e.phi.norm(),
        e.dv.norm(),
        e.dr.norm()
    );
    assert!(e.phi.norm() < 1e-7, "attitude error {}", e.phi.norm());
    assert!(e.dv.norm() < 5e-5, "velocity error {}", e.dv.norm());
    assert!(e.dr.norm() < 2e-3, "position error {}", e.dr.norm());
}

/// Classical sculling: roll oscillation `θ₀ sin Ωt` in phase with an east
/// acceleration `A sin Ωt` (along the body y axis), 2 Hz, 100 Hz samples.
/// The true velocity is `v_E = −(A/Ω) cos Ωt`. Without the sculling term
/// the velocity drifts by 1.7e-3 m/s over 60 s; without the second-order
/// rotation term `⅙ Δθ × (Δθ × Δv)` gravity rectifies into 3.1e-4 m/s
/// (`g ⟨|Δθ|²⟩ / 6` per step); with both the error is about 4e-6 m/s.
#[test]
fn sculling_at_100_hz() {
    let earth = Ellipsoid {
        omega_ie: 0.0,
        ..Ellipsoid::wgs84()
    };
    let (theta0, accel, omega) = (0.02, 1.0, 2.0 * std::f64::consts::TAU);
    let pos = Geodetic::from_degrees(30.0, 0.0, 0.0);
    let g = earth.gravity(pos.lat, pos.h);
    let attitude = |t: f64| Euler::new(theta0 * (omega * t).sin(), 0.0, 0.0).to_quaternion();
    let velocity = |t: f64| Vector3::new(0.0, -accel / omega * (omega * t).cos(), 0.0);
    let start = NavState {
        time: 0.0,
        pos,
        vel: velocity(0.0),
        att: attitude(0.0),
    };
    let mut ins = Strapdown::new(earth, start);
    let dt = 0.01;
    let steps = 6000;
    for k in 1..=steps {
        let (t0, t1) = ((k - 1) as f64 * dt, k as f64 * dt);
        let f_n = |t: f64| Vector3::new(0.0, accel * (omega * t).sin(), -g);
        let imu = ImuIncrement {
            time: t1,
            dt,
            dtheta: gauss(t0, t1, |t| {
                Vector3::new(theta0 * omega * (omega * t).cos(), 0.0, 0.0)
            }),
            dvel: gauss(t0, t1, |t| attitude(t).inverse() * f_n(t)),
        };
        ins.step(&imu);
    }
    let t = steps as f64 * dt;
    let s = ins.state();
    let dv = s.vel - velocity(t);
    let phi = kestrel_nav::attitude_error(&s.att, &attitude(t));
    println!(
        "after 60 s of sculling: |φ| = {:.3e} rad, |δv| = {:.3e} m/s",
        phi.norm(),
        dv.norm()
    );
    assert!(phi.norm() < 1e-8, "attitude error {}", phi.norm());
    assert!(dv.norm() < 2e-5, "velocity error {}", dv.norm());
}
