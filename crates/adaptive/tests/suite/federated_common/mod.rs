//! The linear scenario of the federated tests: a constant-velocity target in
//! the plane, state (px, py, vx, vy), sampled every second and seen by three
//! sensors: A (position), B (x position and velocity, correlated noise) and
//! C (y position).
#![allow(dead_code)]

use kestrel_core::linalg::cholesky;
use kestrel_core::nalgebra::{
    Matrix1, Matrix1x4, Matrix2, Matrix2x4, Matrix3, Matrix3x4, Matrix4, SMatrix, SVector, Vector1,
    Vector2, Vector3, Vector4,
};
use kestrel_core::real::lit;
use kestrel_core::Real;
use kestrel_models::{LinearMeasurement, LinearProcess};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// White-acceleration noise density [m²/s³].
const ACCEL: f64 = 0.05;

pub fn process<T: Real>() -> LinearProcess<T, 4> {
    let phi = Matrix4::new(
        1.0, 0.0, 1.0, 0.0, //
        0.0, 1.0, 0.0, 1.0, //
        0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    );
    let (a, b, c) = (ACCEL / 3.0, ACCEL / 2.0, ACCEL);
    let q = Matrix4::new(
        a, 0.0, b, 0.0, //
        0.0, a, 0.0, b, //
        b, 0.0, c, 0.0, //
        0.0, b, 0.0, c,
    );
    LinearProcess::new(cast(&phi), cast(&q))
}

pub fn sensor_a<T: Real>() -> LinearMeasurement<T, 4, 2> {
    let h = Matrix2x4::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0);
    LinearMeasurement::new(cast(&h), cast(&Matrix2::new(4.0, 0.0, 0.0, 9.0)))
}

pub fn sensor_b<T: Real>() -> LinearMeasurement<T, 4, 3> {
    let h = Matrix3x4::new(
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    );
    let r = Matrix3::new(
        1.0, 0.1, 0.0, //
        0.1, 0.04, 0.0, //
        0.0, 0.0, 0.09,
    );
    LinearMeasurement::new(cast(&h), cast(&r))
}

pub fn sensor_c<T: Real>() -> LinearMeasurement<T, 4, 1> {
    let h = Matrix1x4::new(0.0, 1.0, 0.0, 0.0);
    LinearMeasurement::new(cast(&h), cast(&Matrix1::new(2.25)))
}

/// The initial estimate: 5 m and 1 m/s off the truth.
pub fn x0<T: Real>() -> Vector4<T> {
    cast(&Vector4::new(5.0, -5.0, 11.0, 4.0))
}

pub fn p0<T: Real>() -> Matrix4<T> {
    cast(&Matrix4::from_diagonal(&Vector4::new(
        100.0, 100.0, 4.0, 4.0,
    )))
}

/// One epoch of truth and measurements.
#[derive(Debug, Clone, Copy)]
pub struct Epoch {
    pub truth: Vector4<f64>,
    pub a: Vector2<f64>,
    pub b: Vector3<f64>,
    pub c: Vector1<f64>,
}

/// `epochs` epochs of the truth (starting at (0, 0, 10, 5)) and the three
/// sensors' measurements with their noise, from seed `seed`.
pub fn simulate(epochs: usize, seed: u64) -> Vec<Epoch> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let model = process::<f64>();
    let sq = cholesky(&model.noise).unwrap();
    let (a, b, c) = (sensor_a::<f64>(), sensor_b::<f64>(), sensor_c::<f64>());
    let mut truth = Vector4::new(0.0, 0.0, 10.0, 5.0);
    (0..epochs)
        .map(|_| {
            truth = model.transition * truth + sq * normal::<4>(&mut rng);
            Epoch {
                truth,
                a: a.matrix * truth + cholesky(&a.noise).unwrap() * normal(&mut rng),
                b: b.matrix * truth + cholesky(&b.noise).unwrap() * normal(&mut rng),
                c: c.matrix * truth + cholesky(&c.noise).unwrap() * normal(&mut rng),
            }
        })
        .collect()
}

fn normal<const D: usize>(rng: &mut ChaCha8Rng) -> SVector<f64, D> {
    SVector::from_fn(|_, _| rng.sample(StandardNormal))
}

/// An `f64` matrix in `T`.
pub fn cast<T: Real, const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> SMatrix<T, R, C> {
    m.map(lit)
}

/// Whether `p` has a Cholesky factor (is positive definite).
pub fn is_pd<T: Real, const N: usize>(p: &SMatrix<T, N, N>) -> bool {
    cholesky(p).is_ok()
}
