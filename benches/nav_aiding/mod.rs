//! The aiding benchmarks: one 15-state GNSS update of the loosely coupled
//! engine, and a full 1 h INS/GNSS run at 200 Hz (IMU data simulated once,
//! before timing, so only the engine is timed).

// The IMU, antenna and receiver of the nav crate's aiding tests.
#[path = "../../crates/nav/tests/suite/aiding/tactical.rs"]
mod tactical;

use std::hint::black_box;
use std::time::Instant;

use criterion::Criterion;
use kestrel::nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
use kestrel::nav::measurement::{GnssAntenna, GnssFix};
use kestrel::nav::nalgebra::SVector;
use kestrel::nav::{Ellipsoid, Geodetic, ImuIncrement, NavState, Strapdown};
use kestrel::sim::{GnssSensor, Segment, Trajectory, TrajectorySpec, Vehicle};
use kestrel::Ekf;
use tactical::{gnss_config, imu_sensor, lever, spec};

/// IMU rate of the run, Hz.
const RATE: f64 = 200.0;

type Engine = LooselyCoupled<f64, 15, Ins15, kestrel::form::CovarianceForm<f64, 15>>;

fn engine(start: NavState) -> Engine {
    let system = Ins15::new(spec());
    let p0 = system.initial_covariance(&InitialUncertainty::new(1e-3, 0.1, 2.0));
    LooselyCoupled::new(
        Strapdown::new(Ellipsoid::wgs84(), start),
        Ekf::new(SVector::zeros(), p0).unwrap(),
        system,
        GnssAntenna::new(lever()),
        0.1,
    )
}

/// One hour of driving with turns: noisy 200 Hz IMU data and 1 Hz fixes.
fn hour() -> (NavState, Vec<ImuIncrement>, Vec<GnssFix>) {
    let earth = Ellipsoid::wgs84();
    let mut spec_t = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(30.5, 114.3, 20.0),
        0.0,
        15.0,
    );
    for _ in 0..12 {
        spec_t = spec_t
            .then(Segment::Cruise { duration: 120.0 })
            .then(Segment::turn_rate_deg(5.0, 90.0))
            .then(Segment::Cruise { duration: 60.0 })
            .then(Segment::turn_rate_deg(5.0, -90.0))
            .then(Segment::Accelerate {
                accel: 0.5,
                duration: 10.0,
            })
            .then(Segment::Accelerate {
                accel: -0.5,
                duration: 10.0,
            });
    }
    let spec_t = spec_t.then(Segment::CruiseUntil { time: 3600.0 });
    let traj = Trajectory::new(&spec_t, earth).unwrap();
    let start = traj.initial_state();
    let mut imu = imu_sensor(1);
    let mut gnss = GnssSensor::new(gnss_config(), earth, 1);
    let mut stream = traj.stream(RATE).unwrap();
    let (mut imus, mut fixes) = (Vec::new(), Vec::new());
    while let Some((truth, exact)) = stream.next() {
        imus.push(imu.corrupt(&exact));
        if let Some(f) = gnss.sample(&truth, &stream.motion().omega_nb) {
            fixes.push(f.value);
        }
    }
    (start, imus, fixes)
}

fn run(start: NavState, imus: &[ImuIncrement], fixes: &[GnssFix]) -> NavState {
    let mut e = engine(start);
    e.run_gnss(imus.iter().copied(), fixes.iter().copied(), None, |ep| {
        black_box(ep.nav.pos.lat);
    })
    .unwrap();
    *e.solution()
}

/// `nav_step/gnss_update_15`: measurement, update and feedback of one fix.
pub fn gnss_update(c: &mut Criterion) {
    let (start, imus, fixes) = hour();
    let mut e = engine(start);
    // Converged: run the first minute.
    let n = (60.0 * RATE) as usize;
    e.run_gnss(
        imus[..n].iter().copied(),
        fixes.iter().copied().take(59),
        None,
        |_| {},
    )
    .unwrap();
    let fix = fixes[59];
    c.bench_function("nav_step/gnss_update_15", |b| {
        b.iter(|| black_box(e.gnss(black_box(&fix)).unwrap().nis))
    });
}

/// `nav_run/ins_gnss_1h`: the whole hour, mechanisation at 200 Hz,
/// covariance every 0.1 s, GNSS updates at 1 Hz. Prints the real-time
/// factor of one untimed-by-criterion run first.
pub fn ins_gnss_hour(c: &mut Criterion) {
    let (start, imus, fixes) = hour();
    let t0 = Instant::now();
    let end = run(start, &imus, &fixes);
    let secs = t0.elapsed().as_secs_f64();
    assert!(end.pos.lat.is_finite());
    eprintln!(
        "nav_run/ins_gnss_1h: {} IMU samples, {} fixes in {secs:.3} s: {:.0}× real time",
        imus.len(),
        fixes.len(),
        3600.0 / secs
    );
    let mut group = c.benchmark_group("nav_run");
    group.sample_size(10);
    group.bench_function("ins_gnss_1h", |b| b.iter(|| run(start, &imus, &fixes)));
    group.finish();
}
