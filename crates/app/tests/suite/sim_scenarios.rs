//! Every built-in scenario's trajectory is flown exactly by a perfect IMU
//! through the strapdown mechanisation.

use std::time::Instant;

use kestrel::nav::{attitude_error, Strapdown};
use kestrel_app::scenario::{builtin, Scenario};

/// Maximum position (m), velocity (m/s) and attitude (rad) errors of a
/// perfect-IMU run of `s` started from the true initial state.
fn perfect_run(s: &Scenario) -> (f64, f64, f64) {
    let traj = s.trajectory().unwrap();
    let earth = s.earth;
    let mut ins = Strapdown::new(earth, traj.initial_state());
    let (mut dp, mut dv, mut da) = (0.0f64, 0.0f64, 0.0f64);
    let start = Instant::now();
    let mut n = 0usize;
    for (truth, imu) in traj.stream(s.imu_rate).unwrap() {
        ins.step(&imu);
        let est = ins.state();
        dp = dp.max(earth.ned_offset(&truth.pos, &est.pos).norm());
        dv = dv.max((est.vel - truth.vel).norm());
        da = da.max(attitude_error(&est.att, &truth.att).norm());
        n += 1;
    }
    assert_eq!(n as f64, traj.duration() * s.imu_rate);
    println!(
        "{}: {n} epochs in {:.2} s; max error position {dp:.2e} m, velocity {dv:.2e} m/s, attitude {da:.2e} rad",
        s.name,
        start.elapsed().as_secs_f64()
    );
    (dp, dv, da)
}

/// Worst over the five (scenario 004's 100 Hz, 250 m/s flight): about
/// 0.33 mm, 0.6 µm/s, 0.9 nrad.
#[test]
fn perfect_imu_reproduces_every_scenario() {
    for s in builtin() {
        let (dp, dv, da) = perfect_run(&s);
        assert!(dp < 1e-3, "{}: position error {dp} m", s.name);
        assert!(dv < 1e-5, "{}: velocity error {dv} m/s", s.name);
        assert!(da < 1e-8, "{}: attitude error {da} rad", s.name);
    }
}

#[test]
fn registry_and_durations() {
    use kestrel_app::scenario::by_name;
    let want = [
        ("000", 500.0),
        ("001", 600.0),
        ("002", 3600.0),
        ("003", 3600.0),
        ("004", 2000.0),
    ];
    for (s, (name, duration)) in builtin().iter().zip(want) {
        assert_eq!(s.name, name);
        assert_eq!(by_name(name).as_ref(), Some(s));
        assert_eq!(s.trajectory().unwrap().duration(), duration, "{name}");
        assert!(!s.description.is_empty() && !s.description.contains('\n'));
        assert_eq!(
            s.filter.p0.std_vector(s.filter.error_model).len(),
            s.filter.error_model.dimension()
        );
    }
    assert!(by_name("005").is_none());
}

/// Paper 003's route: headings and speeds on each leg, 4 m/s entering
/// each turn, the 2° uphill during 2000–2100 s.
#[test]
fn scenario_003_route() {
    let s = kestrel_app::scenario::by_name("003").unwrap();
    let t = s.trajectory().unwrap();
    for (time, heading) in [
        (250.0, 90.0),
        (800.0, 0.0),
        (1500.0, 45.0),
        (2400.0, 135.0),
        (3300.0, 90.0),
    ] {
        let m = t.motion_at(time);
        assert!((m.vel.norm() - 20.0).abs() < 1e-9, "{time}");
        let h = m.vel.y.atan2(m.vel.x).to_degrees();
        assert!(
            ((h - heading + 180.0).rem_euclid(360.0) - 180.0).abs() < 1e-9,
            "{time}: {h}"
        );
        assert!(m.euler.roll == 0.0);
    }
    assert!((t.motion_at(10.0).vel.norm() - 20.0).abs() < 1e-12);
    for turn in [500.0, 1200.0, 1900.0, 2900.0] {
        assert!((t.motion_at(turn).vel.norm() - 4.0).abs() < 1e-9, "{turn}");
    }
    let m = t.motion_at(2050.0);
    assert!((m.euler.pitch.to_degrees() - 2.0).abs() < 1e-12 && m.vel.z < 0.0);
}

/// Paper 000 and 004 flights: climbs, final speeds and headings.
#[test]
fn aircraft_profiles() {
    use kestrel_app::scenario::by_name;
    let s = by_name("000").unwrap();
    let (mut h_max, mut last) = (0.0f64, None);
    for (truth, _) in s.trajectory().unwrap().stream(10.0).unwrap() {
        h_max = h_max.max(truth.pos.h);
        last = Some(truth);
    }
    let last = last.unwrap();
    assert!((last.vel.norm() - 150.0).abs() < 1e-9);
    assert!((last.euler().yaw.to_degrees() - 120.0).abs() < 1e-9);
    assert!(h_max > 1500.0 && h_max < 1700.0, "{h_max}");

    let s = by_name("004").unwrap();
    let t = s.trajectory().unwrap();
    let m = t.motion_at(200.0);
    assert!((m.vel.norm() - 250.0).abs() < 1e-9 && (m.euler.yaw.to_degrees() - 45.0).abs() < 1e-9);
    // The hard turn banks at atan(V χ'/g₀) = 65.8°.
    let bank = t.motion_at(1712.0).euler.roll.to_degrees();
    assert!(
        (bank + (250.0 * 5f64.to_radians() / 9.80665).atan().to_degrees()).abs() < 1e-9,
        "{bank}"
    );
}

/// Paper 002's GNSS: some multipath errors exceed 20 m; outages exist.
#[test]
fn scenario_002_gnss_is_hostile() {
    use kestrel::sim::OutlierKind;
    let s = kestrel_app::scenario::by_name("002").unwrap();
    let g = s.gnss.as_ref().unwrap();
    let big = g
        .outliers
        .iter()
        .filter(|o| matches!(o.kind, OutlierKind::Patch { position_offset, .. } if position_offset.norm() > 20.0))
        .count();
    assert!(big >= 5, "{big}");
    assert!(!g.outages.is_empty() && g.lever_arm == s.filter.lever_arm);
}

/// The initial state carries exactly the configured errors.
#[test]
fn initial_errors_are_applied_exactly() {
    for s in builtin() {
        let truth = s.trajectory().unwrap().initial_state();
        let init = s.initial_state(&truth);
        let e = &s.initial_errors;
        assert!(
            (attitude_error(&init.att, &truth.att) - e.attitude).norm() < 1e-15,
            "{}",
            s.name
        );
        assert!((init.vel - truth.vel - e.velocity).norm() < 1e-12);
        assert!((s.earth.ned_offset(&truth.pos, &init.pos) - e.position).norm() < 1e-6);
    }
}

/// Generation alone (no mechanisation) of the two 1 h scenarios; prints
/// the time (the test asserts only that every epoch is produced).
#[test]
fn one_hour_generation_time() {
    for name in ["002", "003"] {
        let s = kestrel_app::scenario::by_name(name).unwrap();
        let traj = s.trajectory().unwrap();
        let start = Instant::now();
        let mut n = 0u64;
        let mut h = 0.0;
        for (truth, imu) in traj.stream(s.imu_rate).unwrap() {
            h += truth.pos.h + imu.dvel.z;
            n += 1;
        }
        println!(
            "{name}: {n} epochs generated in {:.3} s ({h:.1})",
            start.elapsed().as_secs_f64()
        );
        assert_eq!(n, 720_000);
    }
}
