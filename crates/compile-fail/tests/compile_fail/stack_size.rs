// A Stack of 2 + 1 states used in a 4-state filter.
use kestrel::models::{RandomWalk, Stack};
use kestrel::nalgebra::{Matrix4, Vector4};
use kestrel::Ekf;

fn main() {
    let model = Stack::<_, _, 2, 1>::new(
        RandomWalk::<f64, 2>::uniform(1.0).unwrap(),
        RandomWalk::<f64, 1>::uniform(1.0).unwrap(),
    );
    let mut ekf = Ekf::new(Vector4::zeros(), Matrix4::identity()).unwrap();
    ekf.predict(&model, 1.0).unwrap();
}
