//! Paper 001: federated square-root UKF for GPS/INS, aircraft at 10 km.

use kestrel::nalgebra::Vector3;

use super::{
    v3, ErrorModelKind, FilterKind, FilterSetup, InitialErrors, InitialUncertainty,
    MeasurementKind, MeasurementNoise, Scenario,
};
use crate::config::units::{DEG_PER_H, MG};
use kestrel::nav::earth::Ellipsoid;
use kestrel::nav::geodetic::Geodetic;
use kestrel::nav::imu_spec::ImuSpec;
use kestrel::sim::{GnssConfig, ImuErrors, ReportedStd, Segment, TrajectorySpec, Vehicle};

/// Paper 001's experiment.
///
/// **As stated:** aircraft at 10 000 m and 300 m/s, start 30°N 120°E;
/// initial position error 10 m, velocity error 0.5 m/s. INS: accelerometer
/// bias 10 mg, scale factor 0.3 %, white noise 1 mg; gyro drift 50°/h,
/// scale factor 0.05 %, white noise 10°/h. GPS: horizontal position 10 m,
/// vertical 20 m; horizontal velocity 0.1 m/s, vertical 0.2 m/s. Filters:
/// federated UKF versus federated SR-UKF (local GPS KF + local UKF on the
/// nonlinear INS model, EDOP information sharing).
///
/// **Chosen (the paper is silent):**
/// - Duration 600 s and manoeuvres (its figure is missing), all level at
///   10 km: heading east; level until 100 s, turn left 90° at 1.5°/s
///   (65 s including 5 s raised-cosine roll-in and roll-out, bank 38.7°),
///   level until 300 s, turn right 180° at 1.5°/s (125 s), level to 600 s.
/// - IMU at 100 Hz (a low-grade unit); the white noises are densities
///   (1 mg/√Hz, 10°/h/√Hz), so they do not depend on the rate; constant
///   errors and scale factors are +1σ on every axis.
/// - GPS at 1 Hz, no lever arm, reports its σ.
/// - Initial errors: position (10, −10, 10) m, velocity (0.5, −0.5, 0.5) m/s;
///   attitude (0.1°, −0.1°, 0.3°) with P0 σ (0.2°, 0.2°, 0.5°).
///   P0 position 10 m, velocity 0.5 m/s, gyro bias 50°/h, accelerometer
///   bias 10 mg; R equals the GPS noise.
/// - Error model: the 15-state model (the common states of the local
///   filters are position and velocity errors).
/// - Sigma points: α = 10⁻³, β = 2, κ = 0 (van der Merwe's defaults; the
///   tiny α makes W₀ strongly negative, which is where square-root forms
///   matter numerically).
///
/// ```
/// let s = kestrel_app::scenario::scenario_001();
/// let t = s.trajectory().unwrap();
/// assert_eq!(t.duration(), 600.0);
/// assert_eq!(t.initial_state().vel.norm(), 300.0);
/// ```
pub fn scenario_001() -> Scenario {
    let trajectory = TrajectorySpec::new(
        Vehicle::Aircraft,
        Geodetic::from_degrees(30.0, 120.0, 10_000.0),
        90f64.to_radians(),
        300.0,
    )
    .with_edge(5.0)
    .then(Segment::CruiseUntil { time: 100.0 })
    .then(Segment::turn_rate_deg(1.5, -90.0))
    .then(Segment::CruiseUntil { time: 300.0 })
    .then(Segment::turn_rate_deg(1.5, 180.0))
    .then(Segment::CruiseUntil { time: 600.0 });

    let imu = ImuSpec::perfect()
        .with_accel_bias_mg(10.0)
        .with_accel_scale_ppm(3000.0)
        .with_accel_vrw_ug_per_sqrt_hz(1000.0)
        .with_gyro_bias_deg_per_h(50.0)
        .with_gyro_scale_ppm(500.0)
        .with_gyro_arw_deg_per_sqrt_h(10.0 / 60.0);

    let pos_std = v3(10.0, 10.0, 20.0);
    let vel_std = v3(0.1, 0.1, 0.2);
    let mut gnss = GnssConfig::new(1.0, pos_std, Some(vel_std));
    gnss.reported_std = ReportedStd::Actual;

    let att = 0.1f64.to_radians();
    Scenario {
        name: "001".into(),
        description:
            "600 s aircraft at 10 km and 300 m/s, low-grade INS + GPS (federated UKF vs SR-UKF)"
                .into(),
        earth: Ellipsoid::wgs84(),
        trajectory,
        imu_rate: 100.0,
        imu_errors: ImuErrors::from_spec(&imu),
        gnss: Some(gnss),
        odometer: None,
        attitude: None,
        initial_errors: InitialErrors {
            attitude: v3(att, -att, 3.0 * att),
            velocity: v3(0.5, -0.5, 0.5),
            position: v3(10.0, -10.0, 10.0),
        },
        filter: FilterSetup {
            error_model: ErrorModelKind::Ins15,
            measurement: MeasurementKind::GnssPositionVelocity,
            imu_model: imu,
            p0: InitialUncertainty {
                attitude: v3(0.2, 0.2, 0.5).map(f64::to_radians),
                velocity: Vector3::repeat(0.5),
                position: Vector3::repeat(10.0),
                gyro_bias: Vector3::repeat(DEG_PER_H.si(50.0)),
                gyro_markov: Vector3::zeros(),
                accel_bias: Vector3::repeat(MG.si(10.0)),
                odometer_scale: 0.0,
                gyro_scale: Vector3::zeros(),
                accel_scale: Vector3::zeros(),
            },
            r: MeasurementNoise::gnss(pos_std, vel_std),
            lever_arm: Vector3::zeros(),
            odometer_mounting: [0.0; 2],
        },
        filters: vec![
            FilterKind::FederatedUkf {
                alpha: 1e-3,
                beta: 2.0,
                kappa: 0.0,
            },
            FilterKind::FederatedSrUkf {
                alpha: 1e-3,
                beta: 2.0,
                kappa: 0.0,
            },
        ],
        seed: 1,
    }
}
