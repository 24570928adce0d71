//! Loosely coupled INS/GNSS on a simulated drive: a tactical-grade IMU at
//! 100 Hz, GNSS position and velocity at 1 Hz with a 60 s outage, a 15-state
//! error-state Kalman filter with closed-loop feedback.
//! Run with `cargo run --release --example ins_gnss`.
use kestrel::nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
use kestrel::nav::measurement::GnssAntenna;
use kestrel::nav::nalgebra::{SVector, Vector3};
use kestrel::nav::{Ellipsoid, Geodetic, ImuSpec, NavError, Strapdown};
use kestrel::sim::{
    sensor_rng, GnssConfig, GnssSensor, ImuErrors, ImuSensor, Segment, SensorStream, TimeWindow,
    Trajectory, TrajectorySpec, Vehicle,
};
use kestrel::Ekf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let earth = Ellipsoid::wgs84();
    // 10 m/s north, then turns, a speed-up and a climb: 10 minutes.
    let spec = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(30.5, 114.3, 20.0),
        0.0,
        10.0,
    )
    .then(Segment::Cruise { duration: 60.0 })
    .then(Segment::turn_rate_deg(6.0, 90.0))
    .then(Segment::Accelerate {
        accel: 1.0,
        duration: 8.0,
    })
    .then(Segment::climb_pitch_deg(2.0, 60.0))
    .then(Segment::turn_rate_deg(8.0, -135.0))
    .then(Segment::CruiseUntil { time: 600.0 });
    let trajectory = Trajectory::new(&spec, earth)?;

    // The IMU the filter assumes, and the errors this run actually has.
    let imu_spec = ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(3.0)
        .with_gyro_arw_deg_per_sqrt_h(0.15)
        .with_accel_bias_mg(1.0)
        .with_accel_vrw_m_s_per_sqrt_h(0.1);
    let seed = 1;
    let errors = ImuErrors::sample(&imu_spec, &mut sensor_rng(seed, SensorStream::Constants));
    let mut imu = ImuSensor::new(errors, seed);
    let mut gnss_config = GnssConfig::new(
        1.0,
        Vector3::new(1.0, 1.0, 2.0),
        Some(Vector3::repeat(0.05)),
    );
    gnss_config.outages.push(TimeWindow::new(300.0, 360.0));
    let mut gnss = GnssSensor::new(gnss_config, earth, seed);

    let system = Ins15::new(imu_spec);
    let uncertainty = InitialUncertainty::new(0.5_f64.to_radians(), 0.1, 2.0);
    let p0 = system.initial_covariance(&uncertainty);
    let filter = Ekf::<f64, 15>::new(SVector::zeros(), p0)?;
    let ins = Strapdown::new(earth, trajectory.initial_state());
    let mut engine =
        LooselyCoupled::new(ins, filter, system, GnssAntenna::new(Vector3::zeros()), 0.1);

    let mut stream = trajectory.stream(100.0)?;
    while let Some((truth, increment)) = stream.next() {
        engine.imu(&imu.corrupt(&increment))?;
        if let Some(fix) = gnss.sample(&truth, &stream.motion().omega_nb) {
            engine.gnss(&fix.value)?;
        }
        let t = truth.time.round();
        if (truth.time - t).abs() < 1e-6 && (t as u64).is_multiple_of(60) {
            let e = NavError::between(&earth, engine.solution(), &truth);
            println!(
                "t={t:4} s  position error {:6.2} m  velocity error {:5.3} m/s  heading error {:6.3}°",
                e.dr.norm(),
                e.dv.norm(),
                e.phi.z.to_degrees()
            );
        }
    }
    let estimated = engine.corrections().imu;
    println!(
        "gyro bias  true {:?} °/h",
        (errors.gyro_bias * 3600.0).map(f64::to_degrees).as_slice()
    );
    println!(
        "gyro bias  est. {:?} °/h",
        (estimated.gyro * 3600.0).map(f64::to_degrees).as_slice()
    );
    Ok(())
}
