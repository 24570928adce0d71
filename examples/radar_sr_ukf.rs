//! Custom 2-D tracking: a constant-velocity target seen by a range-bearing
//! radar, square-root UKF. Run with `cargo run --example radar_sr_ukf`.
use kestrel::models::ConstantVelocity2d;
use kestrel::nalgebra::{Matrix2, Matrix4, Vector2, Vector4};
use kestrel::{MeasurementModel, ProcessModel, SrUkf};
/// Range [m] and bearing [rad] from a radar at the origin; state [x, ẋ, y, ẏ].
struct Radar;
impl MeasurementModel<f64, 4, 2> for Radar {
    fn predict(&self, x: &Vector4<f64>) -> Vector2<f64> {
        Vector2::new(x[0].hypot(x[2]), x[2].atan2(x[0]))
    }
    fn noise(&self) -> Matrix2<f64> {
        Matrix2::new(25.0, 0.0, 0.0, 0.005 * 0.005)
    }
    fn residual(&self, z: &Vector2<f64>, z_hat: &Vector2<f64>) -> Vector2<f64> {
        let d = z[1] - z_hat[1]; // take the bearing difference the short way round
        Vector2::new(z[0] - z_hat[0], d.sin().atan2(d.cos()))
    }
}
fn main() -> Result<(), kestrel::FilterError> {
    let motion = ConstantVelocity2d::new(0.1).unwrap(); // white acceleration, m²/s³
    let p0 = Matrix4::from_diagonal(&Vector4::new(400.0, 25.0, 400.0, 25.0));
    let mut filter = SrUkf::new(Vector4::new(-900.0, 0.0, 20.0, 0.0), p0)?;
    let mut truth = Vector4::new(-1000.0, 0.0, 300.0, -6.0); // crosses bearing ±π
    for k in 1..=100 {
        truth = motion.propagate(&truth, 1.0);
        let noise = Vector2::new(3.0 * f64::from(k).sin(), 0.002 * f64::from(k).cos());
        filter.predict(&motion, 1.0)?;
        let report = filter.update(&Radar, &(Radar.predict(&truth) + noise))?;
        let x = filter.state();
        if k % 20 == 0 {
            println!(
                "t={k:3} s  x=({:7.1}, {:6.1}) m  NIS={:.2}",
                x[0], x[2], report.nis
            );
        }
    }
    Ok(())
}
