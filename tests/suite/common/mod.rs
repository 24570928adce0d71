//! Helpers shared by the integration tests: seeded random stable linear
//! models, matrix checks, and a dispatch from run-time sizes to
//! monomorphised runners.
#![allow(dead_code)]

use kestrel::models::{LinearMeasurement, LinearProcess};
use kestrel::nalgebra::{Matrix2, Matrix2x4, Matrix4, SMatrix, SVector};
use kestrel::Real;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// A deterministic generator for `seed`.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A matrix of independent standard normal entries.
pub fn gaussian<const R: usize, const C: usize>(rng: &mut ChaCha8Rng) -> SMatrix<f64, R, C> {
    SMatrix::from_fn(|_, _| rng.sample(StandardNormal))
}

/// `10^u` with `u` uniform in `[log10 lo, log10 hi]`.
pub fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    10f64.powf(rng.random_range(lo.log10()..=hi.log10()))
}

/// A random orthogonal matrix (Gram–Schmidt, applied twice for accuracy, on a
/// Gaussian matrix).
pub fn orthogonal<const N: usize>(rng: &mut ChaCha8Rng) -> SMatrix<f64, N, N> {
    let mut q = gaussian::<N, N>(rng);
    for j in 0..N {
        for _ in 0..2 {
            for i in 0..j {
                let proj = q.column(i).dot(&q.column(j));
                let qi = q.column(i).into_owned();
                q.column_mut(j).axpy(-proj, &qi, 1.0);
            }
        }
        let norm = q.column(j).norm();
        q.column_mut(j).unscale_mut(norm);
    }
    q
}

/// A symmetric positive-definite matrix with eigenvalues log-uniform in
/// `[lo, hi]` and random eigenvectors (condition number at most `hi / lo`).
pub fn spd<const N: usize>(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> SMatrix<f64, N, N> {
    let u = orthogonal::<N>(rng);
    let d = SVector::<f64, N>::from_fn(|_, _| log_uniform(rng, lo, hi));
    symmetrize(u * SMatrix::from_diagonal(&d) * u.transpose())
}

/// A diagonal positive-definite matrix with entries log-uniform in `[lo, hi]`.
pub fn diagonal_spd<const N: usize>(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> SMatrix<f64, N, N> {
    SMatrix::from_diagonal(&SVector::from_fn(|_, _| log_uniform(rng, lo, hi)))
}

/// A stable, non-normal transition matrix `Φ = V B V⁻¹`: `B` is block
/// diagonal with damped rotations (`r [cos θ, sin θ; −sin θ, cos θ]`) and a
/// real eigenvalue for odd `N`, all of modulus `r ∈ [0.3, 0.98]`; `V = U Σ Wᵀ`
/// with singular values in `[0.5, 2]`, so `V⁻¹ = W Σ⁻¹ Uᵀ` is exact and the
/// spectral radius is the largest `r` by construction.
pub fn stable_transition<const N: usize>(rng: &mut ChaCha8Rng) -> SMatrix<f64, N, N> {
    let mut b = SMatrix::<f64, N, N>::zeros();
    let mut i = 0;
    while i < N {
        let r = rng.random_range(0.3..0.98);
        if i + 1 < N {
            let theta: f64 = rng.random_range(0.0..std::f64::consts::PI);
            let (s, c) = theta.sin_cos();
            b[(i, i)] = r * c;
            b[(i, i + 1)] = r * s;
            b[(i + 1, i)] = -r * s;
            b[(i + 1, i + 1)] = r * c;
            i += 2;
        } else {
            b[(i, i)] = if rng.random_bool(0.5) { r } else { -r };
            i += 1;
        }
    }
    let u = orthogonal::<N>(rng);
    let w = orthogonal::<N>(rng);
    let sigma = SVector::<f64, N>::from_fn(|_, _| rng.random_range(0.5..2.0));
    let v = u * SMatrix::from_diagonal(&sigma) * w.transpose();
    let v_inv = w * SMatrix::from_diagonal(&sigma.map(|s| 1.0 / s)) * u.transpose();
    v * b * v_inv
}

/// An upper bound on the spectral radius: `‖A^k‖_F^(1/k)` for `k = 2¹⁰`
/// (Gelfand's formula; any submultiplicative norm bounds `ρ(A)^k`).
pub fn spectral_radius_bound<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    // Repeated squaring with renormalisation: track log ‖A^k‖ without overflow.
    let mut power = *a;
    let mut log_scale = 0.0;
    for _ in 0..10 {
        power = power * power;
        log_scale *= 2.0;
        let norm = power.norm();
        power /= norm;
        log_scale += norm.ln();
    }
    (log_scale / 1024.0).exp()
}

/// `(A + Aᵀ) / 2`.
pub fn symmetrize<const N: usize>(a: SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    (a + a.transpose()) * 0.5
}

/// A random stable linear system with a simulated measurement record.
pub struct LinearCase<const N: usize, const M: usize> {
    /// `Φ` (spectral radius < 1) and `Q` (eigenvalues in `[10⁻², 1]`).
    pub process: LinearProcess<f64, N>,
    /// Gaussian `H` and `R` (eigenvalues in `[10⁻², 1]`, diagonal if asked).
    pub measurement: LinearMeasurement<f64, N, M>,
    /// Initial estimate.
    pub x0: SVector<f64, N>,
    /// Initial covariance (eigenvalues in `[10⁻¹, 10]`).
    pub p0: SMatrix<f64, N, N>,
    /// Measurements of a truth trajectory simulated with the model's noises.
    pub measurements: Vec<SVector<f64, M>>,
}

/// A random stable linear case with `steps` measurements.
pub fn linear_case<const N: usize, const M: usize>(
    seed: u64,
    steps: usize,
    diagonal_r: bool,
) -> LinearCase<N, M> {
    let mut rng = rng(seed);
    let phi = stable_transition::<N>(&mut rng);
    let q = spd::<N>(&mut rng, 1e-2, 1.0);
    let h = gaussian::<M, N>(&mut rng);
    let r = if diagonal_r {
        diagonal_spd::<M>(&mut rng, 1e-2, 1.0)
    } else {
        spd::<M>(&mut rng, 1e-2, 1.0)
    };
    let p0 = spd::<N>(&mut rng, 1e-1, 10.0);
    let x0 = gaussian::<N, 1>(&mut rng) * 3.0;

    let chol = |a: &SMatrix<f64, N, N>| a.cholesky().expect("SPD by construction").l();
    let (lq, lp) = (chol(&q), chol(&p0));
    let lr = r.cholesky().expect("SPD by construction").l();
    let mut truth = x0 + lp * gaussian::<N, 1>(&mut rng);
    let mut measurements = Vec::with_capacity(steps);
    for _ in 0..steps {
        truth = phi * truth + lq * gaussian::<N, 1>(&mut rng);
        measurements.push(h * truth + lr * gaussian::<M, 1>(&mut rng));
    }
    LinearCase {
        process: LinearProcess::new(phi, q),
        measurement: LinearMeasurement::new(h, r),
        x0,
        p0,
        measurements,
    }
}

/// `‖a − b‖_F / ‖b‖_F`.
pub fn relative_difference<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
) -> f64 {
    (a - b).norm() / b.norm()
}

/// `‖Δx‖ / (‖x‖ + √‖P‖_F)`: a state difference relative to the size of the
/// reference state and of its uncertainty (a state near zero still has a
/// meaningful scale).
pub fn state_difference<const N: usize>(
    x: &SVector<f64, N>,
    reference: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
) -> f64 {
    (x - reference).norm() / (reference.norm() + p.norm().sqrt())
}

/// `‖P − Pᵀ‖_F / ‖P‖_F`.
pub fn asymmetry<const N: usize>(p: &SMatrix<f64, N, N>) -> f64 {
    (p - p.transpose()).norm() / p.norm()
}

/// The eigenvalues of the symmetric part of `p`, ascending, by cyclic Jacobi
/// rotations (accurate to a few ulps of `‖P‖`, independent of the code under
/// test).
pub fn eigenvalues<const N: usize>(p: &SMatrix<f64, N, N>) -> SVector<f64, N> {
    let mut a = symmetrize(*p);
    for _sweep in 0..64 {
        let off: f64 = (0..N)
            .flat_map(|j| (0..j).map(move |i| (i, j)))
            .map(|(i, j)| a[(i, j)] * a[(i, j)])
            .sum();
        if off <= (f64::EPSILON * a.norm()).powi(2) {
            break;
        }
        for q in 1..N {
            for r in 0..q {
                let apq = a[(r, q)];
                if apq == 0.0 {
                    continue;
                }
                // Rotation that zeroes a[r, q] (Golub & Van Loan, sym.schur2).
                let tau = (a[(q, q)] - a[(r, r)]) / (2.0 * apq);
                let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
                let t = if tau == 0.0 { 1.0 } else { t };
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = t * c;
                for k in 0..N {
                    let (akr, akq) = (a[(k, r)], a[(k, q)]);
                    a[(k, r)] = c * akr - s * akq;
                    a[(k, q)] = s * akr + c * akq;
                }
                for k in 0..N {
                    let (ark, aqk) = (a[(r, k)], a[(q, k)]);
                    a[(r, k)] = c * ark - s * aqk;
                    a[(q, k)] = s * ark + c * aqk;
                }
            }
        }
    }
    let mut d: [f64; N] = core::array::from_fn(|i| a[(i, i)]);
    d.sort_by(f64::total_cmp);
    SVector::from(d)
}

/// The smallest eigenvalue of the symmetric part of `p`.
pub fn min_eigenvalue<const N: usize>(p: &SMatrix<f64, N, N>) -> f64 {
    eigenvalues(p)[0]
}

/// Whether an independent Cholesky factorisation (nalgebra's) of `p` succeeds.
pub fn cholesky_succeeds<const N: usize>(p: &SMatrix<f64, N, N>) -> bool {
    p.cholesky().is_some()
}

/// The `(N, M)` pairs the size dispatch knows, fed to a callback macro rule.
/// Every `N` from 2 to 24 appears; `M ≤ min(N, 6)` varies along the list.
#[allow(unused_macros)]
macro_rules! size_table {
    (@with $($callback:tt)*) => {
        $crate::common::size_table!($($callback)* [
            (2, 1) (2, 2) (3, 3) (4, 1) (5, 2) (6, 6) (7, 3) (8, 4) (9, 5)
            (10, 1) (11, 6) (12, 2) (13, 3) (14, 4) (15, 5) (16, 6) (17, 1)
            (18, 2) (19, 3) (20, 4) (21, 5) (22, 6) (23, 1) (24, 3) (24, 6)
        ])
    };
    (@list [$(($n:literal, $m:literal))*]) => {
        &[$(($n, $m)),*]
    };
    (@match $index:tt $run:ident $args:tt [$(($n:literal, $m:literal))*]) => {
        match $index {
            $(($n, $m) => $run::<$n, $m> $args,)*
            other => panic!("size {other:?} is not in the size table"),
        }
    };
}
#[allow(unused_imports)]
pub(crate) use size_table;

/// The `(N, M)` pairs [`dispatch`] accepts.
pub const SIZES: &[(usize, usize)] = size_table!(@with @list);

/// Calls `run::<N, M>(args…)` for a run-time size `(n, m)` from [`SIZES`].
#[allow(unused_macros)]
macro_rules! dispatch {
    ($size:expr, $run:ident ($($arg:expr),* $(,)?)) => {
        $crate::common::size_table!(@with @match $size $run ($($arg),*))
    };
}
#[allow(unused_imports)]
pub(crate) use dispatch;

/// Constant velocity in two axes (state: position x, y, velocity x, y;
/// Δt = 0.1 s, `Q = 0.01 I`) observed in position with noise `r`.
pub fn constant_velocity<T: Real>(
    r: Matrix2<f64>,
) -> (LinearProcess<T, 4>, LinearMeasurement<T, 4, 2>) {
    let phi = Matrix4::new(
        1.0, 0.0, 0.1, 0.0, //
        0.0, 1.0, 0.0, 0.1, //
        0.0, 0.0, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    );
    let h = Matrix2x4::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0);
    (
        LinearProcess::new(phi.cast(), (Matrix4::identity() * 0.01).cast()),
        LinearMeasurement::new(h.cast(), r.cast()),
    )
}

/// A filter of some form, built from `x0` and `p0` (as [`batch_ekf`],
/// [`ukf`] and [`srukf`] build them), for tests run on every form.
#[allow(dead_code)]
pub type Make<F, const N: usize> =
    fn(SVector<f64, N>, SMatrix<f64, N, N>) -> kestrel::Filter<f64, N, F>;

/// A UKF on `x0` and `p0`.
#[allow(dead_code)]
pub fn ukf<const N: usize>(
    x0: SVector<f64, N>,
    p0: SMatrix<f64, N, N>,
) -> kestrel::Filter<f64, N, kestrel::form::UnscentedForm<f64, N>> {
    kestrel::Ukf::new(x0, p0).expect("finite")
}

/// An SR-UKF on `x0` and `p0`.
#[allow(dead_code)]
pub fn srukf<const N: usize>(
    x0: SVector<f64, N>,
    p0: SMatrix<f64, N, N>,
) -> kestrel::Filter<f64, N, kestrel::form::SquareRootForm<f64, N>> {
    kestrel::SrUkf::new(x0, p0).expect("finite")
}

/// An EKF on `x0` and `p0` with sequential updates off, so that a dense or
/// diagonal `R` takes the batch update.
#[allow(dead_code)]
pub fn batch_ekf<const N: usize>(
    x0: SVector<f64, N>,
    p0: SMatrix<f64, N, N>,
) -> kestrel::Filter<f64, N, kestrel::form::CovarianceForm<f64, N>> {
    let mut f = kestrel::Ekf::new(x0, p0).expect("finite");
    f.form_mut().set_sequential(false);
    f
}
