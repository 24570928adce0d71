//! The engine's per-sample and per-epoch steps never touch the heap: a
//! counting global allocator records the current thread's allocations
//! while armed, and IMU steps, covariance propagations, GNSS updates and
//! odometer updates run armed with a count of zero (covariance form and
//! SR-UKF, with and without an adapter).

use std::hint::black_box;

use kestrel_adaptive::ChiSquareGate;
use kestrel_core::{Ekf, SrUkf};
use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
use kestrel_nav::measurement::{GnssAntenna, GnssFix, Odometer, OdometerReading};
use kestrel_nav::nalgebra::{SVector, Vector3};
use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess};
use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
use kestrel_testkit::heap_calls;

#[test]
fn positive_control_counts_an_allocation() {
    kestrel_testkit::positive_control();
}

fn start() -> NavState {
    NavState::new(
        0.0,
        Geodetic::from_degrees(30.0, 114.0, 10.0),
        Vector3::new(10.0, 0.0, 0.0),
        Euler::default(),
    )
}

/// Level cruise north at 10 m/s: 100 Hz increments of the support force.
fn imu(k: usize, earth: &Ellipsoid) -> ImuIncrement {
    let g = earth.gravity(start().pos.lat, start().pos.h);
    ImuIncrement::from_rates(
        k as f64 * 0.01,
        0.01,
        earth.earth_rate_ned(start().pos.lat),
        Vector3::new(0.0, 0.0, -g),
    )
}

fn spec() -> ImuSpec {
    ImuSpec::perfect()
        .with_gyro_bias_deg_per_h(1.0)
        .with_gyro_arw_deg_per_sqrt_h(0.1)
        .with_accel_bias_mg(0.5)
        .with_accel_vrw_m_s_per_sqrt_h(0.05)
}

#[test]
fn gnss_engine_steps_do_not_allocate() {
    let earth = Ellipsoid::wgs84();
    let system = Ins15::new(spec());
    let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 2.0));
    let antenna = GnssAntenna::new(Vector3::new(0.3, 0.0, -1.0));
    let mut ekf = LooselyCoupled::new(
        Strapdown::new(earth, start()),
        Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(),
        system,
        antenna,
        0.1,
    );
    let mut gated = LooselyCoupled::new(
        Strapdown::new(earth, start()),
        Ekf::<f32, 15>::new(SVector::zeros(), p0.map(|v| v as f32))
            .unwrap()
            .with_adapter(ChiSquareGate::<f32, 6>::new(1e-6).unwrap()),
        system,
        antenna,
        0.1,
    );
    let mut srukf = LooselyCoupled::new(
        Strapdown::new(earth, start()),
        SrUkf::<f64, 15>::new(SVector::zeros(), p0).unwrap(),
        system,
        antenna,
        0.1,
    );
    let (_, calls) = heap_calls(|| {
        for k in 1..=300 {
            let inc = imu(k, &earth);
            ekf.imu(&inc).unwrap();
            gated.imu(&inc).unwrap();
            srukf.imu(&inc).unwrap();
            if k % 100 == 37 {
                // Between IMU samples, 3 ms after this one.
                let t = inc.time + 0.003;
                let truth = ekf.ins_context(t).state;
                let fix = GnssFix::new(t, truth.pos, truth.vel);
                black_box(ekf.gnss(&fix).unwrap());
                black_box(gated.gnss(&fix).unwrap());
                black_box(srukf.gnss(&fix).unwrap());
                black_box(ekf.epoch(t, None::<()>));
            }
        }
    });
    assert_eq!(calls, 0);
}

#[test]
fn odometer_engine_steps_do_not_allocate() {
    let earth = Ellipsoid::wgs84();
    let system = InsOdometer16::new(spec(), ScaleFactorProcess::as_published());
    let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 2.0));
    let mut engine = LooselyCoupled::new(
        Strapdown::new(earth, start()),
        Ekf::<f64, 16>::new(SVector::zeros(), p0).unwrap(),
        system,
        GnssAntenna::new(Vector3::zeros()),
        0.1,
    );
    let odometer = Odometer::new(0.05, 0.1).with_mounting(0.01, 0.02);
    let (_, calls) = heap_calls(|| {
        for k in 1..=300 {
            let inc = imu(k, &earth);
            engine.imu(&inc).unwrap();
            if k % 10 == 0 {
                let reading = OdometerReading::new(inc.time, 10.05);
                let m = engine.odometer_measurement(&odometer, &reading);
                black_box(engine.apply(&m).unwrap());
                black_box(engine.apply_with(&m, &mut ()).unwrap());
            }
        }
    });
    assert_eq!(calls, 0);
}
