//! A planar constant-velocity target, state `(x, y, vx, vy)`, `dt = 1`,
//! white-acceleration process noise `Q = q [I/3 I/2; I/2 I]`, observed in
//! position (`H = [I 0]`), and seeded measurement streams for it.

use kestrel_core::nalgebra::{Matrix2, Matrix2x4, Matrix4, SVector, Vector2, Vector4};
use kestrel_core::Real;
use kestrel_models::{LinearMeasurement, LinearProcess};
use rand::RngExt;

use super::{normal, rng, to};

/// State dimension.
pub const N: usize = 4;
/// Measurement dimension.
pub const M: usize = 2;

/// `Φ = [I I; 0 I]`.
pub fn phi() -> Matrix4<f64> {
    let mut phi = Matrix4::identity();
    phi[(0, 2)] = 1.0;
    phi[(1, 3)] = 1.0;
    phi
}

/// `Q = q [I/3 I/2; I/2 I]`.
pub fn q(q: f64) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    for i in 0..2 {
        m[(i, i)] = q / 3.0;
        m[(i, i + 2)] = q / 2.0;
        m[(i + 2, i)] = q / 2.0;
        m[(i + 2, i + 2)] = q;
    }
    m
}

/// `H = [I 0]`.
pub fn h() -> Matrix2x4<f64> {
    Matrix2x4::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0)
}

/// The process model in precision `T`.
pub fn process<T: Real>(q_level: f64) -> LinearProcess<T, N> {
    LinearProcess::new(phi().map(to), q(q_level).map(to))
}

/// The position sensor with noise `r` in precision `T`.
pub fn sensor<T: Real>(r: &Matrix2<f64>) -> LinearMeasurement<T, N, M> {
    LinearMeasurement::new(h().map(to), r.map(to))
}

/// The initial estimate: the origin, at rest.
pub fn x0<T: Real>() -> SVector<T, N> {
    SVector::zeros()
}

/// The initial covariance `diag(10, 10, 1, 1)`.
pub fn p0<T: Real>() -> Matrix4<T> {
    Matrix4::from_diagonal(&Vector4::new(10.0, 10.0, 1.0, 1.0)).map(to)
}

/// How to draw a stream.
#[derive(Debug, Clone, Copy)]
pub struct Spec {
    /// Generator seed.
    pub seed: u64,
    /// Number of measurements.
    pub steps: usize,
    /// Process noise level `q` (truth and model alike).
    pub q: f64,
    /// The true measurement noise covariance.
    pub r: Matrix2<f64>,
    /// Probability that a measurement is an outlier.
    pub outlier_rate: f64,
    /// An outlier adds `± size · σᵢ` to each component `i` (random signs),
    /// with `σᵢ² = Rᵢᵢ`.
    pub outlier_size: f64,
    /// An unmodelled jump of the true state by the vector, at this step.
    pub jump: Option<(usize, Vector4<f64>)>,
}

impl Spec {
    /// `steps` outlier-free measurements with noise `r`, `q = 0.01`.
    pub fn new(seed: u64, steps: usize, r: Matrix2<f64>) -> Self {
        Self {
            seed,
            steps,
            q: 0.01,
            r,
            outlier_rate: 0.0,
            outlier_size: 0.0,
            jump: None,
        }
    }

    /// The same with outliers.
    pub fn with_outliers(mut self, rate: f64, size: f64) -> Self {
        self.outlier_rate = rate;
        self.outlier_size = size;
        self
    }

    /// The same with a jump of the true state.
    pub fn with_jump(mut self, step: usize, by: Vector4<f64>) -> Self {
        self.jump = Some((step, by));
        self
    }
}

/// A simulated truth and its measurements.
#[derive(Debug, Clone)]
pub struct Stream {
    /// The process noise level it was drawn with.
    pub q: f64,
    /// The true state after each step.
    pub truth: Vec<Vector4<f64>>,
    /// The measurements (with any outliers).
    pub z: Vec<Vector2<f64>>,
    /// The same measurements without the outliers.
    pub clean: Vec<Vector2<f64>>,
    /// Which measurements are outliers.
    pub outlier: Vec<bool>,
}

impl Stream {
    /// The same truth, measured without outliers.
    pub fn without_outliers(&self) -> Self {
        Self {
            z: self.clean.clone(),
            outlier: vec![false; self.z.len()],
            ..self.clone()
        }
    }
}

/// Draws a stream: the truth starts from `N(x0, P0)` and follows the model.
pub fn stream(spec: &Spec) -> Stream {
    let mut rng = rng(spec.seed);
    let lq = q(spec.q).cholesky().expect("SPD").l();
    let lr = spec.r.cholesky().expect("SPD").l();
    let lp = p0::<f64>().cholesky().expect("SPD").l();
    let sigma = spec.r.diagonal().map(f64::sqrt);
    let mut x = lp * normal::<N>(&mut rng);
    let mut out = Stream {
        q: spec.q,
        truth: Vec::with_capacity(spec.steps),
        z: Vec::with_capacity(spec.steps),
        clean: Vec::with_capacity(spec.steps),
        outlier: Vec::with_capacity(spec.steps),
    };
    for k in 0..spec.steps {
        x = phi() * x + lq * normal::<N>(&mut rng);
        if let Some((at, by)) = spec.jump
            && at == k
        {
            x += by;
        }
        let clean = h() * x + lr * normal::<M>(&mut rng);
        let is_outlier = spec.outlier_rate > 0.0 && rng.random_bool(spec.outlier_rate);
        let mut z = clean;
        if is_outlier {
            for i in 0..M {
                let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                z[i] += sign * spec.outlier_size * sigma[i];
            }
        }
        out.truth.push(x);
        out.z.push(z);
        out.clean.push(clean);
        out.outlier.push(is_outlier);
    }
    out
}
