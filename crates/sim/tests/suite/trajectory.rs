//! Trajectory generator: closed-form derivatives, quadrature accuracy, the
//! IMU mounting, and a perfect IMU through the strapdown mechanisation.

use kestrel_nav::nalgebra::{UnitQuaternion, Vector3};
use kestrel_nav::{attitude_error, Ellipsoid, Euler, Geodetic, Strapdown};
use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};

fn aerobatic() -> Trajectory {
    Trajectory::new(&aerobatic_spec(), Ellipsoid::wgs84()).unwrap()
}

fn aerobatic_spec() -> TrajectorySpec {
    TrajectorySpec::new(
        Vehicle::Aircraft,
        Geodetic::from_degrees(40.1, 118.6, 100.0),
        30f64.to_radians(),
        0.0,
    )
    .then(Segment::Stationary { duration: 5.0 })
    .then(Segment::Accelerate {
        accel: 3.0,
        duration: 25.0,
    })
    .then(Segment::climb_pitch_deg(10.0, 40.0))
    .then(Segment::Parallel(vec![
        Segment::turn_rate_deg(3.0, 120.0),
        Segment::climb_rate(-8.0, 30.0),
        Segment::Accelerate {
            accel: 1.0,
            duration: 20.0,
        },
    ]))
    .then(Segment::turn_radius_deg(2000.0, -200.0))
    .then(Segment::side_slip_deg(4.0, 6.0))
    .then(Segment::Cruise { duration: 10.0 })
}

/// The mounting rotates the truth attitude and both increments by the
/// constant `C_v^b` and changes nothing else: `C_b^n = C_v^n C_b^v`,
/// `Δθ^b = C_v^b Δθ^v`, `Δv^b = C_v^b Δv^v` at every epoch, to rounding.
#[test]
fn mounting_rotates_truth_and_increments() {
    let mounting = Euler::from_degrees(1.0, 0.2, -0.3);
    let c_vb = mounting.to_dcm();
    let plain = aerobatic();
    let mounted = Trajectory::new(
        &aerobatic_spec().with_mounting(mounting),
        Ellipsoid::wgs84(),
    )
    .unwrap();
    assert_eq!(mounted.mounting(), mounting);
    let q_bv = mounting.to_quaternion().inverse();
    let start = mounted.initial_state();
    assert!(start.att.angle_to(&(plain.initial_state().att * q_bv)) < 1e-15);
    let mut worst = [0.0f64; 3];
    let mut n = 0;
    for ((tv, iv), (tb, ib)) in plain
        .stream(100.0)
        .unwrap()
        .zip(mounted.stream(100.0).unwrap())
    {
        assert_eq!(
            (tv.pos, tv.vel, iv.time, iv.dt),
            (tb.pos, tb.vel, ib.time, ib.dt)
        );
        worst[0] = worst[0].max(tb.att.angle_to(&(tv.att * q_bv)));
        worst[1] = worst[1].max((ib.dtheta - c_vb * iv.dtheta).norm());
        worst[2] = worst[2].max((ib.dvel - c_vb * iv.dvel).norm());
        n += 1;
    }
    assert_eq!((n, mounted.stream(100.0).unwrap().len()), (20_148, 20_148));
    println!(
        "mounting: attitude {:.1e} rad, Δθ {:.1e} rad, Δv {:.1e} m/s",
        worst[0], worst[1], worst[2]
    );
    assert!(
        worst[0] < 1e-15 && worst[1] < 1e-16 && worst[2] < 1e-14,
        "{worst:?}"
    );
}

/// Velocity rate and body rate agree with central differences of the
/// closed-form velocity and attitude.
#[test]
fn closed_form_derivatives_match_differences() {
    let traj = aerobatic();
    let d = 1e-4;
    let mut t = 0.37;
    while t < traj.duration() - 1.0 {
        let m = traj.motion_at(t);
        let (a, b) = (traj.motion_at(t - d), traj.motion_at(t + d));
        let acc = (b.vel - a.vel) / (2.0 * d);
        assert!((acc - m.acc).norm() < 1e-6, "t = {t}: {acc} vs {}", m.acc);
        // C(t−d)ᵀ C(t+d) = exp([ω× ] 2d) for the body rate over NED.
        let qa = a.euler.to_quaternion();
        let qb = b.euler.to_quaternion();
        let rel: UnitQuaternion<f64> = qa.inverse() * qb;
        let w = rel.scaled_axis() / (2.0 * d);
        assert!(
            (w - m.omega_nb).norm() < 1e-7,
            "t = {t}: {w} vs {}",
            m.omega_nb
        );
        t += 0.731;
    }
}

/// Increments are plain integrals, so five at 1 kHz add up to one at
/// 200 Hz: agreement to rounding shows the quadrature has converged.
#[test]
fn increments_are_additive_across_rates() {
    let traj = aerobatic();
    let fine: Vec<_> = traj.stream(1000.0).unwrap().map(|(_, i)| i).collect();
    let mut worst = (0.0f64, 0.0f64);
    for (k, (_, coarse)) in traj.stream(200.0).unwrap().enumerate() {
        let (mut th, mut v) = (Vector3::zeros(), Vector3::zeros());
        for f in &fine[5 * k..5 * k + 5] {
            th += f.dtheta;
            v += f.dvel;
        }
        worst.0 = worst.0.max((th - coarse.dtheta).norm());
        worst.1 = worst.1.max((v - coarse.dvel).norm());
    }
    println!(
        "max |Δθ| mismatch {:.3e} rad, |Δv| {:.3e} m/s",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-13 && worst.1 < 1e-11, "{worst:?}");
}

/// A perfect IMU through the strapdown mechanisation tracks the truth.
#[test]
fn perfect_imu_reproduces_the_aerobatic_flight() {
    let traj = aerobatic();
    let earth = *traj.earth();
    let mut ins = Strapdown::new(earth, traj.initial_state());
    let (mut dp, mut dv, mut da) = (0.0f64, 0.0f64, 0.0f64);
    for (truth, imu) in traj.stream(200.0).unwrap() {
        ins.step(&imu);
        let s = ins.state();
        dp = dp.max(earth.ned_offset(&truth.pos, &s.pos).norm());
        dv = dv.max((s.vel - truth.vel).norm());
        da = da.max(attitude_error(&s.att, &truth.att).norm());
    }
    println!("max errors: position {dp:.3e} m, velocity {dv:.3e} m/s, attitude {da:.3e} rad");
    assert!(dp < 1e-4 && dv < 1e-6 && da < 1e-8, "{dp} {dv} {da}");
}
