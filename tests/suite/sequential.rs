//! Sequential scalar updates (diagonal `R`, no adapter) give the batch
//! update: state, covariance, innovation covariance and NIS agree to 1e-12
//! (f64), on random stable linear models of 2 to 24 states and on an EKF
//! with a nonlinear range / bearing / range-rate measurement.
//!
//! Each update starts both filters from the same prior (the batch filter is
//! reset to the sequential one's estimate), so the comparison is of one
//! update at a time along the whole run, not of two diverging roundings.

use crate::common;

use common::{dispatch, SIZES};
use kestrel::form::SequentialUpdates;
use kestrel::models::LinearProcess;
use kestrel::nalgebra::{Matrix3, Matrix3x4, Matrix4, SVector, Vector3, Vector4};
use kestrel::{Ekf, LinearizedMeasurement, MeasurementModel, UpdateDetail};
use rand::RngExt;
use rand_distr::StandardNormal;

const TOL: f64 = 1e-12;

/// Asserts the sequential and batch results agree to [`TOL`].
#[track_caller]
fn assert_same<const N: usize, const M: usize>(
    (seq, seq_detail): (&Ekf<f64, N>, &UpdateDetail<f64, M>),
    (batch, batch_detail): (&Ekf<f64, N>, &UpdateDetail<f64, M>),
    what: &str,
) {
    let (seq_report, batch_report) = (&seq_detail.report, &batch_detail.report);
    assert!(seq_report.sequential, "{what}: sequential path not taken");
    assert!(!batch_report.sequential, "{what}: batch path not taken");
    let p_ref = batch.covariance();
    let dp = common::relative_difference(&seq.covariance(), &p_ref);
    assert!(dp <= TOL, "{what}: covariance differs by {dp:e}");
    let dx = common::state_difference(seq.state(), batch.state(), &p_ref);
    assert!(dx <= TOL, "{what}: state differs by {dx:e}");
    let c_ref = batch_detail.innovation_covariance;
    let dc = common::relative_difference(&seq_detail.innovation_covariance, &c_ref);
    assert!(dc <= TOL, "{what}: innovation covariance differs by {dc:e}");
    let dn = (seq_report.nis - batch_report.nis).abs() / batch_report.nis;
    assert!(
        dn <= TOL,
        "{what}: NIS {} vs {}",
        seq_report.nis,
        batch_report.nis
    );
    assert_eq!(seq_report.innovation, batch_report.innovation, "{what}");
}

/// Runs a random linear case, comparing every update.
fn linear<const N: usize, const M: usize>(seed: u64) {
    let case = common::linear_case::<N, M>(seed, 50, true);
    let mut seq = Ekf::new(case.x0, case.p0).expect("finite");
    seq.form_mut().set_sequential(true);
    let mut batch = seq.clone();
    batch.form_mut().set_sequential(false);
    for (k, z) in case.measurements.iter().enumerate() {
        seq.predict(&case.process, 1.0).expect("predict");
        batch.set_state(*seq.state()).expect("finite");
        batch.set_covariance(&seq.covariance()).expect("finite");
        let seq_report = seq.update_detailed(&case.measurement, z).expect("update");
        let batch_report = batch.update_detailed(&case.measurement, z).expect("update");
        let what = format!("N = {N}, M = {M}, seed {seed}, step {k}");
        assert_same((&seq, &seq_report), (&batch, &batch_report), &what);
    }
}

#[test]
fn sequential_equals_batch_on_random_linear_models() {
    for seed in 0..4u64 {
        for &size in SIZES {
            dispatch!(size, linear(seed));
        }
    }
}

/// Whether one update of an `N`-state filter with `when`, on an
/// `M`-component measurement with a diagonal (or a dense) `R`, went one
/// component at a time.
fn path_at<const N: usize, const M: usize>(when: SequentialUpdates, diagonal_r: bool) -> bool {
    let case = common::linear_case::<N, M>(11, 1, diagonal_r);
    let mut f = Ekf::new(case.x0, case.p0).expect("finite");
    f.form_mut().set_sequential_updates(when);
    assert_eq!(f.form().sequential_updates(), when);
    f.predict(&case.process, 1.0).expect("predict");
    let report = f.update(&case.measurement, &case.measurements[0]);
    report.expect("update").sequential
}

/// The paths of one to six components in a 6-state filter, in order.
fn paths(when: SequentialUpdates, diagonal_r: bool) -> [bool; 6] {
    [
        path_at::<6, 1>(when, diagonal_r),
        path_at::<6, 2>(when, diagonal_r),
        path_at::<6, 3>(when, diagonal_r),
        path_at::<6, 4>(when, diagonal_r),
        path_at::<6, 5>(when, diagonal_r),
        path_at::<6, 6>(when, diagonal_r),
    ]
}

#[test]
fn the_default_takes_a_diagonal_r_one_component_at_a_time_from_four_components_up_to_twelve_states()
{
    use SequentialUpdates::{Always, BySize, Never};
    assert_eq!(SequentialUpdates::default(), BySize);
    assert_eq!(SequentialUpdates::MIN_COMPONENTS, 4);
    assert_eq!(SequentialUpdates::MAX_STATES, 12);
    // The state-size bound, on either side.
    assert!(path_at::<12, 4>(BySize, true));
    assert!(!path_at::<13, 4>(BySize, true));
    assert!(!path_at::<15, 6>(BySize, true));
    assert!(path_at::<15, 6>(Always, true));
    let f = Ekf::new(Vector4::zeros(), Matrix4::<f64>::identity()).expect("finite");
    assert_eq!(f.form().sequential_updates(), BySize);
    assert_eq!(paths(BySize, true), [false, false, false, true, true, true]);
    assert_eq!(paths(Always, true), [true; 6]);
    assert_eq!(paths(Never, true), [false; 6]);
    // A dense `R` takes the batch update (a 1 × 1 one is diagonal).
    for when in [BySize, Always, Never] {
        assert_eq!(paths(when, false)[1..], [false; 5], "{when:?}");
    }
    // The shorthand, and the getter it replaces.
    let mut f = f;
    f.form_mut().set_sequential(true);
    assert_eq!(f.form().sequential_updates(), Always);
    #[allow(deprecated)]
    let enabled = f.form().sequential();
    assert!(enabled);
    f.form_mut().set_sequential(false);
    assert_eq!(f.form().sequential_updates(), Never);
    #[allow(deprecated)]
    let enabled = f.form().sequential();
    assert!(!enabled);
}

/// Range, bearing and range rate of a target `[px, py, vx, vy]` seen from
/// the origin.
struct RangeBearingRate {
    noise: Matrix3<f64>,
}

impl MeasurementModel<f64, 4, 3> for RangeBearingRate {
    fn predict(&self, x: &Vector4<f64>) -> Vector3<f64> {
        let range = x[0].hypot(x[1]);
        Vector3::new(range, x[1].atan2(x[0]), (x[0] * x[2] + x[1] * x[3]) / range)
    }
    fn noise(&self) -> Matrix3<f64> {
        self.noise
    }
    fn residual(&self, z: &Vector3<f64>, predicted: &Vector3<f64>) -> Vector3<f64> {
        let mut d = z - predicted;
        d[1] =
            (d[1] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        d
    }
}

impl LinearizedMeasurement<f64, 4, 3> for RangeBearingRate {
    fn jacobian(&self, x: &Vector4<f64>) -> Matrix3x4<f64> {
        let (px, py, vx, vy) = (x[0], x[1], x[2], x[3]);
        let r2 = px * px + py * py;
        let r = r2.sqrt();
        let rate = (px * vx + py * vy) / r;
        Matrix3x4::new(
            px / r,
            py / r,
            0.0,
            0.0,
            -py / r2,
            px / r2,
            0.0,
            0.0,
            (vx - rate * px / r) / r,
            (vy - rate * py / r) / r,
            px / r,
            py / r,
        )
    }
}

#[test]
fn sequential_equals_batch_on_a_nonlinear_ekf() {
    let dt = 1.0f64;
    let phi = Matrix4::new(
        1.0, 0.0, dt, 0.0, //
        0.0, 1.0, 0.0, dt, //
        0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    );
    // White acceleration, 0.5 m/s² per axis.
    let (a, b, c) = (dt.powi(3) / 3.0, dt * dt / 2.0, dt);
    let q = Matrix4::new(
        a, 0.0, b, 0.0, //
        0.0, a, 0.0, b, //
        b, 0.0, c, 0.0, //
        0.0, b, 0.0, c,
    ) * 0.25;
    let process = LinearProcess::new(phi, q);
    let sensor = RangeBearingRate {
        noise: Matrix3::from_diagonal(&Vector3::new(25.0, 1e-4, 0.04)),
    };

    let mut rng = common::rng(7);
    // A target west of the sensor heading south: its bearing crosses the
    // branch cut at ±π, so the bearing residual must wrap.
    let mut truth = Vector4::new(-700.0, 250.0, 3.0, -6.0);
    let lq = q.cholesky().expect("SPD").l();
    let lr = sensor.noise.map(f64::sqrt);
    let x0 = truth + Vector4::new(40.0, -30.0, 2.0, -1.0);
    let p0 = Matrix4::from_diagonal(&Vector4::new(2500.0, 2500.0, 25.0, 25.0));
    let mut seq = Ekf::new(x0, p0).expect("finite");
    seq.form_mut().set_sequential(true);
    let mut batch = seq.clone();
    batch.form_mut().set_sequential(false);
    let (mut min_bearing, mut max_bearing) = (0.0f64, 0.0f64);
    for k in 0..120 {
        truth = phi * truth + lq * noise::<4>(&mut rng);
        let mut z = sensor.predict(&truth) + lr * noise::<3>(&mut rng);
        z[1] =
            (z[1] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;

        seq.predict(&process, dt).expect("predict");
        batch.set_state(*seq.state()).expect("finite");
        batch.set_covariance(&seq.covariance()).expect("finite");
        let seq_report = seq.update_detailed(&sensor, &z).expect("update");
        let batch_report = batch.update_detailed(&sensor, &z).expect("update");
        assert_same(
            (&seq, &seq_report),
            (&batch, &batch_report),
            &format!("step {k}"),
        );
        min_bearing = min_bearing.min(z[1]);
        max_bearing = max_bearing.max(z[1]);
    }
    assert!(
        min_bearing < -3.0 && max_bearing > 3.0,
        "the bearing never wrapped"
    );
}

fn noise<const D: usize>(rng: &mut rand_chacha::ChaCha8Rng) -> SVector<f64, D> {
    SVector::from_fn(|_, _| rng.sample(StandardNormal))
}
