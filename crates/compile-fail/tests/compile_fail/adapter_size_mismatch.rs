// A filter whose adapter works on 2-D measurements, updated with a 1-D
// sensor through `update`: the error names the adapter's size and
// `update_with`.
use kestrel::adaptive::ChiSquareGate;
use kestrel::models::{ConstantVelocity2d, Selection};
use kestrel::nalgebra::{Matrix1, Matrix4, Vector1, Vector4};
use kestrel::Ekf;

fn main() {
    let cv = ConstantVelocity2d::new(0.1).unwrap();
    let gate = ChiSquareGate::<f64, 2>::new(0.01).unwrap();
    let mut ekf = Ekf::new(Vector4::zeros(), Matrix4::identity())
        .unwrap()
        .with_adapter(gate);
    ekf.predict(&cv, 1.0).unwrap();
    let range = Selection::<f64, 4, 1>::new([0], Matrix1::new(1.0)).unwrap();
    ekf.update(&range, &Vector1::new(1.0)).unwrap();
}
