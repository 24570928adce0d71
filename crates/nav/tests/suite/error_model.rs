//! The linear error models against the true error growth of the
//! mechanisation: two strapdown runs on the same increments, one from the
//! true initial state with perfect sensors, one with injected errors; the
//! difference after 60 s must match `Φ`-propagated errors within 5 %.

use crate::common_ins;

use common_ins::stationary_increment;
use kestrel_core::{Ekf, LinearizedProcess};
use kestrel_nav::error_model::{ins15, ins18, ForcingMean, Ins15Model, Ins18Model};
use kestrel_nav::nalgebra::{SMatrix, SVector, Vector3};
use kestrel_nav::{
    Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavError, NavState, Strapdown,
};

const DT: f64 = 0.01;
/// Covariance-propagation interval of the models (as an engine would use).
const INTERVAL: usize = 10;
const STEPS: usize = 6000;

#[derive(Clone, Copy)]
enum Motion {
    Stationary,
    Manoeuvring,
}

fn start(motion: Motion) -> NavState {
    let pos = Geodetic::from_degrees(34.0, 110.0, 200.0);
    match motion {
        Motion::Stationary => NavState::new(
            0.0,
            pos,
            Vector3::zeros(),
            Euler::from_degrees(1.0, -2.0, 30.0),
        ),
        Motion::Manoeuvring => NavState::new(
            0.0,
            pos,
            Vector3::new(15.0, 10.0, 0.0),
            Euler::from_degrees(0.0, 0.0, 33.7),
        ),
    }
}

/// Increments of step `k` (ending at `k·DT`) for the reference run.
fn increment(earth: &Ellipsoid, s0: &NavState, motion: Motion, k: usize) -> ImuIncrement {
    let t = (k as f64 - 0.5) * DT;
    let mut imu = match motion {
        Motion::Stationary => stationary_increment(earth, s0, DT),
        Motion::Manoeuvring => {
            // Turning, accelerating, gently rolling and pitching.
            let w = Vector3::new(0.01 * (0.5 * t).sin(), 0.02 * (0.3 * t).cos(), 0.05);
            let f = Vector3::new(
                0.5 + 0.3 * (0.2 * t).sin(),
                0.3 * (0.25 * t).cos(),
                -earth.gravity(s0.pos.lat, s0.pos.h),
            );
            ImuIncrement::from_rates(0.0, DT, w, f)
        }
    };
    imu.time = k as f64 * DT;
    imu
}

/// Sensor errors of the perturbed run: gyro and accelerometer (body) as
/// functions of time.
struct SensorErrors {
    gyro: Box<dyn Fn(f64) -> Vector3<f64>>,
    accel: Box<dyn Fn(f64) -> Vector3<f64>>,
    /// Scale-factor errors per body axis: `measured = (1 + s) true + …`.
    gyro_scale: Vector3<f64>,
    accel_scale: Vector3<f64>,
}

/// Runs both mechanisations and the linear prediction; returns the true
/// and predicted growth of `[φ, δv, δr]` over `STEPS` (final minus initial
/// error, so an injected error that barely changes is judged by its change,
/// not hidden by its size).
fn compare<const N: usize>(
    motion: Motion,
    dx0: SVector<f64, N>,
    errors: &SensorErrors,
    model: impl Fn(&NavState, &ForcingMean) -> SMatrix<f64, N, N>,
) -> (SVector<f64, 9>, SVector<f64, 9>) {
    let earth = Ellipsoid::wgs84();
    let s0 = start(motion);
    let mut reference = Strapdown::new(earth, s0);
    let perturbed_start = NavError::from_error_state(&dx0).apply(&earth, &s0);
    let mut perturbed = Strapdown::new(earth, perturbed_start);
    let mut dx = dx0;
    let mut mean = ForcingMean::default();
    let mut interval_start = s0;
    for k in 1..=STEPS {
        let imu = increment(&earth, &s0, motion, k);
        reference.step(&imu);
        let t = imu.time - 0.5 * DT;
        let mut bad = imu;
        bad.dtheta += (errors.gyro)(t) * DT + errors.gyro_scale.component_mul(&imu.dtheta);
        bad.dvel += (errors.accel)(t) * DT + errors.accel_scale.component_mul(&imu.dvel);
        perturbed.step(&bad);
        mean.add(&reference, DT);
        if k % INTERVAL == 0 {
            dx = model(&interval_start, &mean) * dx;
            mean.clear();
            interval_start = *reference.state();
        }
    }
    let initial = NavError::from_error_state(&dx0).to_vector();
    let truth = NavError::between(&earth, perturbed.state(), reference.state()).to_vector();
    (
        truth - initial,
        NavError::from_error_state(&dx).to_vector() - initial,
    )
}

/// Relative error of each 3-block (attitude, velocity, position) of the
/// growth; blocks whose true growth is below `floor` (rad, m/s, m) are
/// rounding-level and skipped.
fn block_errors(truth: &SVector<f64, 9>, pred: &SVector<f64, 9>) -> [f64; 3] {
    let floor = [1e-11, 1e-7, 1e-5];
    let mut out = [0.0; 3];
    for (b, o) in out.iter_mut().enumerate() {
        let t = truth.fixed_rows::<3>(3 * b);
        let p = pred.fixed_rows::<3>(3 * b);
        if t.norm() > floor[b] {
            *o = (t - p).norm() / t.norm();
        }
    }
    out
}

fn model15(nav: &NavState, mean: &ForcingMean) -> SMatrix<f64, 15, 15> {
    let m = Ins15Model::from_mean(&Ellipsoid::wgs84(), &ImuSpec::perfect(), nav, mean);
    LinearizedProcess::<f64, 15>::transition(&m, &SVector::zeros(), mean.dt())
}

fn constant(v: Vector3<f64>) -> Box<dyn Fn(f64) -> Vector3<f64>> {
    Box::new(move |_| v)
}

fn check15(name: &str, motion: Motion, dx0: SVector<f64, 15>) {
    let errors = SensorErrors {
        gyro: constant(dx0.fixed_rows::<3>(ins15::GYRO_BIAS).into()),
        accel: constant(dx0.fixed_rows::<3>(ins15::ACCEL_BIAS).into()),
        gyro_scale: Vector3::zeros(),
        accel_scale: Vector3::zeros(),
    };
    let (truth, pred) = compare(motion, dx0, &errors, model15);
    let rel = block_errors(&truth, &pred);
    println!(
        "{name}: growth |φ| {:.3e} rad, |δv| {:.3e} m/s, |δr| {:.3e} m; misfit {:.2e} {:.2e} {:.2e}",
        truth.fixed_rows::<3>(0).norm(),
        truth.fixed_rows::<3>(3).norm(),
        truth.fixed_rows::<3>(6).norm(),
        rel[0],
        rel[1],
        rel[2]
    );
    for (b, r) in rel.iter().enumerate() {
        assert!(*r < 0.05, "{name}: block {b} misfit {r}");
    }
}

fn injected(i: usize, v: [f64; 3]) -> SVector<f64, 15> {
    let mut x = SVector::<f64, 15>::zeros();
    x.fixed_rows_mut::<3>(i).copy_from(&Vector3::from(v));
    x
}

fn cases() -> Vec<(&'static str, SVector<f64, 15>)> {
    let att = injected(ins15::ATT, [1e-3, -1e-3, 2e-3]);
    let vel = injected(ins15::VEL, [0.1, -0.1, 0.05]);
    let pos = injected(ins15::POS, [10.0, -10.0, 5.0]);
    let gyro = injected(ins15::GYRO_BIAS, [1e-5, -1e-5, 2e-5]);
    let accel = injected(ins15::ACCEL_BIAS, [1e-3, -1e-3, 2e-3]);
    vec![
        ("attitude", att),
        ("velocity", vel),
        ("position", pos),
        ("gyro bias", gyro),
        ("accel bias", accel),
        ("combined", att + vel + pos + gyro + accel),
    ]
}

#[test]
fn phi_predicts_error_growth_stationary() {
    for (name, dx0) in cases() {
        check15(name, Motion::Stationary, dx0);
    }
}

#[test]
fn phi_predicts_error_growth_manoeuvring() {
    for (name, dx0) in cases() {
        check15(name, Motion::Manoeuvring, dx0);
    }
}

/// Single components one at a time (each of the 15), manoeuvring.
#[test]
fn phi_predicts_each_component() {
    let sizes = [1e-3, 1e-3, 2e-3, 0.1, 0.1, 0.05, 10.0, 10.0, 5.0];
    let biases = [2e-5, 1e-3];
    for i in 0..15 {
        let mut dx0 = SVector::<f64, 15>::zeros();
        dx0[i] = if i < 9 { sizes[i] } else { biases[(i - 9) / 3] };
        check15(&format!("component {i}"), Motion::Manoeuvring, dx0);
    }
}

/// The 18-state model with a decaying Markov gyro drift: the perturbed run
/// sees `ε_c + ε_r e^{−t/τ}` and `∇ e^{−t/τ_a}`.
#[test]
fn eighteen_state_markov_drift() {
    let tau = 100.0;
    let tau_a = 50.0;
    let spec = ImuSpec::perfect()
        .with_gyro_markov_deg_per_h(1.0, tau)
        .with_accel_markov_ug(100.0, tau_a);
    let mut dx0 = SVector::<f64, 18>::zeros();
    let eps_c = Vector3::new(5e-6, -5e-6, 1e-5);
    let eps_r = Vector3::new(-2e-5, 1e-5, 3e-5);
    let nabla = Vector3::new(1e-3, 2e-3, -1e-3);
    dx0.fixed_rows_mut::<3>(ins18::GYRO_CONST).copy_from(&eps_c);
    dx0.fixed_rows_mut::<3>(ins18::GYRO_MARKOV)
        .copy_from(&eps_r);
    dx0.fixed_rows_mut::<3>(ins18::ACCEL_BIAS).copy_from(&nabla);
    dx0[0] = 5e-4;
    dx0[4] = 0.05;
    let errors = SensorErrors {
        gyro: Box::new(move |t| eps_c + eps_r * (-t / tau).exp()),
        accel: Box::new(move |t| nabla * (-t / tau_a).exp()),
        gyro_scale: Vector3::zeros(),
        accel_scale: Vector3::zeros(),
    };
    let model = |nav: &NavState, mean: &ForcingMean| {
        *Ins18Model::from_mean(&Ellipsoid::wgs84(), &spec, nav, mean).phi()
    };
    for motion in [Motion::Stationary, Motion::Manoeuvring] {
        let (truth, pred) = compare(motion, dx0, &errors, model);
        let rel = block_errors(&truth, &pred);
        println!(
            "18-state: relative misfit {:.2e} {:.2e} {:.2e}",
            rel[0], rel[1], rel[2]
        );
        for r in rel {
            assert!(r < 0.05, "18-state misfit {r}");
        }
    }
}

/// The 21-state model with injected scale-factor errors of a few hundred
/// ppm (and biases): `Φ` predicts the true error growth within 5 %, and the
/// 15-state model (which has no scale states) does not when the vehicle
/// turns, so the check can fail.
#[test]
fn twenty_one_state_scale_factors() {
    use kestrel_nav::error_model::{ins21, Ins21Model};
    let gyro_scale = Vector3::new(400.0e-6, -300.0e-6, 500.0e-6);
    let accel_scale = Vector3::new(300.0e-6, 200.0e-6, -400.0e-6);
    let gyro = Vector3::new(5e-6, -5e-6, 1e-5);
    let accel = Vector3::new(5e-4, -5e-4, 1e-3);
    let mut dx0 = SVector::<f64, 21>::zeros();
    dx0.fixed_rows_mut::<3>(ins21::GYRO_BIAS).copy_from(&gyro);
    dx0.fixed_rows_mut::<3>(ins21::ACCEL_BIAS).copy_from(&accel);
    dx0.fixed_rows_mut::<3>(ins21::GYRO_SCALE)
        .copy_from(&gyro_scale);
    dx0.fixed_rows_mut::<3>(ins21::ACCEL_SCALE)
        .copy_from(&accel_scale);
    dx0[0] = 5e-4;
    dx0[4] = 0.05;
    let errors = || SensorErrors {
        gyro: constant(gyro),
        accel: constant(accel),
        gyro_scale,
        accel_scale,
    };
    let model = |nav: &NavState, mean: &ForcingMean| {
        let spec = ImuSpec::perfect();
        *Ins21Model::from_mean_scaled(&Ellipsoid::wgs84(), &spec, f64::INFINITY, nav, mean).phi()
    };
    for motion in [Motion::Stationary, Motion::Manoeuvring] {
        let (truth, pred) = compare(motion, dx0, &errors(), model);
        let rel = block_errors(&truth, &pred);
        println!(
            "21-state: growth |φ| {:.3e} rad, |δv| {:.3e} m/s, |δr| {:.3e} m; misfit {:.2e} {:.2e} {:.2e}",
            truth.fixed_rows::<3>(0).norm(),
            truth.fixed_rows::<3>(3).norm(),
            truth.fixed_rows::<3>(6).norm(),
            rel[0], rel[1], rel[2]
        );
        for r in rel {
            assert!(r < 0.05, "21-state misfit {r}");
        }
    }
    // Without scale states the same errors are mispredicted when turning.
    let dx15: SVector<f64, 15> = dx0.fixed_rows::<15>(0).into();
    let (truth, pred) = compare(Motion::Manoeuvring, dx15, &errors(), model15);
    let rel = block_errors(&truth, &pred);
    assert!(rel[0] > 0.2, "15-state attitude misfit only {}", rel[0]);
}

/// The models drive an f32 filter: one covariance prediction matches f64.
#[test]
fn f32_filter_predicts_like_f64() {
    let earth = Ellipsoid::wgs84();
    let nav = start(Motion::Manoeuvring);
    let spec = ImuSpec::perfect()
        .with_gyro_arw_deg_per_sqrt_h(0.1)
        .with_accel_vrw_m_s_per_sqrt_h(0.05)
        .with_gyro_markov_deg_per_h(1.0, 3600.0);
    let m = Ins15Model::new(&earth, &spec, &nav, &Vector3::new(0.5, 0.1, -9.8), 0.1);
    let mut p0 = SMatrix::<f64, 15, 15>::identity();
    for i in 0..3 {
        p0[(i, i)] = 1e-4;
        p0[(9 + i, 9 + i)] = 1e-10;
        p0[(12 + i, 12 + i)] = 1e-6;
    }
    let mut k64 = Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap();
    let mut k32 = Ekf::<f32, 15>::new(SVector::zeros(), p0.cast::<f32>()).unwrap();
    k64.predict(&m, 0.1).unwrap();
    k32.predict(&m, 0.1_f32).unwrap();
    let expected = m.phi() * p0 * m.phi().transpose() + m.qd();
    let p64 = k64.covariance();
    assert!((p64 - expected).norm() < 1e-12 * expected.norm());
    let p32 = k32.covariance().cast::<f64>();
    for i in 0..15 {
        let d = expected[(i, i)];
        assert!((p32[(i, i)] - d).abs() < 1e-5 * d, "P[{i},{i}]");
    }
}

/// Random-walk biases: no decay in `F`, the density on the bias states,
/// and their variance grows linearly over an interval.
#[test]
fn random_walk_biases() {
    let spec = ImuSpec::perfect()
        .with_gyro_bias_rw_deg_per_h_per_sqrt_h(6.0)
        .with_accel_bias_rw_ug_per_sqrt_h(30.0);
    let nav = start(Motion::Stationary);
    let earth = Ellipsoid::wgs84();
    let (f, q) = Ins15Model::continuous(&earth, &spec, &nav, &Vector3::new(0.0, 0.0, -9.8));
    let (g, a) = (ins15::GYRO_BIAS, ins15::ACCEL_BIAS);
    assert_eq!((f[(g, g)], f[(a, a)]), (0.0, 0.0));
    assert_eq!(q[g], spec.gyro_bias_rw.powi(2));
    assert_eq!(q[a + 2], spec.accel_bias_rw.powi(2));
    // 6 °/h/√h over 100 s: σ = 6 °/h × √(100 / 3600) = 1 °/h.
    let m = Ins15Model::new(&earth, &spec, &nav, &Vector3::new(0.0, 0.0, -9.8), 100.0);
    let sigma = m.qd()[(g, g)].sqrt().to_degrees() * 3600.0;
    assert!((sigma - 1.0).abs() < 1e-9, "{sigma}");
}
