//! A dense, stable, seeded linear model `x⁺ = Φ x + w`, `z = H x + v`.

use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::real::lit;
use kestrel::Real;

use super::rng::SplitMix64;

/// Spectral radius the transition matrix is scaled to (at most).
const RADIUS: f64 = 0.95;

/// Every matrix a benchmark needs, all dense.
#[derive(Clone)]
pub struct Model<T: Real, const N: usize, const M: usize> {
    /// Transition `Φ`, spectral radius ≤ 0.95.
    pub phi: SMatrix<T, N, N>,
    /// Process noise `Q`, dense SPD.
    pub q: SMatrix<T, N, N>,
    /// Measurement matrix `H`, dense.
    pub h: SMatrix<T, M, N>,
    /// Measurement noise `R`, dense SPD.
    pub r: SMatrix<T, M, M>,
    /// The diagonal of `R` alone.
    // Not every benchmark times a diagonal `R`.
    #[allow(dead_code)]
    pub r_diag: SMatrix<T, M, M>,
    /// Initial covariance, dense SPD.
    pub p0: SMatrix<T, N, N>,
    /// Initial state.
    pub x0: SVector<T, N>,
    /// The measurement fed at every step: with a constant `z` and a stable
    /// `Φ` the filter converges to a fixed point, so millions of steps
    /// neither diverge nor underflow.
    pub z: SVector<T, M>,
}

fn random<const R: usize, const C: usize>(rng: &mut SplitMix64) -> SMatrix<f64, R, C> {
    SMatrix::from_fn(|_, _| rng.symmetric())
}

/// `scale (A Aᵀ / N + floor I)` for a random `A`: dense and well conditioned.
fn spd<const N: usize>(rng: &mut SplitMix64, scale: f64, floor: f64) -> SMatrix<f64, N, N> {
    let a = random::<N, N>(rng);
    let mut p = (a * a.transpose() / N as f64 + SMatrix::identity() * floor) * scale;
    p.fill_upper_triangle_with_lower_triangle();
    p
}

/// An upper bound of the spectral radius, `‖A^k‖_F^{1/k}` for `k = 2¹²`
/// (Gelfand's formula), by repeated squaring with renormalisation.
fn radius_bound<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    const SQUARINGS: i32 = 12;
    let mut b = *a;
    // A^(2^j) = exp(log_norm) · b with ‖b‖_F = 1.
    let mut log_norm = 0.0;
    for j in 0..=SQUARINGS {
        if j > 0 {
            b = b * b;
            log_norm *= 2.0;
        }
        let nb = b.norm();
        b /= nb;
        log_norm += nb.ln();
    }
    (log_norm / 2f64.powi(SQUARINGS)).exp()
}

impl<const N: usize, const M: usize> Model<f64, N, M> {
    /// The step benchmarks' model of size `N` (its seed depends on `N`
    /// alone, so every benchmark times the same model at a size).
    pub fn of_step_benchmarks() -> Self {
        Self::generate(0x6b65_7374_7265_6c00 + N as u64)
    }

    /// The model for seed `seed`.
    pub fn generate(seed: u64) -> Self {
        let mut rng = SplitMix64::new(seed);
        let a = random::<N, N>(&mut rng);
        let phi = a * (RADIUS / radius_bound(&a));
        let q = spd::<N>(&mut rng, 0.01, 0.1);
        let h = random::<M, N>(&mut rng);
        let r = spd::<M>(&mut rng, 0.1, 0.5);
        let r_diag = SMatrix::from_diagonal(&r.diagonal());
        let p0 = spd::<N>(&mut rng, 1.0, 0.1);
        let x0 = random::<N, 1>(&mut rng);
        let z = random::<M, 1>(&mut rng);
        Self {
            phi,
            q,
            h,
            r,
            r_diag,
            p0,
            x0,
            z,
        }
    }

    /// The same model in precision `T`.
    // Not every benchmark times `f32`.
    #[allow(dead_code)]
    pub fn to<T: Real>(&self) -> Model<T, N, M> {
        Model {
            phi: self.phi.map(lit),
            q: self.q.map(lit),
            h: self.h.map(lit),
            r: self.r.map(lit),
            r_diag: self.r_diag.map(lit),
            p0: self.p0.map(lit),
            x0: self.x0.map(lit),
            z: self.z.map(lit),
        }
    }
}
