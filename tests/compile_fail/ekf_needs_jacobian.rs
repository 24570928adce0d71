// A measurement model without a Jacobian in the covariance form.
use kestrel::nalgebra::{Matrix1, Matrix2, Vector1, Vector2};
use kestrel::{Ekf, MeasurementModel};

struct Range;
impl MeasurementModel<f64, 2, 1> for Range {
    fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> {
        Vector1::new(x.norm())
    }
    fn noise(&self) -> Matrix1<f64> {
        Matrix1::new(1.0)
    }
}

fn main() {
    let mut ekf = Ekf::new(Vector2::new(1.0, 1.0), Matrix2::identity()).unwrap();
    ekf.update(&Range, &Vector1::new(1.5)).unwrap();
}
