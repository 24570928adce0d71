//! Paper 000: improved adaptive KF (Sage–Husa + fading memory + outlier
//! compression) for GPS/SINS on a 500 s aircraft flight.

use kestrel::nalgebra::Vector3;

use super::{
    v3, ErrorModelKind, FadeBlock, FilterKind, FilterSetup, InitialErrors, InitialUncertainty,
    MeasurementKind, MeasurementNoise, Scenario,
};
use crate::config::units::{DEG_PER_H, UG};
use kestrel::nav::earth::Ellipsoid;
use kestrel::nav::geodetic::Geodetic;
use kestrel::nav::imu_spec::ImuSpec;
use kestrel::sim::{
    GnssConfig, ImuErrors, NoiseWindow, Outlier, OutlierKind, ReportedStd, Segment, TimeWindow,
    TrajectorySpec, Vehicle,
};

/// Paper 000's experiment.
///
/// **As stated:** 500 s flight: runway take-off acceleration, climb,
/// accelerate level, climb, accelerate level, constant level, turn; start
/// 118.6°E 40.1°N 100 m; Krasovsky Earth (Re = 6 378 245 m). Gyro constant
/// drift 0.01°/h, random drift 0.005°/h; accelerometer constant bias 50 µg,
/// random 50 µg. GPS position noise 5 m, velocity 0.3 m/s; velocity noise
/// 1.5 m/s during 50–100 s and 3 m/s during 200–300 s; patchy outliers of
/// peak 15 m/s on east and north velocity during 350–360 s. 18-state
/// filter, measurement INS − GPS position and velocity. R(0) = 5 m,
/// 0.3 m/s; P0 attitude 1°, velocity 0.3 m/s, position 5 m, gyro constant
/// 0.1°/h, gyro Markov 0.02°/h, accelerometer 100 µg; X(0) = 0. Filters:
/// standard KF, Sage–Husa + fading, improved adaptive.
///
/// **Chosen (the paper is silent):**
/// - Manoeuvres (its figure is missing), with 5 s raised-cosine edges on
///   accelerations and turn rates (roll rates stay below 10°/s): heading north; from rest
///   accelerate 3 m/s² for 25 s (75 m/s, take-off), climb at 10° for 60 s,
///   accelerate 1 m/s² for 30 s level (105 m/s), climb at 8° for 60 s,
///   accelerate 1.5 m/s² for 30 s (150 m/s), level until 400 s, turn right
///   120° at 2°/s (65 s), level to 500 s (about 1.5 km of climb).
/// - IMU at 200 Hz. "Random drift 0.005°/h" is the gyro first-order Markov
///   drift of the 18-state model, τ = 3600 s (as in paper 003); "random
///   50 µg" is accelerometer white noise of 50 µg/√Hz; the gyro white noise
///   is 0.01°/h/√Hz, the value the paper's Q carries. Constant errors are
///   +1σ on every axis; no scale-factor errors.
/// - GPS at 10 Hz, no lever arm; the noise changes apply to all three
///   velocity axes (position noise stays 5 m); the receiver reports its
///   nominal σ. The outlier patch adds to north and east velocity at each
///   fix of 350–360 s a common offset of 10 m/s plus a uniform error in
///   ±5 m/s (peak 15 m/s). Why: the paper's standard KF ends far above its
///   GPS noise (8.6, 9.4 m; 0.57, 0.95 m/s), so its faults must bias the
///   fixes for a while. With a zero-mean ±15 m/s patch at 1 Hz our KF has
///   3.1, 3.0 m and 0.14, 0.15 m/s (seed 0), about 3× better than the
///   paper's and only 2× worse than the improved filter. The biased patch
///   makes the KF integrate a wrong velocity for 10 s (about 5.5 m per
///   horizontal axis on seeds 0–2, the paper has 8.6 and 9.4 m); the
///   10 Hz rate gives the compression 100 instead of 10 outlying fixes to
///   refuse and the adaptive filters more fixes to average. The noise
///   windows barely move a KF whose assumed IMU is this good, so the KF's
///   velocity error stays 4–6× below the paper's. Position noise windows
///   were tried too: they hurt every filter alike.
/// - The filter assumes the true IMU model (Q of the paper: gyro white and
///   Markov, accelerometer white).
/// - Initial errors (the paper gives only P0): half the P0 σ with
///   alternating signs: attitude (0.5°, −0.5°, 0.5°), velocity
///   (0.15, −0.15, 0.15) m/s, position (2.5, −2.5, 2.5) m.
/// - Adaptive parameters: forgetting factor b = 0.97 (middle of the
///   paper's 0.95–0.99), compression significance α = 0.05 (paper: 0.05
///   or 0.02), reserve coefficient γ = 4, fades clamped to λ ≤ 1.5 and
///   applied to the velocity and position errors only (states 3–8, the
///   states the fixes read; `FadeBlock::VelocityPosition`).
///   γ = 4: `C` is dominated by the three position variances, so for a
///   consistent filter `νᵀν / (tr C / 3)` is close to χ²(3) and the test
///   fails by chance in `P(χ²(3) > 12)` = 0.7 % of the epochs (γ = 3:
///   2.9 %, i.e. three false fades a second at 10 Hz).
///   Why the block and the clamp: a whole-covariance fade multiplies what
///   the fixes do not observe (the difference of the constant and Markov
///   gyro drifts exactly, heading and accelerometer bias nearly), whose
///   variance therefore grows by the product of the fades; with the
///   paper's γ = 1 and λ ≤ 100 the heading σ exceeds 1 rad within 13 s and
///   both adaptive filters diverge. The block fade removes that runaway,
///   but a large λ on velocity still makes the filters follow the noisy
///   fixes of the noise windows (γ = 1, λ ≤ 100: velocity RMS 2–3 m/s,
///   seeds 0–3), so the clamp λ ≤ 1.5 stays. Chosen on seeds 0–7, not
///   per seed.
///
/// **Tuning seeds:** 0–7 (the patch, the GNSS rate, γ, the clamp and the
/// fade block; [`TUNING_SEEDS`](super::TUNING_SEEDS)). The size of the
/// result is set by the patch: on held-out seeds the improved filter's
/// horizontal RMS is 13× below the KF's with this patch at 10 Hz, 4.4×
/// with it at 1 Hz and 1.9–2.4× without its bias ([`variants`](super::variants)).
///
/// ```
/// let s = kestrel_app::scenario::scenario_000();
/// assert_eq!(s.earth.a, 6_378_245.0);
/// assert_eq!(s.filters.len(), 3);
/// ```
pub fn scenario_000() -> Scenario {
    let trajectory = TrajectorySpec::new(
        Vehicle::Aircraft,
        Geodetic::from_degrees(40.1, 118.6, 100.0),
        0.0,
        0.0,
    )
    .with_edge(5.0)
    .then(Segment::Accelerate {
        accel: 3.0,
        duration: 25.0,
    })
    .then(Segment::climb_pitch_deg(10.0, 60.0))
    .then(Segment::Accelerate {
        accel: 1.0,
        duration: 30.0,
    })
    .then(Segment::climb_pitch_deg(8.0, 60.0))
    .then(Segment::Accelerate {
        accel: 1.5,
        duration: 30.0,
    })
    .then(Segment::CruiseUntil { time: 400.0 })
    .then(Segment::turn_rate_deg(2.0, 120.0))
    .then(Segment::CruiseUntil { time: 500.0 });

    let imu = ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(0.01)
        .with_gyro_markov_deg_per_h(0.005, 3600.0)
        .with_gyro_arw_deg_per_sqrt_h(0.01 / 60.0)
        .with_accel_bias_ug(50.0)
        .with_accel_vrw_ug_per_sqrt_hz(50.0);

    let mut gnss = GnssConfig::new(10.0, Vector3::repeat(5.0), Some(Vector3::repeat(0.3)));
    gnss.noise_windows = vec![
        NoiseWindow::velocity(TimeWindow::new(50.0, 100.0), Vector3::repeat(1.5)),
        NoiseWindow::velocity(TimeWindow::new(200.0, 300.0), Vector3::repeat(3.0)),
    ];
    gnss.outliers = vec![Outlier {
        window: TimeWindow::new(350.0, 360.0),
        kind: OutlierKind::Patch {
            position_offset: Vector3::zeros(),
            position_amplitude: Vector3::zeros(),
            velocity_offset: v3(10.0, 10.0, 0.0),
            velocity_amplitude: v3(5.0, 5.0, 0.0),
        },
    }];
    gnss.reported_std = ReportedStd::Nominal;

    let (att, vel, pos) = (0.5f64.to_radians(), 0.15, 2.5);
    Scenario {
        name: "000".into(),
        description: "500 s aircraft GPS/SINS, velocity noise changes and outliers (Sage-Husa + fading + compression)".into(),
        earth: Ellipsoid::krasovsky(),
        trajectory,
        imu_rate: 200.0,
        imu_errors: ImuErrors::from_spec(&imu),
        gnss: Some(gnss),
        odometer: None,
        attitude: None,
        initial_errors: InitialErrors {
            attitude: v3(att, -att, att),
            velocity: v3(vel, -vel, vel),
            position: v3(pos, -pos, pos),
        },
        filter: FilterSetup {
            error_model: ErrorModelKind::Ins18,
            measurement: MeasurementKind::GnssPositionVelocity,
            imu_model: imu,
            p0: InitialUncertainty {
                attitude: Vector3::repeat(1f64.to_radians()),
                velocity: Vector3::repeat(0.3),
                position: Vector3::repeat(5.0),
                gyro_bias: Vector3::repeat(DEG_PER_H.si(0.1)),
                gyro_markov: Vector3::repeat(DEG_PER_H.si(0.02)),
                accel_bias: Vector3::repeat(UG.si(100.0)),
                odometer_scale: 0.0,
                gyro_scale: Vector3::zeros(),
                accel_scale: Vector3::zeros(),
            },
            r: MeasurementNoise::gnss(Vector3::repeat(5.0), Vector3::repeat(0.3)),
            lever_arm: Vector3::zeros(),
            odometer_mounting: [0.0; 2],
        },
        filters: vec![
            FilterKind::Standard,
            FilterKind::SageHusaFading {
                forgetting: 0.97,
                reserve: 4.0,
                lambda_max: 1.5,
                fade_states: FadeBlock::VelocityPosition,
            },
            FilterKind::ImprovedAdaptive {
                forgetting: 0.97,
                reserve: 4.0,
                lambda_max: 1.5,
                significance: 0.05,
                fade_states: FadeBlock::VelocityPosition,
            },
        ],
        seed: 0,
    }
}
