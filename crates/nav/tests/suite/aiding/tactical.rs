//! The tactical-grade INS/GNSS set-up shared by the aiding tests and the
//! aiding benchmarks: IMU specification, antenna lever arm, GNSS receiver,
//! the seeded IMU and the filter's initial navigation uncertainty.
#![allow(dead_code)] // each user takes the parts it needs

use kestrel_nav::engine::InitialUncertainty;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::ImuSpec;
use kestrel_sim::{sensor_rng, GnssConfig, ImuErrors, ImuSensor, SensorStream};

/// A tactical-grade IMU: 3 °/h gyro bias, 0.15 °/√h ARW, 1 mg
/// accelerometer bias, 0.1 m/s/√h VRW.
pub fn spec() -> ImuSpec {
    ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(3.0)
        .with_gyro_arw_deg_per_sqrt_h(0.15)
        .with_accel_bias_mg(1.0)
        .with_accel_vrw_m_s_per_sqrt_h(0.1)
}

/// The GNSS antenna in the body frame, m.
pub fn lever() -> Vector3<f64> {
    Vector3::new(0.5, 0.3, -1.2)
}

/// 1 Hz fixes with σ (1, 1, 2) m and 0.05 m/s, taken at [`lever`].
pub fn gnss_config() -> GnssConfig {
    let mut config = GnssConfig::new(
        1.0,
        Vector3::new(1.0, 1.0, 2.0),
        Some(Vector3::repeat(0.05)),
    );
    config.lever_arm = lever();
    config
}

/// An IMU of [`spec`] with its errors and noise drawn from `seed`.
pub fn imu_sensor(seed: u64) -> ImuSensor {
    let errors = ImuErrors::sample(&spec(), &mut sensor_rng(seed, SensorStream::Constants));
    ImuSensor::new(errors, seed)
}

/// The initial σ of the filter's navigation errors: 0.05° level and 0.5°
/// heading, 0.1 m/s, 2 m.
pub fn uncertainty() -> InitialUncertainty {
    InitialUncertainty {
        att: Vector3::new(0.05, 0.05, 0.5).map(f64::to_radians),
        vel: Vector3::repeat(0.1),
        pos: Vector3::repeat(2.0),
    }
}
