//! Paper 002: innovation-χ²-test extended robust KF for INS/GNSS in an
//! urban drive with heavy multipath.

use kestrel::nalgebra::Vector3;

use super::{
    v3, ErrorModelKind, FilterKind, FilterSetup, InitialErrors, InitialUncertainty,
    MeasurementKind, MeasurementNoise, Scenario,
};
use crate::config::units::{DEG_PER_H, MG};
use kestrel::nav::earth::Ellipsoid;
use kestrel::nav::geodetic::Geodetic;
use kestrel::nav::imu_spec::ImuSpec;
use kestrel::sim::{
    GnssConfig, ImuErrors, MultipathBursts, Outlier, OutlierKind, ReportedStd, Segment, TimeWindow,
    TrajectorySpec, Vehicle,
};

/// City blocks: cruise speed (m/s), cruise time (s), wait at a red light
/// before the turn (s, 0 = none), turn (°, + right), with an overpass.
const BLOCKS: [(f64, f64, f64, f64, bool); 15] = [
    (12.0, 150.0, 0.0, 90.0, false),
    (14.0, 200.0, 30.0, 90.0, false),
    (10.0, 120.0, 0.0, -90.0, false),
    (15.0, 180.0, 45.0, -90.0, false),
    (12.0, 160.0, 0.0, 90.0, true),
    (8.0, 100.0, 25.0, 90.0, false),
    (13.0, 210.0, 0.0, -90.0, false),
    (12.0, 140.0, 40.0, -90.0, false),
    (14.0, 190.0, 0.0, 90.0, false),
    (10.0, 130.0, 30.0, 90.0, false),
    (15.0, 170.0, 0.0, -90.0, true),
    (12.0, 150.0, 35.0, -90.0, false),
    (11.0, 160.0, 0.0, 90.0, false),
    (13.0, 140.0, 20.0, 90.0, false),
    (12.0, 120.0, 0.0, -90.0, false),
];

/// Multipath episodes: start (s), length (s), position offset N, E, D (m),
/// uniform jitter half-width (m).
const MULTIPATH: [(f64, f64, [f64; 3], f64); 12] = [
    (300.0, 40.0, [6.0, -4.0, 12.0], 2.0),
    (610.0, 25.0, [-9.0, 7.0, 18.0], 3.0),
    (880.0, 60.0, [4.0, 11.0, -15.0], 3.0),
    (1240.0, 30.0, [-14.0, -6.0, 22.0], 4.0),
    (1500.0, 45.0, [8.0, 3.0, 10.0], 2.0),
    (1680.0, 20.0, [-18.0, 12.0, 25.0], 5.0),
    (2050.0, 50.0, [5.0, -9.0, 14.0], 2.0),
    (2450.0, 35.0, [12.0, 15.0, -20.0], 4.0),
    (2700.0, 40.0, [-6.0, 8.0, 12.0], 2.0),
    (2950.0, 25.0, [20.0, -10.0, 28.0], 5.0),
    (3250.0, 55.0, [-7.0, -5.0, 16.0], 3.0),
    (3420.0, 30.0, [9.0, 13.0, -18.0], 3.0),
];

/// The random urban error processes, active from 60 s to the end (drawn
/// from the seed, so every Monte Carlo run sees other bursts): short
/// multipath bursts, NLOS biases and slow biases (see `scenario_002`).
fn urban_bursts() -> [MultipathBursts; 3] {
    [
        // Multipath bursts: abrupt, a few seconds, metres to tens of
        // metres, with a Doppler (velocity) bias.
        MultipathBursts {
            onset_probability: 0.02,
            duration: (2.0, 8.0),
            rise: 0.0,
            position: v3(15.0, 15.0, 25.0),
            position_jitter: v3(2.0, 2.0, 3.0),
            velocity_bias: v3(0.6, 0.6, 0.4),
            velocity: v3(0.2, 0.2, 0.2),
        },
        // NLOS biases: tens of seconds, building up over 15 s, mostly
        // vertical (up to 40 m).
        MultipathBursts {
            onset_probability: 0.02,
            duration: (20.0, 80.0),
            rise: 15.0,
            position: v3(6.0, 6.0, 40.0),
            position_jitter: v3(1.0, 1.0, 2.0),
            velocity_bias: v3(0.02, 0.02, 0.03),
            velocity: v3(0.02, 0.02, 0.03),
        },
        // Slow biases: minutes, building up over 60 s, too slow for any
        // innovation test.
        MultipathBursts {
            onset_probability: 0.01,
            duration: (120.0, 300.0),
            rise: 60.0,
            position: v3(3.0, 3.0, 20.0),
            position_jitter: Vector3::zeros(),
            velocity_bias: Vector3::zeros(),
            velocity: Vector3::zeros(),
        },
    ]
}

/// Signal blockages: start (s), length (s).
const OUTAGES: [(f64, f64); 5] = [
    (420.0, 25.0),
    (1105.0, 55.0),
    (1790.0, 10.0),
    (2330.0, 60.0),
    (3020.0, 25.0),
];

/// Paper 002's experiment, simulated (the paper processes real data).
///
/// **As stated:** urban vehicle drive of about 1 h; NovAtel SPAN-FSAS IMU:
/// gyro bias < 0.75°/h, ARW 0.1°/√h, accelerometer bias 1 mg, VRW
/// 0.05 mg/√Hz, 200 Hz; GNSS 1 Hz with heavy multipath (some delays
/// above 20 m) and frequent loss of lock. Initial errors: position 10 m,
/// velocity 0.1 m/s, attitude 0.03°. R: position 3, 3, 5 m, velocity 0.03,
/// 0.03, 0.05 m/s (E, N, U). 15-state EKF versus ICT-EREKF, α = 0.05.
///
/// **Chosen (a simulation of what the data contained):**
/// - Place and route: start 30.5°N 114.4°E 20 m heading north; 60 s at rest,
///   then 15 city blocks (cruise 8–15 m/s, 1.5 m/s² speed changes, 90°
///   turns of 12 m radius at 5 m/s, 7 red lights of 20–45 s, two overpasses
///   of ±3° grade), straight driving until 3540 s, stop, rest to 3600 s.
/// - True IMU errors, explicit per axis inside the datasheet bounds: gyro
///   bias (0.5, −0.6, 0.7)°/h, accelerometer bias (0.8, −1.0, 0.6) mg; ARW
///   and VRW as stated; no scale-factor errors.
/// - GNSS: nominal white noise equal to the paper's R (N, E, D: 3, 3, 5 m;
///   0.03, 0.03, 0.05 m/s), so the χ² tests see only the outliers;
///   antenna lever arm (0.25, 0.10, −1.05) m, known to the filter; nominal
///   σ reported; five outages of 10–60 s. The paper's multipath is only
///   "heavy, some above 20 m"; its EKF row (E, N, U: 2.2, 2.6, 8.0 m;
///   0.11, 0.09, 0.08 m/s) says how heavy: far above R, vertical three
///   times each horizontal axis, and in velocity too. The simulated errors are calibrated
///   so the EKF's RMS lands near that row, out of five processes:
///   - twelve fixed multipath episodes of 20–60 s with constant offsets of
///     13–36 m (six above 20 m), ±2–5 m jitter, ±(0.3, 0.3, 0.5) m/s
///     velocity errors;
///   - isolated spikes with probability 2 % per fix (10–40 m,
///     0.3–1.5 m/s);
///   - random multipath bursts ([`MultipathBursts`]): onset 2 % per fix,
///     2–8 s, step biases up to ±(15, 15, 25) m (N, E, D) with ±(2, 2, 3) m
///     jitter and a Doppler bias up to ±(0.6, 0.6, 0.4) m/s with
///     ±0.2 m/s jitter — the abrupt errors an innovation test catches and
///     the EKF follows (its velocity RMS comes from these; white velocity
///     errors alone average out, and larger biases made the robust filter
///     lock onto a burst met at the end of an outage, which the paper's
///     results do not show);
///   - random NLOS biases: onset 2 % per fix, 20–80 s, building up over
///     15 s to ±(6, 6, 40) m, ±(1, 1, 2) m jitter, ±0.02–0.03 m/s velocity
///     errors (urban canyons: vertical much larger than horizontal);
///   - random slow biases: onset 1 % per fix, 2–5 min, building up over
///     60 s to ±(3, 3, 20) m: too slow for any innovation test, followed
///     by both filters alike — they keep the robust filter's vertical RMS
///     near the paper's 6 m and its gain near the paper's 25 %.
/// - Initial errors per axis with alternating signs: position
///   (10, −10, 10) m, velocity (0.1, −0.1, 0.1) m/s, attitude
///   (0.03°, −0.03°, 0.03°); P0 with these σ and gyro bias 0.75°/h,
///   accelerometer bias 1 mg.
/// - The filter models the biases as first-order Markov processes with
///   those σ and τ = 3600 s.
/// - Neither filter was tuned: both keep the paper's R, P0 and α.
///
/// **Tuning seeds:** 0–7 (the multipath calibration against the paper's
/// EKF row and the burst cap; [`TUNING_SEEDS`](super::TUNING_SEEDS)). With
/// the bursts doubled the robust filter's lead grows (held-out seeds:
/// horizontal 2.1× against 1.4×; [`variants`](super::variants)).
///
/// **Result** (mean of seeds 0–7, full length; position E, N, U, velocity
/// and attitude N, E, D): EKF 2.78, 2.73, 8.20 m; 0.089, 0.088, 0.061 m/s;
/// 0.034°, 0.038°, 0.30°. ICT-EREKF 2.11, 1.88, 5.50 m; 0.036, 0.036,
/// 0.031 m/s; 0.014°, 0.015°, 0.10°. The robust filter's 3-D RMS is 31 %
/// lower in position (per seed 20–44 %) and 57 % in velocity (45–66 %);
/// the paper: 25 % and 50 %. The EKF's heading error (0.30°) is 2.4 times
/// the paper's 0.125°: the simulated Doppler biases turn the heading more
/// than the real drive's errors did.
///
/// ```
/// let s = kestrel_app::scenario::scenario_002();
/// assert_eq!(s.trajectory().unwrap().duration(), 3600.0);
/// assert_eq!(s.imu_rate, 200.0);
/// ```
pub fn scenario_002() -> Scenario {
    let mut trajectory = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(30.5, 114.4, 20.0),
        0.0,
        0.0,
    )
    .then(Segment::Stationary { duration: 60.0 });
    let speed_change = |speed| Segment::AccelerateTo { speed, accel: 1.5 };
    for &(speed, cruise, wait, turn, overpass) in &BLOCKS {
        trajectory = trajectory.then(speed_change(speed));
        if overpass {
            let half = 0.5 * cruise - 20.0;
            trajectory = trajectory
                .then(Segment::Cruise { duration: half })
                .then(Segment::climb_pitch_deg(3.0, 20.0))
                .then(Segment::climb_pitch_deg(-3.0, 20.0))
                .then(Segment::Cruise { duration: half });
        } else {
            trajectory = trajectory.then(Segment::Cruise { duration: cruise });
        }
        if wait > 0.0 {
            trajectory = trajectory
                .then(Segment::Stop { decel: 1.5 })
                .then(Segment::Stationary { duration: wait });
        }
        trajectory = trajectory
            .then(speed_change(5.0))
            .then(Segment::turn_radius_deg(12.0, turn));
    }
    trajectory = trajectory
        .then(speed_change(12.0))
        .then(Segment::CruiseUntil { time: 3540.0 })
        .then(Segment::Stop { decel: 1.5 })
        .then(Segment::CruiseUntil { time: 3600.0 });

    let datasheet = ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(0.75)
        .with_gyro_arw_deg_per_sqrt_h(0.1)
        .with_accel_bias_mg(1.0)
        .with_accel_vrw_ug_per_sqrt_hz(50.0);
    let mut errors = ImuErrors::from_spec(&datasheet);
    errors.gyro_bias = v3(0.5, -0.6, 0.7).map(|x| DEG_PER_H.si(x));
    errors.accel_bias = v3(0.8, -1.0, 0.6).map(|x| MG.si(x));
    let mut filter_imu = datasheet;
    filter_imu.gyro_markov_sigma = datasheet.gyro_bias;
    filter_imu.gyro_markov_tau = 3600.0;
    filter_imu.accel_markov_sigma = datasheet.accel_bias;
    filter_imu.accel_markov_tau = 3600.0;

    let pos_std = v3(3.0, 3.0, 5.0);
    let vel_std = v3(0.03, 0.03, 0.05);
    let lever_arm = v3(0.25, 0.10, -1.05);
    let mut gnss = GnssConfig::new(1.0, pos_std, Some(vel_std));
    gnss.lever_arm = lever_arm;
    gnss.reported_std = ReportedStd::Nominal;
    gnss.outliers = MULTIPATH
        .iter()
        .map(|&(start, len, offset, jitter)| Outlier {
            window: TimeWindow::starting(start, len),
            kind: OutlierKind::Patch {
                position_offset: Vector3::from(offset),
                position_amplitude: Vector3::repeat(jitter),
                velocity_offset: Vector3::zeros(),
                velocity_amplitude: v3(0.3, 0.3, 0.5),
            },
        })
        .collect();
    gnss.outliers.extend(urban_bursts().map(|b| Outlier {
        window: TimeWindow::new(60.0, 3600.0),
        kind: OutlierKind::Multipath(b),
    }));
    gnss.outliers.push(Outlier {
        window: TimeWindow::new(60.0, 3600.0),
        kind: OutlierKind::Spikes {
            probability: 0.02,
            position: (10.0, 40.0),
            velocity: (0.3, 1.5),
        },
    });
    gnss.outages = OUTAGES
        .iter()
        .map(|&(start, len)| TimeWindow::starting(start, len))
        .collect();

    let att = 0.03f64.to_radians();
    Scenario {
        name: "002".into(),
        description: "1 h urban drive, SPAN-FSAS IMU, GNSS with heavy multipath and outages (EKF vs ICT-EREKF)".into(),
        earth: Ellipsoid::wgs84(),
        trajectory,
        imu_rate: 200.0,
        imu_errors: errors,
        gnss: Some(gnss),
        odometer: None,
        attitude: None,
        initial_errors: InitialErrors {
            attitude: v3(att, -att, att),
            velocity: v3(0.1, -0.1, 0.1),
            position: v3(10.0, -10.0, 10.0),
        },
        filter: FilterSetup {
            error_model: ErrorModelKind::Ins15,
            measurement: MeasurementKind::GnssPositionVelocity,
            imu_model: filter_imu,
            p0: InitialUncertainty {
                attitude: Vector3::repeat(att),
                velocity: Vector3::repeat(0.1),
                position: Vector3::repeat(10.0),
                gyro_bias: Vector3::repeat(datasheet.gyro_bias),
                gyro_markov: Vector3::zeros(),
                accel_bias: Vector3::repeat(datasheet.accel_bias),
                odometer_scale: 0.0,
                gyro_scale: Vector3::zeros(),
                accel_scale: Vector3::zeros(),
            },
            r: MeasurementNoise::gnss(pos_std, vel_std),
            lever_arm,
            odometer_mounting: [0.0; 2],
        },
        filters: vec![
            FilterKind::Standard,
            FilterKind::IctErekf { significance: 0.05 },
        ],
        seed: 2,
    }
}
