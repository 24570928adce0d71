//! A target turning at an unknown rate, seen by a range-bearing radar: a UKF, and an EKF
//! whose Jacobians come from automatic differentiation (checked against finite differences).
//! Run with `cargo run --example coordinated_turn`.
use kestrel::models::{check_measurement_jacobian as check_h, check_process_jacobian as check_f};
use kestrel::models::{AutoJacobian, CoordinatedTurn};
use kestrel::nalgebra::{Matrix2, Matrix5, Vector2, Vector5};
use kestrel::{real::lit, Ekf, MeasurementModel, ProcessModel, Real, Ukf};
/// Range [m] and bearing [rad] from the origin, written for any scalar (dual numbers too).
struct Radar;
impl<T: Real> MeasurementModel<T, 5, 2> for Radar {
    fn predict(&self, x: &Vector5<T>) -> Vector2<T> {
        Vector2::new(x[0].hypot(x[2]), x[2].atan2(x[0]))
    }
    fn noise(&self) -> Matrix2<T> {
        Matrix2::new(lit(25.0), T::zero(), T::zero(), lit(1e-5))
    }
}
fn main() -> Result<(), kestrel::FilterError> {
    let turn = AutoJacobian(CoordinatedTurn::new(0.05, 1e-6)?);
    let radar = AutoJacobian(Radar);
    let mut truth = Vector5::new(-800.0, 12.0, 400.0, 0.0, 0.03); // [x, ẋ, y, ẏ, ω]
    assert!(check_f(&turn, &truth, 1.0).passes(1e-7) && check_h(&radar, &truth).passes(1e-7));
    let x0 = Vector5::new(-780.0, 10.0, 420.0, 0.0, 0.0);
    let p0 = Matrix5::from_diagonal(&Vector5::new(400.0, 25.0, 400.0, 25.0, 1e-3));
    let (mut ukf, mut ekf) = (Ukf::new(x0, p0)?, Ekf::new(x0, p0)?);
    for k in 1..=120 {
        truth = turn.propagate(&truth, 1.0);
        let z = radar.predict(&truth) + Vector2::new(4.0, 0.002) * f64::from(k).sin(); // noise
        ukf.predict(&turn, 1.0)?;
        ekf.predict(&turn, 1.0)?;
        ukf.update(&radar, &z)?;
        ekf.update(&radar, &z)?;
    }
    let (u, e) = (ukf.state()[4], ekf.state()[4]);
    println!("turn rate {:.4} rad/s: UKF {u:.4}, EKF {e:.4}", truth[4]);
    Ok(())
}
