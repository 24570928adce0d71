//! Sensor models: noise statistics, Markov correlation, windows and faults
//! applied exactly where configured, reproducible seeds.

use kestrel_nav::measurement::GnssFix;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState};
use kestrel_sim::{
    sensor_rng, GaussMarkov, GnssConfig, GnssSensor, ImuErrors, ImuSensor, NoiseWindow,
    OdometerConfig, OdometerFault, OdometerSensor, Outlier, OutlierKind, ReportedStd, Segment,
    SensorStream, Simulated, TimeWindow, Trajectory, TrajectorySpec, Vehicle,
};

fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|a| (a - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, v.sqrt())
}

fn zero_increment(t: f64, dt: f64) -> ImuIncrement {
    ImuIncrement {
        time: t,
        dt,
        dtheta: Vector3::zeros(),
        dvel: Vector3::zeros(),
    }
}

/// White noise of density N integrates to σ = N √Δt per increment, at any
/// rate. 100 000 samples per axis: the sample σ is within 1.1 % (5σ of its
/// estimator) and the mean within 5 σ/√n.
#[test]
fn white_noise_std_per_increment() {
    let arw = 0.1f64.to_radians() / 60.0; // 0.1 °/√h
    let vrw = 50e-6 * 9.80665; // 50 µg/√Hz
    for dt in [0.005, 0.02] {
        let mut e = ImuErrors::perfect();
        e.gyro_arw = Vector3::repeat(arw);
        e.accel_vrw = Vector3::new(vrw, 2.0 * vrw, 0.5 * vrw);
        let mut imu = ImuSensor::new(e, 11);
        let n = 100_000;
        let mut th = [vec![], vec![], vec![]];
        let mut dv = [vec![], vec![], vec![]];
        for k in 0..n {
            let m = imu.corrupt(&zero_increment(k as f64 * dt, dt));
            for i in 0..3 {
                th[i].push(m.dtheta[i]);
                dv[i].push(m.dvel[i]);
            }
        }
        for i in 0..3 {
            for (x, sigma) in [
                (&th[i], arw * dt.sqrt()),
                (&dv[i], e.accel_vrw[i] * dt.sqrt()),
            ] {
                let (m, s) = mean_std(x);
                assert!(
                    (s / sigma - 1.0).abs() < 0.011,
                    "dt {dt} axis {i}: {s} vs {sigma}"
                );
                assert!(m.abs() < 5.0 * sigma / (n as f64).sqrt(), "mean {m}");
            }
        }
    }
}

/// Constant bias and scale factor enter exactly: Δθ' = (1 + s)Δθ + b Δt.
#[test]
fn bias_and_scale_are_exact() {
    let mut e = ImuErrors::perfect();
    e.gyro_bias = Vector3::new(1e-5, -2e-5, 3e-5);
    e.gyro_scale = Vector3::new(1e-3, 0.0, -5e-4);
    e.accel_bias = Vector3::new(0.01, 0.02, -0.03);
    e.accel_scale = Vector3::new(0.003, 0.003, 0.003);
    let mut imu = ImuSensor::new(e, 5);
    let exact = ImuIncrement {
        time: 0.01,
        dt: 0.01,
        dtheta: Vector3::new(0.002, -0.001, 0.0005),
        dvel: Vector3::new(0.05, 0.0, -0.098),
    };
    let m = imu.corrupt(&exact);
    let want_th = exact.dtheta + e.gyro_scale.component_mul(&exact.dtheta) + e.gyro_bias * 0.01;
    let want_v = exact.dvel + e.accel_scale.component_mul(&exact.dvel) + e.accel_bias * 0.01;
    assert!((m.dtheta - want_th).norm() < 1e-18);
    assert!((m.dvel - want_v).norm() < 1e-17);
    assert_eq!((m.time, m.dt), (exact.time, exact.dt));
}

/// The discrete Gauss–Markov process has variance σ² and one-step
/// regression coefficient e^{−Δt/τ}, and correlation e^{−1} at lag τ.
#[test]
fn gauss_markov_statistics() {
    let (sigma, tau, dt) = (2.0, 1.0, 0.01);
    let mut rng = sensor_rng(21, SensorStream::Imu);
    let mut m = GaussMarkov::new(sigma, tau, &mut rng);
    let n = 2_000_000;
    let mut x = Vec::with_capacity(n);
    for _ in 0..n {
        m.step(dt, &mut rng);
        x.push(m.value());
    }
    let (mean, s) = mean_std(&x);
    // 2·10⁴ correlation times: σ of the variance estimate ≈ √(2τ/T) = 1 %.
    assert!(
        (s * s / (sigma * sigma) - 1.0).abs() < 0.05,
        "variance {}",
        s * s
    );
    assert!(mean.abs() < 0.1, "mean {mean}");
    let corr = |lag: usize| {
        let c: f64 = x
            .iter()
            .zip(&x[lag..])
            .map(|(a, b)| (a - mean) * (b - mean))
            .sum();
        c / (n - lag) as f64 / (s * s)
    };
    let phi = (-dt / tau).exp();
    let num: f64 = x.iter().zip(&x[1..]).map(|(a, b)| a * b).sum();
    let den: f64 = x[..n - 1].iter().map(|a| a * a).sum();
    assert!((num / den - phi).abs() < 5e-4, "φ {} vs {phi}", num / den);
    assert!(
        (corr(100) - (-1.0f64).exp()).abs() < 0.03,
        "ρ(τ) = {}",
        corr(100)
    );
    assert!(corr(500).abs() < 0.04, "ρ(5τ) = {}", corr(500));
}

/// The IMU's Markov drift integrates into the increments: with only a
/// drift of long τ, Δθ/Δt equals the drift (mean of the step's ends).
#[test]
fn imu_markov_drift_enters_the_increments() {
    let mut e = ImuErrors::perfect();
    e.gyro_markov_sigma = Vector3::repeat(1e-4);
    e.gyro_markov_tau = Vector3::repeat(100.0);
    let mut imu = ImuSensor::new(e, 8);
    let before = imu.markov().0;
    assert!(before.norm() > 0.0);
    let m = imu.corrupt(&zero_increment(0.01, 0.01));
    let after = imu.markov().0;
    assert!((m.dtheta / 0.01 - 0.5 * (before + after)).norm() < 1e-18);
    assert_eq!(imu.biases().0, after);
}

fn still(t: f64) -> NavState {
    NavState::new(
        t,
        Geodetic::from_degrees(40.1, 118.6, 100.0),
        Vector3::new(3.0, -4.0, 0.5),
        Euler::from_degrees(1.0, 2.0, 30.0),
    )
}

/// Runs `gnss` on `still` truth for `seconds` s at its own rate.
fn fixes(gnss: &mut GnssSensor, seconds: f64) -> Vec<Simulated<GnssFix>> {
    let rate = gnss.config().rate;
    (1..=(seconds * rate) as u64)
        .filter_map(|k| gnss.sample(&still(k as f64 / rate), &Vector3::zeros()))
        .collect()
}

/// Per-window noise: σ 0.3 → 1.5 → 0.3 → 3 m/s, position σ (5, 5, 8) m
/// throughout; 5000 fixes per window, σ estimates within 3 % (5σ).
#[test]
fn gnss_noise_follows_the_windows() {
    let earth = Ellipsoid::krasovsky();
    let mut c = GnssConfig::new(
        100.0,
        Vector3::new(5.0, 5.0, 8.0),
        Some(Vector3::repeat(0.3)),
    );
    c.noise_windows = vec![
        NoiseWindow::velocity(TimeWindow::new(50.0, 100.0), Vector3::repeat(1.5)),
        NoiseWindow::velocity(TimeWindow::new(150.0, 200.0), Vector3::repeat(3.0)),
    ];
    c.reported_std = ReportedStd::Actual;
    let mut g = GnssSensor::new(c, earth, 77);
    let all = fixes(&mut g, 200.0);
    assert_eq!(all.len(), 20_000);
    for (w, sv) in [
        ((0.0, 50.0), 0.3),
        ((50.0, 100.0), 1.5),
        ((100.0, 150.0), 0.3),
        ((150.0, 200.0), 3.0),
    ] {
        let inside: Vec<_> = all
            .iter()
            .filter(|f| f.value.time >= w.0 && f.value.time < w.1)
            .collect();
        for axis in 0..3 {
            let ve: Vec<f64> = inside
                .iter()
                .map(|f| f.value.vel.unwrap()[axis] - still(0.0).vel[axis])
                .collect();
            let pe: Vec<f64> = inside
                .iter()
                .map(|f| earth.ned_offset(&still(0.0).pos, &f.value.pos)[axis])
                .collect();
            let (_, s) = mean_std(&ve);
            assert!((s / sv - 1.0).abs() < 0.03, "window {w:?} axis {axis}: {s}");
            let sp = [5.0, 5.0, 8.0][axis];
            let (_, s) = mean_std(&pe);
            assert!((s / sp - 1.0).abs() < 0.03, "window {w:?} axis {axis}: {s}");
        }
        assert!(inside
            .iter()
            .all(|f| f.value.vel_std == Vector3::repeat(sv) && !f.faulty));
    }
}

/// Without white noise, a patch adds exactly a uniform ±15 m/s on north and
/// east inside [350, 360) and nothing elsewhere; fixes are flagged exactly
/// there, and the nominal σ is reported throughout.
#[test]
fn gnss_patch_outliers_are_confined_to_their_window() {
    let mut c = GnssConfig::new(10.0, Vector3::zeros(), Some(Vector3::zeros()));
    c.outliers = vec![Outlier::velocity_patch(
        TimeWindow::new(350.0, 360.0),
        Vector3::new(15.0, 15.0, 0.0),
    )];
    c.reported_std = ReportedStd::Nominal;
    let earth = Ellipsoid::wgs84();
    let mut g = GnssSensor::new(c, earth, 3);
    let all = fixes(&mut g, 400.0);
    let (mut inside, mut peak) = (0, 0.0f64);
    for Simulated { value: f, faulty } in &all {
        let e = f.vel.unwrap() - still(f.time).vel;
        let p = earth.ned_offset(&still(f.time).pos, &f.pos).norm();
        assert!(p < 1e-6, "position disturbed at {}", f.time);
        if (350.0..360.0).contains(&f.time) {
            inside += 1;
            assert!(*faulty && e.x.abs() <= 15.0 && e.y.abs() <= 15.0 && e.z.abs() < 1e-12);
            peak = peak.max(e.x.abs()).max(e.y.abs());
        } else {
            assert!(!faulty && e.norm() < 1e-12, "t {} error {e}", f.time);
        }
        assert_eq!(f.vel_std, Vector3::zeros());
    }
    assert_eq!(inside, 100);
    assert!(
        peak > 13.0,
        "uniform ±15 m/s should come near its peak in 200 draws: {peak}"
    );
}

/// Spikes hit a fraction p of fixes (100 000 fixes, p = 0.02: 2000 ± 220,
/// 5σ) with sizes inside the configured range.
#[test]
fn gnss_spike_rate_and_size() {
    let mut c = GnssConfig::new(100.0, Vector3::zeros(), Some(Vector3::zeros()));
    c.outliers = vec![Outlier {
        window: TimeWindow::new(0.0, 2000.0),
        kind: OutlierKind::Spikes {
            probability: 0.02,
            position: (20.0, 40.0),
            velocity: (1.0, 2.0),
        },
    }];
    let earth = Ellipsoid::wgs84();
    let mut g = GnssSensor::new(c, earth, 99);
    let all = fixes(&mut g, 1000.0);
    let hits: Vec<_> = all.iter().filter(|f| f.faulty).map(|f| f.value).collect();
    assert!(
        (hits.len() as f64 - 2000.0).abs() < 220.0,
        "{} hits",
        hits.len()
    );
    for f in &hits {
        let p = earth.ned_offset(&still(f.time).pos, &f.pos).norm();
        let v = (f.vel.unwrap() - still(f.time).vel).norm();
        assert!(
            (20.0 - 1e-6..=40.0 + 1e-6).contains(&p) && (1.0..=2.0).contains(&v),
            "{p} {v}"
        );
    }
}

/// No fixes inside outages; fixes at every multiple of 1/rate elsewhere.
#[test]
fn gnss_outages_drop_exactly_their_fixes() {
    let mut c = GnssConfig::new(1.0, Vector3::repeat(1.0), None);
    c.outages = vec![TimeWindow::new(10.0, 20.0), TimeWindow::starting(30.5, 2.0)];
    let mut g = GnssSensor::new(c, Ellipsoid::wgs84(), 1);
    // Poll at 200 Hz as a simulation loop does.
    let times: Vec<f64> = (1..=40 * 200)
        .filter_map(|k| g.sample(&still(k as f64 / 200.0), &Vector3::zeros()))
        .map(|f| f.value.time)
        .collect();
    let want: Vec<f64> = (1..=40)
        .map(f64::from)
        .filter(|t| !(10.0..20.0).contains(t) && !(30.5..32.5).contains(t))
        .collect();
    assert_eq!(times, want);
    assert!(fixes(
        &mut GnssSensor::new(
            GnssConfig::new(1.0, Vector3::zeros(), None),
            Ellipsoid::wgs84(),
            0
        ),
        3.0
    )
    .iter()
    .all(|f| f.value.vel.is_none()));
}

/// Same seed, same numbers; another seed, other numbers; adding an outlier
/// window changes no fix outside it (separate random streams).
#[test]
fn seeds_are_reproducible_and_streams_independent() {
    let c = GnssConfig::new(1.0, Vector3::repeat(5.0), Some(Vector3::repeat(0.3)));
    let earth = Ellipsoid::wgs84();
    let a = fixes(&mut GnssSensor::new(c.clone(), earth, 42), 100.0);
    let b = fixes(&mut GnssSensor::new(c.clone(), earth, 42), 100.0);
    let other = fixes(&mut GnssSensor::new(c.clone(), earth, 43), 100.0);
    assert_eq!(a, b);
    assert!(a
        .iter()
        .zip(&other)
        .all(|(x, y)| x.value.pos != y.value.pos));
    let mut with_patch = c.clone();
    with_patch.outliers = vec![Outlier::position_patch(
        TimeWindow::new(40.0, 50.0),
        Vector3::repeat(10.0),
        Vector3::repeat(2.0),
    )];
    let p = fixes(&mut GnssSensor::new(with_patch, earth, 42), 100.0);
    for (x, y) in a.iter().zip(&p) {
        let (x, y) = (&x.value, &y.value);
        assert_eq!(
            x.pos == y.pos,
            !(40.0..50.0).contains(&x.time),
            "t = {}",
            x.time
        );
    }

    let mut e = ImuErrors::perfect();
    e.gyro_arw = Vector3::repeat(1e-4);
    e.accel_markov_sigma = Vector3::repeat(1e-3);
    e.accel_markov_tau = Vector3::repeat(60.0);
    let run = |seed| {
        let mut s = ImuSensor::new(e, seed);
        (1..100)
            .map(|k| s.corrupt(&zero_increment(k as f64 * 0.01, 0.01)))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(7), run(7));
    assert_ne!(run(7), run(8));
}

/// Odometer on a vehicle whose IMU is mounted at pitch 0.2°, yaw −0.3°: it
/// reads the vehicle's forward speed while the IMU body sees the velocity
/// off its own x axis; the scale error and the three faults apply exactly
/// inside their windows (no noise, so every reading is checkable).
#[test]
fn odometer_faults_apply_exactly_in_their_windows() {
    let (pitch, yaw) = (0.2f64.to_radians(), -0.3f64.to_radians());
    let mut c = OdometerConfig::new(10.0);
    c.scale_error = 0.005;
    c.faults = vec![
        OdometerFault::wheel_spin(TimeWindow::starting(600.0, 3.0), 1.5),
        OdometerFault::skid(TimeWindow::starting(1600.0, 3.0), 0.25),
        OdometerFault::roll_slip(TimeWindow::new(2000.0, 2100.0), 1.0, 1.3),
    ];
    let mut odo = OdometerSensor::new(c, Ellipsoid::wgs84(), 4);
    // Driving straight at 20 m/s, heading 135°.
    let spec = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        135f64.to_radians(),
        20.0,
    )
    .then(Segment::Cruise { duration: 2200.0 })
    .with_mounting(Euler::new(0.0, pitch, yaw));
    let traj = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    let mut stream = traj.stream(10.0).unwrap();
    // C_v^b e₁: the vehicle's forward axis in body axes.
    let forward = Vector3::new(
        pitch.cos() * yaw.cos(),
        pitch.cos() * yaw.sin(),
        -pitch.sin(),
    );
    let (mut n, mut slip_factors) = (0, vec![]);
    while let Some((truth, _)) = stream.next() {
        let t = truth.time;
        let v_body = truth.att.inverse() * truth.vel;
        assert!((v_body - 20.0 * forward).norm() < 1e-9, "t {t}: {v_body}");
        assert!((odo.true_speed(&truth, stream.motion()) - 20.0).abs() < 1e-12);
        let r = odo.sample(&truth, stream.motion()).unwrap();
        assert_eq!(r.value.time, t);
        let f = r.value.speed / (1.005 * 20.0);
        if (600.0..603.0).contains(&t) {
            assert!((f - 1.5).abs() < 1e-12 && r.faulty);
        } else if (1600.0..1603.0).contains(&t) {
            assert!((f - 0.25).abs() < 1e-12 && r.faulty);
        } else if (2000.0..2100.0).contains(&t) {
            assert!((1.0..1.3).contains(&f) && r.faulty);
            slip_factors.push(f);
        } else {
            assert!((f - 1.0).abs() < 1e-12 && !r.faulty, "t {t}: {f}");
        }
        n += 1;
    }
    assert_eq!(n, 22_000);
    assert_eq!(slip_factors.len(), 1000);
    let (m, s) = mean_std(&slip_factors);
    // Uniform on [1, 1.3]: mean 1.15, σ 0.3/√12 = 0.0866.
    assert!(
        (m - 1.15).abs() < 0.02 && (s - 0.0866).abs() < 0.01,
        "{m} {s}"
    );
}

/// The simulated odometer is what the filter's measurement model predicts
/// from the truth: along a drive with turns, a grade and speed changes, an
/// IMU mounted at roll 0.5°, pitch 0.2°, yaw −0.3° and the exact body
/// rate, the forward row of `Odometer::forward_nhc` vanishes for a wheel
/// at any lever arm, and the constraint rows too for a wheel at the IMU
/// (the point the trajectory moves along the vehicle's forward axis; the
/// filter's mounting has no roll, which the constraint does not see).
#[test]
fn odometer_matches_the_filter_model() {
    use kestrel_nav::engine::Ins15;
    use kestrel_nav::measurement::{InsContext, Odometer};
    use kestrel_nav::ImuSpec;
    let earth = Ellipsoid::wgs84();
    let (pitch, yaw) = (0.2f64.to_radians(), -0.3f64.to_radians());
    let spec = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        0.4,
        5.0,
    )
    .then(Segment::Accelerate {
        accel: 1.5,
        duration: 10.0,
    })
    .then(Segment::turn_rate_deg(8.0, 120.0))
    .then(Segment::climb_pitch_deg(3.0, 20.0))
    .then(Segment::turn_radius_deg(30.0, -90.0))
    .with_mounting(Euler::new(0.5f64.to_radians(), pitch, yaw));
    let traj = Trajectory::new(&spec, earth).unwrap();
    let lever = Vector3::new(-1.2, 0.4, 0.9);
    let mut with_arm = OdometerConfig::new(10.0);
    with_arm.lever_arm = lever;
    let mut sensors = [
        OdometerSensor::new(with_arm, earth, 0),
        OdometerSensor::new(OdometerConfig::new(10.0), earth, 0),
    ];
    let models = [
        Odometer::new(0.1, 0.1)
            .with_mounting(pitch, yaw)
            .with_lever_arm(lever),
        Odometer::new(0.1, 0.1).with_mounting(pitch, yaw),
    ];
    let layout = Ins15::new(ImuSpec::perfect());
    let mut stream = traj.stream(100.0).unwrap();
    let (mut n, mut worst) = (0, [0.0f64; 2]);
    while let Some((truth, _)) = stream.next() {
        let ins = InsContext::new(earth, truth, stream.angular_rate());
        for k in 0..2 {
            let Some(r) = sensors[k].sample(&truth, stream.motion()) else {
                continue;
            };
            let z = models[k]
                .forward_nhc::<f64, 15, _>(&layout, &ins, &r.value, 0.0)
                .z();
            worst[k] = worst[k].max(if k == 0 { z.x.abs() } else { z.norm() });
            n += 1;
        }
    }
    println!("filter model vs simulated odometer: {worst:?} m/s over {n} readings");
    assert_eq!(n, 2 * (traj.duration() * 10.0).floor() as usize);
    assert!(worst[0] < 1e-9 && worst[1] < 1e-9, "{worst:?}");
}

/// A side-slip manoeuvre moves the vehicle sideways; the odometer sees only
/// the forward component V cos β, and the trajectory's body velocity has
/// the lateral part V sin β.
#[test]
fn odometer_does_not_see_side_slip() {
    let spec = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(34.0, 120.0, 0.0),
        0.3,
        15.0,
    )
    .then(Segment::Cruise { duration: 1.0 })
    .then(Segment::side_slip_deg(10.0, 4.0))
    .then(Segment::Cruise { duration: 1.0 });
    let traj = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    let mut odo = OdometerSensor::new(OdometerConfig::new(200.0), Ellipsoid::wgs84(), 0);
    let mut stream = traj.stream(200.0).unwrap();
    // Through t = 3 s, the middle of the slip: β = 10°.
    for _ in 0..600 {
        let (truth, _) = stream.next().unwrap();
        let r = odo.sample(&truth, stream.motion()).unwrap();
        assert!(r.value.speed <= 15.0 + 1e-12);
    }
    let truth = traj.initial_state();
    let m = traj.motion_at(3.0);
    let v_body = m.c_bn.transpose() * m.vel;
    let beta = 10f64.to_radians();
    assert!((v_body - Vector3::new(15.0 * beta.cos(), 15.0 * beta.sin(), 0.0)).norm() < 1e-12);
    let state = NavState {
        time: 3.0,
        pos: truth.pos,
        vel: m.vel,
        att: m.euler.to_quaternion(),
    };
    assert!((odo.true_speed(&state, &m) - 15.0 * beta.cos()).abs() < 1e-12);
}

/// The GNSS lever arm: the antenna sits at C_b^n l from the IMU and its
/// reported velocity is the derivative of its position (fourth-order
/// central differences in the middle point's NED frame, along a turning,
/// banking flight).
#[test]
fn gnss_lever_arm_position_and_velocity() {
    let spec = TrajectorySpec::new(
        Vehicle::Aircraft,
        Geodetic::from_degrees(30.0, 114.0, 500.0),
        0.0,
        80.0,
    )
    .then(Segment::turn_rate_deg(6.0, 90.0));
    let traj = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
    let earth = *traj.earth();
    let mut c = GnssConfig::new(1.0, Vector3::zeros(), None);
    c.lever_arm = Vector3::new(1.5, -0.5, -2.0);
    let g = GnssSensor::new(c.clone(), earth, 0);
    let rate = 200.0;
    let mut stream = traj.stream(rate).unwrap();
    let mut hist = vec![];
    while let Some((truth, _)) = stream.next() {
        let (p, v) = g.antenna(&truth, &stream.motion().omega_nb);
        let arm = earth.ned_offset(&truth.pos, &p);
        assert!((arm - truth.att * c.lever_arm).norm() < 1e-6);
        hist.push((p, v));
    }
    let mut worst = 0.0f64;
    let bps = traj.breakpoints();
    for (k, w) in hist.windows(5).enumerate() {
        // Skip stencils across a jump of the angular acceleration.
        let (t0, t1) = ((k + 1) as f64 / rate, (k + 5) as f64 / rate);
        if bps.iter().any(|&b| b > t0 - 1e-9 && b < t1 + 1e-9) {
            continue;
        }
        let o = |k: usize| earth.ned_offset(&w[2].0, &w[k].0);
        let d = (o(0) - 8.0 * o(1) + 8.0 * o(3) - o(4)) * (rate / 12.0);
        worst = worst.max((d - w[2].1).norm());
    }
    // The lever-arm term itself is up to 0.19 m/s here.
    assert!(worst < 1e-6, "{worst}");
}
