//! Paper 003: fuzzy adaptive KF for SINS / odometer (dead-reckoning)
//! integration with odometer faults.

use kestrel::nalgebra::Vector3;

use super::{
    v3, ErrorModelKind, FilterKind, FilterSetup, InitialErrors, InitialUncertainty,
    MeasurementKind, MeasurementNoise, Scenario,
};
use crate::config::units::{ARCMIN, DEG_PER_H, UG};
use kestrel::nav::attitude::Euler;
use kestrel::nav::earth::Ellipsoid;
use kestrel::nav::geodetic::Geodetic;
use kestrel::nav::imu_spec::ImuSpec;
use kestrel::sim::{
    ImuErrors, OdometerConfig, OdometerFault, Segment, TimeWindow, TrajectorySpec, Vehicle,
};

/// Paper 003's experiment.
///
/// **As stated:** 1 h vehicle run starting at rest at 34°N 120°E 200 m
/// (the paper later also says 110°E; 120°E is used), heading east:
/// accelerate at 2 m/s² for 10 s to 20 m/s; east for 500 s, left turn and
/// north for 700 s, right 45° to north-east for 700 s, right 90° to
/// south-east for 1000 s, left 45° to east for 700 s. Before each turn
/// decelerate at −2 m/s² for 8 s, turn with a 10 m radius, re-accelerate to
/// 20 m/s. Odometer faults: wheel spin at 600 s for 3 s (reads ≫ true),
/// skid at 1600 s (reads ≪ true), 2000–2100 s slippery uphill road rolling
/// with slipping (reads 1–1.3 × true). Initial misalignment 1′, 1′, 10′
/// (E, N, U); position exactly known. Gyros: constant 0.01°/h, random
/// 0.005°/h; accelerometers: constant 100 µg, random 50 µg; odometer scale
/// error: constant 0.5 %, random 0.05 %; all random terms first-order
/// Markov with τ = 3600 s. Filters: no fault processing, the max-threshold
/// method, the fuzzy adaptive filter. No GNSS.
///
/// **Chosen (the paper is silent):**
/// - Each turn starts exactly at a leg boundary (500, 1200, 1900, 2900 s),
///   the 8 s deceleration ending there (the turn itself takes 3–5 s at
///   4 m/s, 0.4 rad/s); the vehicle does not bank.
/// - The uphill road: a 2° grade during 2000–2100 s (about 65 m of climb).
/// - Fault sizes: wheel spin reads 1.5 × true speed, the skid 0.25 × true,
///   both for 3 s; rolling with slipping draws a factor uniformly in
///   [1, 1.3] per reading.
/// - IMU at 200 Hz, errors on all three axes (the paper lists two
///   accelerometers), constant terms +1σ; white noise gyro 0.001°/√h,
///   accelerometer 10 µg/√Hz (not given; small against the drifts).
/// - Odometer at 10 Hz, white noise 0.05 m/s, no lever arm; the IMU is
///   mounted on the vehicle with pitch 0.2° and yaw −0.3° (the vehicle
///   frame in body axes; calibrated: the filter knows them), so the
///   odometer measures along the vehicle's forward axis, not the IMU's.
/// - Initial errors: φ (N, E, D) = (1′, 1′, −10′), no velocity or
///   position error; P0: those attitude σ, velocity 0.01 m/s, position
///   0.01 m, gyro bias 0.01°/h, accelerometer bias 100 µg, odometer scale
///   0.5 %. The filter models gyro and accelerometer biases as Markov
///   processes (σ 0.01°/h and 100 µg, τ = 3600 s).
/// - R of the velocity matching: 0.1 m/s per NED axis; max-threshold
///   1 m/s (both chosen: the paper gives neither); fuzzy R window 20
///   innovations.
///
/// **Tuning seeds:** 3 (the fuzzy rules' plateau) and 100–103 (the sweep
/// of the tuned max-threshold baseline, [`tuned`](super::tuned));
/// [`TUNING_SEEDS`](super::TUNING_SEEDS). The chosen 1 m/s baseline is
/// kept here; a tuned threshold and the baseline with the fuzzy filter's
/// windowed R are in [`tuned`](super::tuned) and [`variants`](super::variants).
///
/// ```
/// let s = kestrel_app::scenario::scenario_003();
/// let t = s.trajectory().unwrap();
/// assert!((t.velocity_at(600.0).x - 20.0).abs() < 1e-9); // north at 20 m/s
/// ```
pub fn scenario_003() -> Scenario {
    let decel = Segment::Accelerate {
        accel: -2.0,
        duration: 8.0,
    };
    let accel = Segment::Accelerate {
        accel: 2.0,
        duration: 8.0,
    };
    let turn = |angle| Segment::turn_radius_deg(10.0, angle);
    let mounting = [0.2f64.to_radians(), -0.3f64.to_radians()];
    let trajectory = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        90f64.to_radians(),
        0.0,
    )
    .then(Segment::Accelerate {
        accel: 2.0,
        duration: 10.0,
    })
    .then(Segment::CruiseUntil { time: 492.0 })
    .then(decel.clone())
    .then(turn(-90.0))
    .then(accel.clone())
    .then(Segment::CruiseUntil { time: 1192.0 })
    .then(decel.clone())
    .then(turn(45.0))
    .then(accel.clone())
    .then(Segment::CruiseUntil { time: 1892.0 })
    .then(decel.clone())
    .then(turn(90.0))
    .then(accel.clone())
    .then(Segment::CruiseUntil { time: 2000.0 })
    .then(Segment::climb_pitch_deg(2.0, 100.0))
    .then(Segment::CruiseUntil { time: 2892.0 })
    .then(decel)
    .then(turn(-45.0))
    .then(accel)
    .then(Segment::CruiseUntil { time: 3600.0 })
    .with_mounting(Euler::new(0.0, mounting[0], mounting[1]));

    let truth = ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(0.01)
        .with_gyro_markov_deg_per_h(0.005, 3600.0)
        .with_gyro_arw_deg_per_sqrt_h(0.001)
        .with_accel_bias_ug(100.0)
        .with_accel_markov_ug(50.0, 3600.0)
        .with_accel_vrw_ug_per_sqrt_hz(10.0);
    let filter_imu = ImuSpec::perfect()
        .with_gyro_markov_deg_per_h(0.01, 3600.0)
        .with_gyro_arw_deg_per_sqrt_h(0.001)
        .with_accel_markov_ug(100.0, 3600.0)
        .with_accel_vrw_ug_per_sqrt_hz(10.0);

    let mut odometer = OdometerConfig::new(10.0);
    odometer.scale_error = 0.005;
    odometer.scale_markov_sigma = 0.0005;
    odometer.scale_markov_tau = 3600.0;
    odometer.noise_std = 0.05;
    odometer.faults = vec![
        OdometerFault::wheel_spin(TimeWindow::starting(600.0, 3.0), 1.5),
        OdometerFault::skid(TimeWindow::starting(1600.0, 3.0), 0.25),
        OdometerFault::roll_slip(TimeWindow::new(2000.0, 2100.0), 1.0, 1.3),
    ];

    let att = v3(ARCMIN.si(1.0), ARCMIN.si(1.0), ARCMIN.si(10.0));
    Scenario {
        name: "003".into(),
        description: "1 h vehicle SINS/odometer run with wheel spin, skid and slip faults (fuzzy adaptive KF)".into(),
        earth: Ellipsoid::wgs84(),
        trajectory,
        imu_rate: 200.0,
        imu_errors: ImuErrors::from_spec(&truth),
        gnss: None,
        odometer: Some(odometer),
        attitude: None,
        initial_errors: InitialErrors {
            attitude: v3(att.x, att.y, -att.z),
            velocity: Vector3::zeros(),
            position: Vector3::zeros(),
        },
        filter: FilterSetup {
            error_model: ErrorModelKind::Odometer16 { scale_tau: 3600.0 },
            measurement: MeasurementKind::OdometerVelocity,
            imu_model: filter_imu,
            p0: InitialUncertainty {
                attitude: att,
                velocity: Vector3::repeat(0.01),
                position: Vector3::repeat(0.01),
                gyro_bias: Vector3::repeat(DEG_PER_H.si(0.01)),
                gyro_markov: Vector3::zeros(),
                accel_bias: Vector3::repeat(UG.si(100.0)),
                odometer_scale: 0.005,
                gyro_scale: Vector3::zeros(),
                accel_scale: Vector3::zeros(),
            },
            r: MeasurementNoise {
                position: None,
                velocity: None,
                attitude: None,
                odometer: Some(Vector3::repeat(0.1)),
            },
            lever_arm: Vector3::zeros(),
            odometer_mounting: mounting,
        },
        filters: vec![
            FilterKind::Standard,
            FilterKind::MaxThreshold {
                threshold: 1.0,
                r_window: None,
            },
            FilterKind::FuzzyAdaptive { window: 20 },
        ],
        seed: 3,
    }
}
