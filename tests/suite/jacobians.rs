//! Jacobians without hand derivation: forward-mode automatic
//! differentiation (`AutoJacobian`) equals the hand-derived Jacobians of the
//! coordinated-turn and range-bearing models to rounding, in `f64` and
//! `f32`; the finite-difference check accepts them and finds a wrong one;
//! an EKF step with automatic Jacobians allocates nothing.

use kestrel::models::{
    check_measurement_jacobian, check_process_jacobian, AutoJacobian, CoordinatedTurn, RangeBearing,
};
use kestrel::nalgebra::{Matrix2, Matrix5, SVector, Vector2, Vector5};
use kestrel::real::lit;
use kestrel::{Ekf, LinearizedMeasurement, LinearizedProcess, MeasurementModel, Real};
use kestrel_testkit::heap_calls;

/// Range and bearing from a sensor at (100, −50), for any scalar.
struct Radar;
impl<T: Real> MeasurementModel<T, 5, 2> for Radar {
    fn predict(&self, x: &Vector5<T>) -> Vector2<T> {
        let (dx, dy) = (x[0] - lit(100.0), x[2] + lit(50.0));
        Vector2::new(dx.hypot(dy), dy.atan2(dx))
    }
    fn noise(&self) -> Matrix2<T> {
        Matrix2::identity()
    }
}

fn states() -> [Vector5<f64>; 5] {
    [
        Vector5::new(-800.0, 12.0, 400.0, 0.0, 0.03),
        Vector5::new(10.0, -3.0, 7.0, 2.0, 0.0),
        Vector5::new(1e4, 250.0, -3e3, 120.0, 1e-6),
        Vector5::new(0.0, 1.0, 0.0, 1.0, -0.7),
        Vector5::new(350.0, 0.0, -20.0, -30.0, 2.0),
    ]
}

#[test]
fn automatic_equals_hand_derived_coordinated_turn() {
    let ct = CoordinatedTurn::new(0.1, 1e-4).unwrap();
    for x in states() {
        for dt in [0.01, 1.0, 5.0] {
            let hand = ct.transition(&x, dt);
            let auto = AutoJacobian(ct).transition(&x, dt);
            let scale = hand.norm();
            assert!((hand - auto).norm() <= 1e-14 * scale, "{hand}{auto}");
        }
    }
    // f32 through the same code.
    let x = Vector5::new(-800.0_f32, 12.0, 400.0, 0.0, 0.03);
    let (hand, auto) = (ct.transition(&x, 1.0), AutoJacobian(ct).transition(&x, 1.0));
    assert!((hand - auto).norm() <= 1e-5 * hand.norm(), "{hand}{auto}");
}

#[test]
fn automatic_equals_hand_derived_range_bearing() {
    let mut rb = RangeBearing::<f64, 5>::new(0, 2, Matrix2::identity()).unwrap();
    rb.sensor = Vector2::new(100.0, -50.0);
    for x in states() {
        let (hand, auto) = (rb.jacobian(&x), AutoJacobian(Radar).jacobian(&x));
        assert!(
            (hand - auto).norm() <= 1e-15 * hand.norm().max(1.0),
            "{hand}{auto}"
        );
        assert!(check_measurement_jacobian(&AutoJacobian(Radar), &x).passes(1e-7));
        assert!(
            check_process_jacobian(&CoordinatedTurn::new(0.1, 0.0).unwrap(), &x, 1.0).passes(1e-7)
        );
    }
}

/// A Jacobian with one wrong entry is found, at that entry.
#[test]
fn the_check_finds_a_wrong_jacobian() {
    struct Wrong(CoordinatedTurn);
    impl kestrel::ProcessModel<f64, 5> for Wrong {
        fn propagate(&self, x: &Vector5<f64>, dt: f64) -> Vector5<f64> {
            self.0.propagate(x, dt)
        }
        fn noise(&self, x: &Vector5<f64>, dt: f64) -> Matrix5<f64> {
            self.0.noise(x, dt)
        }
    }
    impl LinearizedProcess<f64, 5> for Wrong {
        fn transition(&self, x: &Vector5<f64>, dt: f64) -> Matrix5<f64> {
            let mut phi = self.0.transition(x, dt);
            phi[(2, 4)] = -phi[(2, 4)]; // a sign slip in ∂y/∂ω
            phi
        }
    }
    let x = states()[0];
    let check = check_process_jacobian(&Wrong(CoordinatedTurn::new(0.1, 0.0).unwrap()), &x, 1.0);
    assert!(!check.passes(1e-3));
    assert_eq!((check.row, check.col), (2, 4));
}

#[test]
fn an_ekf_step_with_automatic_jacobians_does_not_allocate() {
    let turn = AutoJacobian(CoordinatedTurn::new(0.05, 1e-6).unwrap());
    let radar = AutoJacobian(Radar);
    let x0 = states()[0];
    let mut ekf = Ekf::new(x0, Matrix5::identity() * 10.0).unwrap();
    let z = Vector2::new(900.0, 2.6);
    let (result, calls) = heap_calls(|| {
        for _ in 0..10 {
            ekf.predict(&turn, 1.0)?;
            ekf.update(&radar, &z)?;
        }
        Ok::<SVector<f64, 5>, kestrel::FilterError>(*ekf.state())
    });
    assert!(result.unwrap().iter().all(|v| v.is_finite()));
    assert_eq!(calls, 0);
}
