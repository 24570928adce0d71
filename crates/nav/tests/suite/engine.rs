//! The loosely coupled engine: GNSS outages (coasting), aiding epochs
//! between IMU samples, equality with a hand-driven filter loop, and the
//! same run through other filter types (SR-UKF, f32, an adapter tuple).

use crate::aiding;

use aiding::tactical::{gnss_config, imu_sensor, lever, spec, uncertainty};
use aiding::{drive, perturb, record, Normal, Sample};
use kestrel_adaptive::{ChiSquareGate, HuberInflation};
use kestrel_core::form::PredictForm;
use kestrel_core::{Ekf, Filter, SrUkf};
use kestrel_nav::engine::{Epoch, ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
use kestrel_nav::error_model::{ForcingMean, Ins15Model};
use kestrel_nav::measurement::{GnssAntenna, GnssFix, InsContext};
use kestrel_nav::nalgebra::{SMatrix, SVector, Vector3};
use kestrel_nav::{
    feedback_ins15, Ellipsoid, Geodetic, ImuBiases, ImuIncrement, ImuSpec, NavError, NavState,
    Strapdown,
};
use kestrel_sim::{GnssConfig, GnssSensor, Segment, TimeWindow, TrajectorySpec, Vehicle};

const RATE: f64 = 100.0;

/// Noisy IMU increments and GNSS fixes of one seeded run over `samples`.
fn sensors(
    seed: u64,
    samples: &[Sample],
    outages: Vec<TimeWindow>,
) -> (Vec<ImuIncrement>, Vec<GnssFix>) {
    let mut imu = imu_sensor(seed);
    let config = GnssConfig {
        outages,
        ..gnss_config()
    };
    let mut gnss = GnssSensor::new(config, Ellipsoid::wgs84(), seed);
    let imus = samples.iter().map(|s| imu.corrupt(&s.imu)).collect();
    let fixes = samples
        .iter()
        .filter_map(|s| gnss.sample(&s.truth, &s.motion.omega_nb))
        .map(|f| f.value)
        .collect();
    (imus, fixes)
}

/// An engine over filter `filter` starting from the seeded initial errors.
fn engine<F, A>(
    filter: Filter<f64, 15, F, A>,
    start: &NavState,
    seed: u64,
) -> LooselyCoupled<f64, 15, Ins15, F, A>
where
    F: kestrel_core::form::Form<f64, 15> + PredictForm<f64, 15, Ins15Model>,
    A: kestrel_core::adapter::PriorAdapter<f64>,
{
    let earth = Ellipsoid::wgs84();
    let initial = perturb(&earth, start, &uncertainty(), &mut Normal::new(seed));
    LooselyCoupled::new(
        Strapdown::new(earth, initial),
        filter,
        Ins15::new(spec()),
        GnssAntenna::new(lever()),
        0.1,
    )
}

fn p0() -> SMatrix<f64, 15, 15> {
    Ins15::new(spec()).initial_covariance(&uncertainty())
}

fn short_drive() -> (NavState, Vec<Sample>) {
    record(
        &drive(Geodetic::from_degrees(30.5, 114.3, 20.0), 3),
        Ellipsoid::wgs84(),
        RATE,
    )
}

/// Position σ (m): the root of the trace of the position block.
fn pos_sigma<R>(e: &Epoch<f64, 15, R>) -> f64 {
    (e.covariance[(6, 6)] + e.covariance[(7, 7)] + e.covariance[(8, 8)]).sqrt()
}

#[test]
fn gnss_outage_coasts_without_updates_while_the_covariance_grows() {
    let (start, samples) = short_drive();
    let outage = TimeWindow::new(60.0, 120.0);
    let (imus, fixes) = sensors(7, &samples, vec![outage]);
    assert!(fixes.iter().all(|f| !outage.contains(f.time)));
    let mut e = engine(Ekf::new(SVector::zeros(), p0()).unwrap(), &start, 7);

    let mut epochs = Vec::new();
    e.run_gnss(imus, fixes.iter().copied(), Some(1.0), |ep| {
        epochs.push((ep.time, ep.report.is_some(), pos_sigma(ep), ep.nav));
    })
    .unwrap();

    let updates = epochs.iter().filter(|e| e.1).count();
    assert_eq!(updates, fixes.len(), "one update report per fix");
    // Inside the outage: coasting epochs only, one per second, position σ
    // strictly growing.
    let coast: Vec<_> = epochs
        .iter()
        .filter(|e| e.0 > 60.5 && e.0 < 119.5)
        .collect();
    assert!(coast.len() >= 58, "{} coasting epochs", coast.len());
    assert!(
        coast.iter().all(|e| !e.1),
        "no update reports during the outage"
    );
    assert!(
        coast.windows(2).all(|w| w[1].2 > w[0].2),
        "σ grows while coasting"
    );
    let before = epochs.iter().rfind(|e| e.1 && e.0 < 60.0).unwrap();
    let last_coast = coast.last().unwrap();
    let after = epochs.iter().find(|e| e.1 && e.0 > 120.0).unwrap();
    assert!(
        last_coast.2 > 3.0 * before.2,
        "σ {} → {}",
        before.2,
        last_coast.2
    );
    assert!(
        after.2 < 0.5 * last_coast.2,
        "the first fix after the outage shrinks σ"
    );
    // The coasting solution drifts; the first fix pulls it back.
    let earth = Ellipsoid::wgs84();
    let truth_at = |t: f64| samples[(t * RATE).round() as usize - 1].truth;
    let err = |e: &(f64, bool, f64, NavState)| {
        NavError::between(&earth, &e.3, &truth_at(e.3.time))
            .dr
            .norm()
    };
    assert!(
        err(last_coast) > 2.0 * err(before),
        "{} vs {}",
        err(last_coast),
        err(before)
    );
    assert!(err(after) < 0.5 * err(last_coast));
}

/// A straight run accelerating at 1 m/s² from 15 m/s with a perfect IMU:
/// fixes 4 ms after an IMU sample, exact truth. With the extrapolation the
/// innovation is the truth's third-order remainder; without it, it would
/// be v · 4 ms ≈ 6 cm and a · 4 ms = 4 mm/s.
#[test]
fn an_epoch_between_imu_samples_is_extrapolated() {
    let earth = Ellipsoid::wgs84();
    let spec = TrajectorySpec::new(
        Vehicle::Ground,
        Geodetic::from_degrees(30.0, 114.0, 0.0),
        0.7,
        15.0,
    )
    .then(Segment::Accelerate {
        accel: 1.0,
        duration: 12.0,
    });
    // Truth at 1 kHz; the IMU at 100 Hz sums ten increments (no rotation:
    // the sums are exact to the Earth rate's 1e-9).
    let (start, fine) = record(&spec, earth, 1000.0);
    let imus: Vec<ImuIncrement> = fine
        .chunks(10)
        .map(|c| ImuIncrement {
            time: c[9].imu.time,
            dt: c.iter().map(|s| s.imu.dt).sum(),
            dtheta: c.iter().map(|s| s.imu.dtheta).sum(),
            dvel: c.iter().map(|s| s.imu.dvel).sum(),
        })
        .collect();
    let fixes: Vec<GnssFix> = (1..12)
        .map(|k| {
            let t = &fine[k * 1000 + 3].truth; // 4 ms after the IMU sample at k s
            GnssFix::new(t.time, t.pos, t.vel)
        })
        .collect();
    let system = Ins15::new(ImuSpec::perfect());
    let p = system.initial_covariance(&InitialUncertainty::new(1e-4, 0.01, 0.1));
    let mut e = LooselyCoupled::new(
        Strapdown::new(earth, start),
        Ekf::<f64, 15>::new(SVector::zeros(), p).unwrap(),
        system,
        GnssAntenna::new(Vector3::zeros()),
        0.1,
    );
    let mut worst = (0.0f64, 0.0f64);
    e.run_gnss(imus, fixes, None, |ep| {
        let r = ep.report.unwrap();
        assert!(
            (ep.time - ep.nav.time - 0.004).abs() < 1e-9,
            "processed at the earlier sample"
        );
        worst.0 = worst.0.max(r.innovation.fixed_rows::<3>(0).norm());
        worst.1 = worst.1.max(r.innovation.fixed_rows::<3>(3).norm());
    })
    .unwrap();
    assert!(worst.0 < 1e-3 && worst.1 < 1e-4, "innovations {worst:?}");
}

/// Irregular fixes (gaps of 0.4–2.6 s, at any time between IMU samples)
/// give exactly the result of the engine's algorithm written out with the
/// crate's parts: bias compensation, mechanisation, covariance propagation
/// every 0.1 s and before each update, extrapolated measurement, update,
/// feedback, reset.
#[test]
fn same_result_as_a_hand_driven_filter_loop() {
    let earth = Ellipsoid::wgs84();
    let (start, samples) = short_drive();
    let (imus, _) = sensors(3, &samples, vec![]);
    let mut rng = Normal::new(99);
    let mut fixes = Vec::new();
    let mut t = 0.3;
    while t < 170.0 {
        let k = (t * RATE).floor() as usize - 1;
        let s = &samples[k].truth;
        let dt = t - s.time;
        let pos = earth.displace(&s.pos, &(s.vel * dt + rng.vec3(&Vector3::repeat(1.0))));
        fixes.push(GnssFix::new(
            t,
            pos,
            s.vel + rng.vec3(&Vector3::repeat(0.05)),
        ));
        t += 1.5 + 1.1 * rng.next().clamp(-1.0, 1.0) + 0.00123;
    }

    let mut e = engine(Ekf::new(SVector::zeros(), p0()).unwrap(), &start, 3);
    let mut reports = Vec::new();
    e.run_gnss(imus.iter().copied(), fixes.iter().copied(), None, |ep| {
        reports.push(ep.report.unwrap().nis)
    })
    .unwrap();

    // The hand-driven loop.
    let initial = perturb(&earth, &start, &uncertainty(), &mut Normal::new(3));
    let mut ins = Strapdown::new(earth, initial);
    let mut kf = Ekf::<f64, 15>::new(SVector::zeros(), p0()).unwrap();
    let mut biases = ImuBiases::default();
    let mut mean = ForcingMean::default();
    let (mut omega, mut accel) = (Vector3::zeros(), Vector3::zeros());
    let antenna = GnssAntenna::new(lever());
    let system = Ins15::new(spec());
    let mut next = fixes.iter().peekable();
    let mut nis = Vec::new();
    let propagate = |kf: &mut Ekf<f64, 15>, mean: &mut ForcingMean, ins: &Strapdown| {
        if mean.dt() > 0.0 {
            let model = Ins15Model::from_mean(&earth, &system.spec, ins.state(), mean);
            kf.predict(&model, mean.dt()).unwrap();
            mean.clear();
        }
    };
    for raw in &imus {
        while let Some(fix) = next.next_if(|f| f.time < raw.time) {
            propagate(&mut kf, &mut mean, &ins);
            let ctx = InsContext::new(earth, *ins.state(), omega)
                .extrapolated(fix.time - ins.state().time, &accel);
            let m = antenna.position_velocity::<f64, 15, _>(&system, &ctx, fix);
            nis.push(kf.update(&m, &m.z()).unwrap().nis);
            let dx = *kf.state();
            feedback_ins15(&earth, ins.state_mut(), &mut biases, &dx);
            kf.set_state(SVector::zeros()).unwrap();
        }
        let imu = biases.compensate(raw);
        let v0 = ins.state().vel;
        ins.step(&imu);
        omega = imu.dtheta / imu.dt;
        accel = (ins.state().vel - v0) / imu.dt;
        mean.add(&ins, imu.dt);
        if mean.dt() >= 0.1 - 1e-9 {
            propagate(&mut kf, &mut mean, &ins);
        }
    }

    assert_eq!(nis.len(), fixes.len());
    assert_eq!(reports, nis, "the same innovations at every epoch");
    let (a, b) = (e.solution(), ins.state());
    assert_eq!((a.pos, a.vel, a.att), (b.pos, b.vel, b.att));
    assert_eq!(e.corrections().imu, biases);
    assert_eq!(e.covariance(), kf.covariance());
    // And it navigates: irregular epochs need no special handling.
    let truth = samples.last().unwrap().truth;
    assert!(NavError::between(&earth, a, &truth).dr.norm() < 3.0);
}

/// The same run through the SR-UKF, an f32 covariance filter and a filter
/// with an adapter tuple: the error-state models are linear, so all agree
/// with the f64 covariance filter (to rounding, f32 to its precision).
#[test]
fn any_filter_type_runs_the_engine() {
    let earth = Ellipsoid::wgs84();
    let (start, samples) = short_drive();
    let (imus, fixes) = sensors(11, &samples, vec![]);
    let truth = samples.last().unwrap().truth;

    let mut ekf = engine(Ekf::new(SVector::zeros(), p0()).unwrap(), &start, 11);
    ekf.run_gnss(imus.iter().copied(), fixes.iter().copied(), None, |_| {})
        .unwrap();
    let reference = *ekf.solution();
    assert!(NavError::between(&earth, &reference, &truth).dr.norm() < 3.0);
    let close = |nav: &NavState, tol_m: f64| {
        let d = NavError::between(&earth, nav, &reference);
        assert!(d.dr.norm() < tol_m && d.dv.norm() < tol_m / 10.0, "{d:?}");
    };

    let mut srukf = engine(SrUkf::new(SVector::zeros(), p0()).unwrap(), &start, 11);
    srukf
        .run_gnss(imus.iter().copied(), fixes.iter().copied(), None, |_| {})
        .unwrap();
    close(srukf.solution(), 1e-6);

    // A gate that never fires and paper 002's Huber inflation at 1 %: a few
    // components of clean data get inflated, so the result moves a little.
    let gated = Ekf::new(SVector::zeros(), p0()).unwrap().with_adapter((
        ChiSquareGate::<f64, 6>::new(1e-9).unwrap(),
        HuberInflation::<f64, 6>::new(0.01).unwrap(),
    ));
    let mut adapted = engine(gated, &start, 11);
    let (mut rejected, mut inflated) = (0, 0);
    adapted
        .run_gnss(imus.iter().copied(), fixes.iter().copied(), None, |ep| {
            let r = ep.report.unwrap();
            rejected += r.adapters.0.rejected as usize;
            inflated += r.adapters.1.inflated;
        })
        .unwrap();
    assert_eq!(rejected, 0);
    assert!(
        inflated > 0 && inflated < fixes.len() / 5,
        "{inflated} inflated components"
    );
    close(adapted.solution(), 0.5);

    let initial = perturb(&earth, &start, &uncertainty(), &mut Normal::new(11));
    let mut single = LooselyCoupled::new(
        Strapdown::new(earth, initial),
        Ekf::<f32, 15>::new(SVector::zeros(), p0().map(|v| v as f32)).unwrap(),
        Ins15::new(spec()),
        GnssAntenna::new(lever()),
        0.1,
    );
    single
        .run_gnss(imus.iter().copied(), fixes.iter().copied(), None, |_| {})
        .unwrap();
    close(single.solution(), 0.05);
}

/// The 18-state system of papers 000/004 with the attitude + velocity +
/// position measurement (m = 9) through the generic `apply`: the attitude
/// reference (σ 0.05°) pins the yaw that GNSS alone would leave loose.
#[test]
fn eighteen_states_with_an_attitude_reference() {
    use kestrel_nav::engine::Ins18;
    use kestrel_nav::measurement::AttitudeFix;
    let earth = Ellipsoid::wgs84();
    let (start, samples) = short_drive();
    let (imus, fixes) = sensors(5, &samples, vec![]);
    let spec18 = spec().with_gyro_markov_deg_per_h(1.0, 3600.0);
    let system = Ins18::new(spec18);
    let p0 = system.initial_covariance(&uncertainty());
    let initial = perturb(&earth, &start, &uncertainty(), &mut Normal::new(5));
    let mut e = LooselyCoupled::new(
        Strapdown::new(earth, initial),
        Ekf::<f64, 18>::new(SVector::zeros(), p0).unwrap(),
        system,
        GnssAntenna::new(lever()),
        0.1,
    );
    let att_std = Vector3::repeat(0.05f64.to_radians());
    let mut rng = Normal::new(55);
    let mut updates = 0;
    e.drive(imus, fixes, |e, fix| {
        let k = (fix.time * RATE).round() as usize - 1;
        let truth = samples[k].truth.att;
        let att = kestrel_nav::correct_attitude(&truth, &rng.vec3(&att_std));
        let m = e.antenna().attitude_velocity_position(
            e.system(),
            &e.ins_context(fix.time),
            &AttitudeFix::new(fix.time, att, att_std),
            &fix,
        );
        updates += 1;
        e.apply(&m).map(|_| ())
    })
    .unwrap();
    assert_eq!(updates, 180);
    let truth = samples.last().unwrap().truth;
    let err = NavError::between(&earth, e.solution(), &truth);
    let sd = e.std_devs();
    for i in 0..3 {
        assert!(
            err.phi[i].abs() < 3.0 * sd[i],
            "attitude {i}: {} vs σ {}",
            err.phi[i],
            sd[i]
        );
        assert!(sd[i] < 0.05f64.to_radians(), "attitude σ {i}: {}", sd[i]);
    }
}
