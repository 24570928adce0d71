//! Attitude conversions: hand-computed values and round trips.

use kestrel_nav::nalgebra::{Matrix3, UnitQuaternion, Vector3};
use kestrel_nav::{
    attitude_error, correct_attitude, error_rotation, quaternion_to_rotation_vector,
    rotation_vector_to_quaternion, skew, Euler,
};
use proptest::prelude::*;

fn rx(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}
fn ry(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}
fn rz(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

#[test]
fn zyx_order_and_hand_values() {
    let e = Euler::new(0.3, -0.2, 1.1);
    let c = e.to_quaternion().to_rotation_matrix().into_inner();
    assert!((c - rz(1.1) * ry(-0.2) * rx(0.3)).norm() < 1e-15);
    assert!((e.to_dcm() - c).norm() < 1e-15);
    // Hand values, yaw 90° then pitch 30°: body forward = (0, cos 30°, −sin 30°).
    let c = Euler::from_degrees(0.0, 30.0, 90.0).to_dcm();
    assert!((c.column(0) - Vector3::new(0.0, 0.75f64.sqrt(), -0.5)).norm() < 1e-15);
    // Yaw 30°: q = [cos 15°, 0, 0, sin 15°].
    let q = Euler::from_degrees(0.0, 0.0, 30.0).to_quaternion();
    assert!((q.w - 0.965_925_826_289_068_3).abs() < 1e-15);
    assert!((q.k - 0.258_819_045_102_520_76).abs() < 1e-15);
    // Pitch 90° nose up maps body forward to up (−down).
    let q = Euler::from_degrees(0.0, 90.0, 0.0).to_quaternion();
    assert!((q * Vector3::x() - Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-15);
    // Roll 90° right wing down maps body right to down.
    let q = Euler::from_degrees(90.0, 0.0, 0.0).to_quaternion();
    assert!((q * Vector3::y() - Vector3::z()).norm() < 1e-15);
}

#[test]
fn rotation_vector_hand_values() {
    // 90° about down: q = [cos 45°, 0, 0, sin 45°].
    let q = rotation_vector_to_quaternion(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!((q.w - h).abs() < 1e-15 && (q.k - h).abs() < 1e-15);
    // Small angles use the series: compare with the closed form.
    for &n in &[1e-9, 1e-5, 1e-3, 0.05, 0.099, 0.1001, 0.5] {
        let phi = Vector3::new(0.6, -0.8, 0.0) * n;
        let q = rotation_vector_to_quaternion(&phi);
        let (s, c) = (0.5 * n).sin_cos();
        assert!((q.w - c).abs() < 2e-16, "w at {n}");
        assert!((q.i - 0.6 * s).abs() < 2e-16 && (q.j + 0.8 * s).abs() < 2e-16);
        let back = quaternion_to_rotation_vector(&q);
        assert!((back - phi).norm() < 1e-16 + 1e-15 * n, "back at {n}");
    }
    // Angle π maps to |φ| = π, never above.
    let q = UnitQuaternion::from_quaternion(kestrel_nav::nalgebra::Quaternion::new(
        -1e-17, 0.0, 1.0, 0.0,
    ));
    assert!((quaternion_to_rotation_vector(&q).norm() - std::f64::consts::PI).abs() < 1e-12);
}

#[test]
fn small_angle_error_rotation() {
    let truth = Euler::new(0.1, 0.2, -2.0).to_quaternion();
    let phi = Vector3::new(2e-4, -1e-4, 3e-4);
    let computed = correct_attitude(&truth, &(-phi));
    // C(computed) = (I − [φ×]) C(true) to first order: residual O(|φ|²).
    let c_c = computed.to_rotation_matrix().into_inner();
    let c_t = truth.to_rotation_matrix().into_inner();
    assert!((c_c - error_rotation(&phi) * c_t).norm() < 1e-7);
    assert!((attitude_error(&computed, &truth) - phi).norm() < 1e-16);
    assert_eq!(skew(&phi) * phi, Vector3::zeros());
}

#[test]
fn gimbal_lock_is_finite() {
    let e = Euler::from_quaternion(&Euler::from_degrees(10.0, 90.0, 20.0).to_quaternion());
    assert!(e.roll.is_finite() && e.yaw.is_finite());
    assert!((e.pitch - std::f64::consts::FRAC_PI_2).abs() < 1e-7);
}

proptest! {
    #[test]
    fn euler_quaternion_round_trip(
        roll in -3.1f64..3.1, pitch in -1.5f64..1.5, yaw in -3.1f64..3.1,
    ) {
        let e = Euler::new(roll, pitch, yaw);
        let q = e.to_quaternion();
        prop_assert!((q.norm() - 1.0).abs() < 1e-15);
        let back = Euler::from_quaternion(&q);
        prop_assert!((back.roll - roll).abs() < 1e-12);
        prop_assert!((back.pitch - pitch).abs() < 1e-12);
        prop_assert!((back.yaw - yaw).abs() < 1e-12);
        // Same rotation as the explicit product and the DCM route.
        let c = q.to_rotation_matrix().into_inner();
        prop_assert!((c - rz(yaw) * ry(pitch) * rx(roll)).norm() < 1e-14);
        prop_assert!((e.to_dcm() - c).norm() < 1e-14);
        let via_dcm = Euler::from_dcm(&c);
        prop_assert!((via_dcm.roll - roll).abs() < 1e-12);
        prop_assert!((via_dcm.pitch - pitch).abs() < 1e-12);
        prop_assert!((via_dcm.yaw - yaw).abs() < 1e-12);
    }

    #[test]
    fn rotation_vector_round_trip(x in -1.8f64..1.8, y in -1.8f64..1.8, z in -1.8f64..1.8) {
        let phi = Vector3::new(x, y, z);
        prop_assume!(phi.norm() < 3.1);
        let q = rotation_vector_to_quaternion(&phi);
        let reference = UnitQuaternion::from_scaled_axis(phi);
        prop_assert!(q.angle_to(&reference) < 1e-14);
        prop_assert!((quaternion_to_rotation_vector(&q) - phi).norm() < 1e-13);
    }
}
