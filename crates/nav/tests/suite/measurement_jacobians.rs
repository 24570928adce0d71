//! The measurement models' `H` against hand-computed matrices and against
//! central differences of the INS-minus-sensor difference, obtained by
//! perturbing a true navigation state per the error definitions
//! (`C̃ = exp(−[φ×]) C`, `ṽ = v + δv`, position displaced by `δr`,
//! `ω̃ = ω + b_g`, `k̂ = k − δk`) and rebuilding the measurement.

use kestrel_core::MeasurementModel;
use kestrel_nav::engine::{Ins15, Ins18};
use kestrel_nav::measurement::{
    AttitudeFix, ErrorLayout, ErrorMeasurement, GnssAntenna, GnssFix, InsContext, Odometer,
    OdometerReading,
};
use kestrel_nav::nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess};
use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavError, NavState};

fn truth() -> NavState {
    NavState::new(
        100.0,
        Geodetic::from_degrees(34.0, 120.0, 200.0),
        Vector3::new(12.0, -15.0, 0.4),
        Euler::from_degrees(2.0, -3.0, 130.0),
    )
}

fn omega() -> Vector3<f64> {
    Vector3::new(0.02, -0.03, 0.15)
}

/// The INS context of the truth perturbed by the first 9 components of
/// `dx` and a gyro error `dbg`.
fn perturbed<const N: usize>(
    earth: &Ellipsoid,
    dx: &SVector<f64, N>,
    dbg: Vector3<f64>,
) -> InsContext {
    let err = NavError::from_error_state(dx);
    let computed = err.apply(earth, &truth());
    InsContext::new(*earth, computed, omega() + dbg)
}

/// The gyro error of `dx` under layout `L` (sum of its blocks).
fn gyro_error<const N: usize, L: ErrorLayout<N>>(dx: &SVector<f64, N>) -> Vector3<f64> {
    L::GYRO_BIAS
        .iter()
        .map(|&b| Vector3::new(dx[b], dx[b + 1], dx[b + 2]))
        .sum()
}

/// Step of the central difference for state `i` of layout `L`.
fn step<const N: usize, L: ErrorLayout<N>>(i: usize) -> f64 {
    match i {
        0..=2 => 1e-4,
        3..=5 => 1e-3,
        6..=8 => 0.5,
        _ if Some(i) == L::ODOMETER_SCALE => 1e-5,
        _ => 1e-5,
    }
}

/// Central differences of `z(dx)` at zero.
fn numeric<const N: usize, const M: usize, L: ErrorLayout<N>>(
    z: impl Fn(&SVector<f64, N>) -> SVector<f64, M>,
) -> SMatrix<f64, M, N> {
    let mut h = SMatrix::<f64, M, N>::zeros();
    for i in 0..N {
        let e = step::<N, L>(i);
        let mut dx = SVector::<f64, N>::zeros();
        dx[i] = e;
        let plus = z(&dx);
        dx[i] = -e;
        let minus = z(&dx);
        h.set_column(i, &((plus - minus) / (2.0 * e)));
    }
    h
}

/// Largest |difference| of two matrices, with the location.
fn worst<const M: usize, const N: usize>(
    a: &SMatrix<f64, M, N>,
    b: &SMatrix<f64, M, N>,
) -> (f64, usize, usize) {
    let mut w = (0.0, 0, 0);
    for i in 0..M {
        for j in 0..N {
            let d = (a[(i, j)] - b[(i, j)]).abs();
            if d > w.0 {
                w = (d, i, j);
            }
        }
    }
    w
}

fn assert_close<const M: usize, const N: usize>(
    analytic: &SMatrix<f64, M, N>,
    numeric: &SMatrix<f64, M, N>,
    tol: f64,
    what: &str,
) {
    let (d, i, j) = worst(analytic, numeric);
    assert!(
        d <= tol,
        "{what}: H[{i},{j}] = {} but the difference quotient is {} (|Δ| = {d:e} > {tol:e})",
        analytic[(i, j)],
        numeric[(i, j)]
    );
}

fn lever() -> Vector3<f64> {
    Vector3::new(0.8, -0.3, -1.5)
}

/// A GNSS fix at the true antenna: position `r + C l`, velocity
/// `v + C (ω_eb × l)` with `ω_eb = ω_ib − Cᵀ ω_ie` (the rate of the body
/// with respect to the Earth).
fn fix(earth: &Ellipsoid) -> GnssFix {
    let t = truth();
    let cl = t.att * lever();
    let w_eb = omega() - t.att.inverse() * earth.earth_rate_ned(t.pos.lat);
    let v_ant = t.vel + t.att * w_eb.cross(&lever());
    GnssFix::new(t.time, earth.displace(&t.pos, &cl), v_ant)
        .with_std(Vector3::new(2.0, 2.0, 4.0), Vector3::new(0.05, 0.05, 0.1))
}

#[test]
fn lever_arm_h_by_hand() {
    // Level, heading east (C_b^n = R_z(90°)): body x → east, y → south.
    // No Earth rotation, so the velocity rows hold only the ω × l terms.
    let earth = Ellipsoid {
        omega_ie: 0.0,
        ..Ellipsoid::wgs84()
    };
    let nav = NavState::new(
        0.0,
        Geodetic::from_degrees(30.0, 114.0, 0.0),
        Vector3::zeros(),
        Euler::from_degrees(0.0, 0.0, 90.0),
    );
    let ins = InsContext::new(earth, nav, Vector3::new(0.0, 0.0, 0.1));
    let antenna = GnssAntenna::new(Vector3::new(1.0, 0.0, -2.0));
    let fix = GnssFix::new(0.0, nav.pos, Vector3::zeros());
    let m: ErrorMeasurement<f64, 15, 6> =
        antenna.position_velocity(&Ins15::new(ImuSpec::perfect()), &ins, &fix);
    let h = m.h();

    // C l = (0, 1, −2): [(C l)×] = [[0, 2, 1], [−2, 0, 0], [−1, 0, 0]].
    let h_r_phi = Matrix3::new(0.0, 2.0, 1.0, -2.0, 0.0, 0.0, -1.0, 0.0, 0.0);
    // ω × l = (0, 0.1, 0), C (ω × l) = (−0.1, 0, 0):
    // [(C(ω × l))×] = [[0, 0, 0], [0, 0, 0.1], [0, −0.1, 0]].
    let h_v_phi = Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.1, 0.0, -0.1, 0.0);
    // [l×] = [[0, 2, 0], [−2, 0, −1], [0, 1, 0]]; −C [l×] = [[−2, 0, −1], [0, −2, 0], [0, −1, 0]].
    let h_v_bg = Matrix3::new(-2.0, 0.0, -1.0, 0.0, -2.0, 0.0, 0.0, -1.0, 0.0);

    let mut expected = SMatrix::<f64, 6, 15>::zeros();
    expected.fixed_view_mut::<3, 3>(0, 0).copy_from(&h_r_phi);
    expected
        .fixed_view_mut::<3, 3>(0, 6)
        .copy_from(&Matrix3::identity());
    expected.fixed_view_mut::<3, 3>(3, 0).copy_from(&h_v_phi);
    expected
        .fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&Matrix3::identity());
    expected.fixed_view_mut::<3, 3>(3, 9).copy_from(&h_v_bg);
    assert_close(h, &expected, 1e-15, "hand-computed lever-arm H");

    // z: the INS antenna is 1 m east and 2 m up of the fix (at the IMU);
    // its velocity is C (ω × l) = 0.1 m/s south.
    let z = m.z();
    assert!(
        (z[0]).abs() < 1e-6 && (z[1] - 1.0).abs() < 1e-6 && (z[2] + 2.0).abs() < 1e-6,
        "{z}"
    );
    assert!((z[3] + 0.1).abs() < 1e-15 && z[4].abs() < 1e-15 && z[5].abs() < 1e-15);
    assert_eq!(m.predict(&SVector::zeros()), SVector::<f64, 6>::zeros());
}

#[test]
fn gnss_position_velocity_matches_differences_15_and_18() {
    let earth = Ellipsoid::wgs84();
    let fix = fix(&earth);
    let antenna = GnssAntenna::new(lever());

    let sys = Ins15::new(ImuSpec::perfect());
    let z = |dx: &SVector<f64, 15>| {
        let ins = perturbed(&earth, dx, gyro_error::<15, Ins15>(dx));
        antenna
            .position_velocity::<f64, 15, _>(&sys, &ins, &fix)
            .z()
    };
    let zero = z(&SVector::zeros());
    assert!(
        zero.norm() < 1e-6,
        "a fix at the true antenna gives z = 0: {zero}"
    );
    let analytic = *antenna
        .position_velocity::<f64, 15, _>(
            &sys,
            &perturbed(&earth, &SVector::<f64, 15>::zeros(), Vector3::zeros()),
            &fix,
        )
        .h();
    // Neglected: the NED frames at the fix and at the IMU differ by
    // |l| / R ≈ 3e-7 rad.
    assert_close(
        &analytic,
        &numeric::<15, 6, Ins15>(z),
        1e-6,
        "GNSS pos+vel, 15 states",
    );

    let sys = Ins18::new(ImuSpec::perfect());
    let z = |dx: &SVector<f64, 18>| {
        let ins = perturbed(&earth, dx, gyro_error::<18, Ins18>(dx));
        antenna
            .position_velocity::<f64, 18, _>(&sys, &ins, &fix)
            .z()
    };
    let analytic = *antenna
        .position_velocity::<f64, 18, _>(
            &sys,
            &perturbed(&earth, &SVector::<f64, 18>::zeros(), Vector3::zeros()),
            &fix,
        )
        .h();
    assert_close(
        &analytic,
        &numeric::<18, 6, Ins18>(z),
        1e-6,
        "GNSS pos+vel, 18 states",
    );
    // Both gyro blocks (constant and Markov drift) enter alike.
    assert_eq!(
        analytic.fixed_view::<3, 3>(3, 9),
        analytic.fixed_view::<3, 3>(3, 12)
    );
}

#[test]
fn gnss_position_matches_differences() {
    let earth = Ellipsoid::wgs84();
    let fix = fix(&earth);
    let antenna = GnssAntenna::new(lever());
    let sys = Ins15::new(ImuSpec::perfect());
    let z = |dx: &SVector<f64, 15>| {
        let ins = perturbed(&earth, dx, gyro_error::<15, Ins15>(dx));
        antenna.position::<f64, 15, _>(&sys, &ins, &fix).z()
    };
    let ins0 = perturbed(&earth, &SVector::<f64, 15>::zeros(), Vector3::zeros());
    let m = antenna.position::<f64, 15, _>(&sys, &ins0, &fix);
    // Neglected: the NED frames at the fix and at the IMU differ by
    // |l| / R ≈ 3e-7 rad.
    assert_close(m.h(), &numeric::<15, 3, Ins15>(z), 1e-6, "GNSS position");
    assert_eq!(m.noise_covariance()[(2, 2)], 16.0);
}

#[test]
fn attitude_velocity_position_matches_differences() {
    let earth = Ellipsoid::wgs84();
    let fix = fix(&earth);
    let att = AttitudeFix::new(0.0, truth().att, Vector3::repeat(1e-3));
    let antenna = GnssAntenna::new(lever());
    let sys = Ins18::new(ImuSpec::perfect());
    let z = |dx: &SVector<f64, 18>| {
        let ins = perturbed(&earth, dx, gyro_error::<18, Ins18>(dx));
        antenna
            .attitude_velocity_position::<f64, 18, _>(&sys, &ins, &att, &fix)
            .z()
    };
    assert!(z(&SVector::zeros()).norm() < 1e-6);
    let ins0 = perturbed(&earth, &SVector::<f64, 18>::zeros(), Vector3::zeros());
    let m = antenna.attitude_velocity_position::<f64, 18, _>(&sys, &ins0, &att, &fix);
    assert_close(
        m.h(),
        &numeric::<18, 9, Ins18>(z),
        1e-6,
        "attitude + velocity + position",
    );
    assert_eq!(m.noise_covariance()[(0, 0)], 1e-6);
    assert_eq!(m.noise_covariance()[(8, 8)], 16.0);
}

/// The odometer at its mounting: forward speed 1.3 % fast, true scale
/// error k = 0.013, estimate k̂ = k − δk.
#[test]
fn odometer_models_match_differences() {
    let earth = Ellipsoid::wgs84();
    let odo = Odometer::new(0.05, 0.1)
        .with_mounting(0.01, -0.02)
        .with_lever_arm(Vector3::new(-1.2, 0.4, 1.1));
    let sys = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
    let k = 0.013;
    // The true vehicle-frame velocity of the odometer point relative to
    // the Earth: C_b^v (Cᵀ v + ω_eb × l), ω_eb = ω_ib − Cᵀ ω_ie.
    let t = truth();
    let w_eb = omega() - t.att.inverse() * earth.earth_rate_ned(t.pos.lat);
    let v_wheel = odo.body_to_vehicle() * (t.att.inverse() * t.vel + w_eb.cross(&odo.lever_arm));
    let reading = OdometerReading::new(t.time, (1.0 + k) * v_wheel.x);

    let z3 = |dx: &SVector<f64, 16>| {
        let ins = perturbed(&earth, dx, gyro_error::<16, InsOdometer16>(dx));
        odo.forward_nhc::<f64, 16, _>(&sys, &ins, &reading, k - dx[15])
            .z()
    };
    let ins0 = perturbed(&earth, &SVector::<f64, 16>::zeros(), Vector3::zeros());
    let m3 = odo.forward_nhc::<f64, 16, _>(&sys, &ins0, &reading, k);
    let zero = m3.z();
    assert!(zero.x.abs() < 1e-12, "the corrected speed matches: {zero}");
    // The truth moves sideways in the vehicle frame: the constraint rows
    // show its lateral and vertical velocity.
    assert!((zero.y - v_wheel.y).abs() < 1e-12 && (zero.z - v_wheel.z).abs() < 1e-12);
    assert_close(
        m3.h(),
        &numeric::<16, 3, InsOdometer16>(z3),
        1e-7,
        "odometer + NHC",
    );

    let m1 = odo.forward::<f64, 16, _>(&sys, &ins0, &reading, k);
    let m2 = odo.nhc::<f64, 16, _>(&sys, &ins0);
    assert_eq!(m1.h().row(0), m3.h().row(0));
    assert_eq!(m2.h().row(0), m3.h().row(1));
    assert_eq!(m2.h().row(1), m3.h().row(2));
    assert_eq!(
        (m1.z()[0], m2.z()[0], m2.z()[1]),
        (m3.z()[0], m3.z()[1], m3.z()[2])
    );
    assert_eq!(m1.noise_covariance()[(0, 0)], 0.05 * 0.05);
    assert_eq!(m2.noise_covariance()[(1, 1)], 0.1 * 0.1);
    // The scale column: −ŝ / (1 + k̂) in the forward row only.
    let s_hat = reading.speed / (1.0 + k);
    assert!((m3.h()[(0, 15)] + s_hat / (1.0 + k)).abs() < 1e-12);
    assert_eq!(m3.h()[(1, 15)], 0.0);
}

/// Without an odometer scale state the forward row has no scale column.
#[test]
fn odometer_in_15_states_takes_the_scale_as_known() {
    let earth = Ellipsoid::wgs84();
    let odo = Odometer::new(0.05, 0.1);
    let ins0 = perturbed(&earth, &SVector::<f64, 15>::zeros(), Vector3::zeros());
    let sys = Ins15::new(ImuSpec::perfect());
    let z = |dx: &SVector<f64, 15>| {
        let ins = perturbed(&earth, dx, gyro_error::<15, Ins15>(dx));
        odo.forward_nhc::<f64, 15, _>(&sys, &ins, &OdometerReading::new(0.0, 20.0), 0.0)
            .z()
    };
    let m = odo.forward_nhc::<f64, 15, _>(&sys, &ins0, &OdometerReading::new(0.0, 20.0), 0.0);
    assert_close(
        m.h(),
        &numeric::<15, 3, Ins15>(z),
        1e-7,
        "odometer + NHC, 15 states",
    );
}

/// f32 filters get the same matrices, rounded.
#[test]
fn f32_models_round_the_f64_ones() {
    let earth = Ellipsoid::wgs84();
    let fix = fix(&earth);
    let ins0 = perturbed(&earth, &SVector::<f64, 15>::zeros(), Vector3::zeros());
    let sys = Ins15::new(ImuSpec::perfect());
    let a = GnssAntenna::new(lever());
    let m64 = a.position_velocity::<f64, 15, _>(&sys, &ins0, &fix);
    let m32 = a.position_velocity::<f32, 15, _>(&sys, &ins0, &fix);
    assert_eq!(m32.h(), &m64.h().map(|v| v as f32));
    assert_eq!(m32.z(), m64.z().map(|v| v as f32));
}
