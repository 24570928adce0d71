// A constant-velocity model of an odd state size.
use kestrel::models::ConstantVelocity;

fn main() {
    let _cv = ConstantVelocity::<f64, 3>::new(1.0);
}
