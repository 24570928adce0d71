//! Discretisation of a continuous linear system with white noise.

use core::ops::{Add, Mul, Sub};

use kestrel_core::linalg::sandwich;
use kestrel_core::nalgebra::SMatrix;
use kestrel_core::Real;

use crate::lu::Lu;
use crate::pade::{column_sums, nan, scaled_pade, SquareAlgebra};

/// The `2N × 2N` block upper-triangular matrix `[[a, b], [0, c]]`, kept as its
/// three `N × N` blocks (a `2N` size cannot be written as a const generic).
/// Sums and products of such matrices stay block upper-triangular, so the
/// Padé evaluation runs on the blocks.
#[derive(Clone, Copy)]
struct BlockUpper<T: Real, const N: usize> {
    a: SMatrix<T, N, N>,
    b: SMatrix<T, N, N>,
    c: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> Add for BlockUpper<T, N> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            a: self.a + o.a,
            b: self.b + o.b,
            c: self.c + o.c,
        }
    }
}

impl<T: Real, const N: usize> Sub for BlockUpper<T, N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            a: self.a - o.a,
            b: self.b - o.b,
            c: self.c - o.c,
        }
    }
}

impl<T: Real, const N: usize> Mul for BlockUpper<T, N> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self {
            a: self.a * o.a,
            b: self.a * o.b + self.b * o.c,
            c: self.c * o.c,
        }
    }
}

impl<T: Real, const N: usize> Mul<T> for BlockUpper<T, N> {
    type Output = Self;
    fn mul(self, k: T) -> Self {
        Self {
            a: self.a * k,
            b: self.b * k,
            c: self.c * k,
        }
    }
}

impl<T: Real, const N: usize> SquareAlgebra<T> for BlockUpper<T, N> {
    fn identity() -> Self {
        Self {
            a: SMatrix::identity(),
            b: SMatrix::zeros(),
            c: SMatrix::identity(),
        }
    }
    fn norm1(&self) -> T {
        let (left, top, bottom) = (
            column_sums(&self.a),
            column_sums(&self.b),
            column_sums(&self.c),
        );
        (0..N).fold(T::zero(), |m, j| m.max(left[j]).max(top[j] + bottom[j]))
    }
    fn is_finite(&self) -> bool {
        self.a.is_finite() && self.b.is_finite() && self.c.is_finite()
    }
    /// Block back substitution: `X_c = c⁻¹ r_c`, `X_b = a⁻¹ (r_b − b X_c)`,
    /// `X_a = a⁻¹ r_a`.
    fn solve(&self, rhs: &Self) -> Option<Self> {
        let lu_a = Lu::new(&self.a)?;
        let xc = Lu::new(&self.c)?.solve(&rhs.c);
        let xb = lu_a.solve(&(rhs.b - self.b * xc));
        let xa = lu_a.solve(&rhs.a);
        Some(Self {
            a: xa,
            b: xb,
            c: xc,
        })
    }
}

/// Discretises `ẋ = F x + G w`, `E[w(t) w(s)ᵀ] = Q_c δ(t − s)`, over `dt`
/// (Van Loan 1978): returns `(Φ, Q_d)` with `Φ = e^{F dt}` and
/// `Q_d = ∫₀^dt e^{Fs} G Q_c Gᵀ e^{Fᵀs} ds` (symmetric).
///
/// Van Loan's matrix `M = [[−F, G Q_c Gᵀ], [0, Fᵀ]] dt` has
/// `e^M = [[·, Φ⁻¹ Q_d], [0, Φᵀ]]`. Its exponential is computed on the three
/// `N × N` blocks with the same scaled Padé approximant as [`expm`](crate::expm),
/// giving `Φ` and `Q_d = Φ (Φ⁻¹ Q_d)` for the step `h = dt / 2ˢ`. The `s`
/// squarings of `e^M` are then carried out on `(Φ, Q_d)` directly,
/// `Q(2h) = Φ(h) Q(h) Φ(h)ᵀ + Q(h)`, `Φ(2h) = Φ(h)²`, which is the same
/// product written without `e^{−F dt}`: that block overflows or swamps `Q_d`
/// when `F` has fast stable modes, while the doubling only adds positive
/// semi-definite terms. Since `e^M`'s upper-right block is linear in
/// `G Q_c Gᵀ`, that block is normalised to unit 1-norm and the result scaled
/// back, so a large or tiny noise level does not drive the scaling.
///
/// `dt` is expected to be non-negative. Cost: two `N × N` LU factorisations,
/// three times the products of [`expm`](crate::expm) (each block product is
/// three `N × N` products), plus three products per squaring. Allocation-free. Non-finite input gives NaN matrices.
///
/// ```
/// use kestrel_models::van_loan;
/// use kestrel_core::nalgebra::{Matrix1, Matrix2, Vector2};
/// // Constant velocity: white acceleration of density q drives the velocity.
/// let (dt, q) = (0.5_f64, 2.0);
/// let f = Matrix2::new(0.0, 1.0, 0.0, 0.0);
/// let (phi, qd) = van_loan(&f, &Vector2::new(0.0, 1.0), &Matrix1::new(q), dt);
/// assert!((phi - Matrix2::new(1.0, dt, 0.0, 1.0)).norm() < 1e-15);
/// let want = Matrix2::new(dt.powi(3) / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt) * q;
/// assert!((qd - want).norm() < 1e-15);
/// ```
pub fn van_loan<T: Real, const N: usize, const W: usize>(
    f: &SMatrix<T, N, N>,
    g: &SMatrix<T, N, W>,
    qc: &SMatrix<T, W, W>,
    dt: T,
) -> (SMatrix<T, N, N>, SMatrix<T, N, N>) {
    let nan = || {
        (
            SMatrix::from_element(nan::<T>()),
            SMatrix::from_element(nan::<T>()),
        )
    };
    let s = sandwich(g, &symmetrised(qc));
    let scale = s.norm1() * dt.abs();
    if !(s.is_finite() && scale.is_finite()) {
        return nan();
    }
    if scale == T::zero() {
        return (crate::expm(&(f * dt)), SMatrix::zeros());
    }
    let m = BlockUpper {
        a: -f * dt,
        b: s * (dt / scale),
        c: f.transpose() * dt,
    };
    let Some((e, squarings)) = scaled_pade(&m) else {
        return nan();
    };
    let mut phi = e.c.transpose();
    let mut q = symmetrised(&(phi * e.b)) * scale;
    for _ in 0..squarings {
        q += sandwich(&phi, &q);
        phi *= phi;
    }
    (phi, q)
}

/// `(A + Aᵀ) / 2`.
fn symmetrised<T: Real, const N: usize>(a: &SMatrix<T, N, N>) -> SMatrix<T, N, N> {
    (a + a.transpose()) * kestrel_core::real::lit::<T>(0.5)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix1, Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

    fn rel_err<const N: usize>(got: &SMatrix<f64, N, N>, want: &SMatrix<f64, N, N>) -> f64 {
        (got - want).norm() / want.norm()
    }

    #[test]
    fn constant_velocity_closed_form() {
        let f = Matrix2::new(0.0, 1.0, 0.0, 0.0);
        let g = Vector2::new(0.0, 1.0);
        for (dt, q) in [
            (1e-4_f64, 3.0),
            (0.1, 0.5),
            (1.0, 1.0),
            (7.5, 1e-6),
            (120.0, 40.0),
        ] {
            let (phi, qd) = van_loan(&f, &g, &Matrix1::new(q), dt);
            let want = Matrix2::new(dt.powi(3) / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt) * q;
            assert!(
                rel_err(&phi, &Matrix2::new(1.0, dt, 0.0, 1.0)) < 1e-14,
                "dt {dt}"
            );
            assert!(rel_err(&qd, &want) < 1e-12, "dt {dt}: {qd} vs {want}");
            assert_eq!(qd, qd.transpose());
        }
    }

    #[test]
    fn constant_acceleration_closed_form() {
        let f = Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
        let g = Vector3::new(0.0, 0.0, 1.0);
        for (dt, q) in [(0.01_f64, 2.0), (0.5, 1.0), (3.0, 0.1), (25.0, 1.0)] {
            let (d2, d3, d4, d5) = (dt * dt, dt.powi(3), dt.powi(4), dt.powi(5));
            #[rustfmt::skip]
            let want = Matrix3::new(
                d5 / 20.0, d4 / 8.0, d3 / 6.0,
                d4 / 8.0, d3 / 3.0, d2 / 2.0,
                d3 / 6.0, d2 / 2.0, dt,
            ) * q;
            let (phi, qd) = van_loan(&f, &g, &Matrix1::new(q), dt);
            let phi_want = Matrix3::new(1.0, dt, d2 / 2.0, 0.0, 1.0, dt, 0.0, 0.0, 1.0);
            assert!(rel_err(&phi, &phi_want) < 1e-14, "dt {dt}");
            assert!(rel_err(&qd, &want) < 1e-12, "dt {dt}: {qd} vs {want}");
        }
    }

    /// Scalar Gauss-Markov ẋ = −x/τ + w, Q_c = 2σ²/τ: Q_d = σ² (1 − e^{−2dt/τ}),
    /// including dt/τ = 40 where e^{−F dt} ≈ 2·10¹⁷ would swamp a direct
    /// Φ · (Φ⁻¹ Q_d).
    #[test]
    fn gauss_markov_closed_form() {
        let (tau, sigma) = (2.0, 0.3);
        for dt in [1e-3, 0.5, 1.0, 7.0, 80.0] {
            let f = Matrix1::new(-1.0 / tau);
            let qc = Matrix1::new(2.0 * sigma * sigma / tau);
            let (phi, qd) = van_loan(&f, &Matrix1::new(1.0), &qc, dt);
            let want = sigma * sigma * -f64::exp_m1(-2.0 * dt / tau);
            assert!(
                (phi[0] / f64::exp(-dt / tau) - 1.0).abs() < 1e-12,
                "dt {dt}"
            );
            assert!(
                (qd[0] / want - 1.0).abs() < 1e-12,
                "dt {dt}: {} vs {want}",
                qd[0]
            );
        }
    }

    /// A coupled, non-normal system against Simpson's rule on the integrand
    /// `e^{Fs} G Q_c Gᵀ e^{Fᵀs}`, each point by `expm`.
    #[test]
    fn coupled_system_against_quadrature() {
        let f = Matrix3::new(-0.4, 1.2, 0.0, -0.8, -0.1, 0.5, 0.3, 0.0, -1.0);
        let g = Matrix3x2::new(1.0, 0.0, 0.5, -1.0, 0.0, 2.0);
        let qc = Matrix2::new(0.7, 0.2, 0.2, 0.3);
        let (dt, n) = (1.7, 4000);
        let s = g * qc * g.transpose();
        let h = dt / n as f64;
        let mut acc = Matrix3::zeros();
        for k in 0..=n {
            let e = crate::expm(&(f * (k as f64 * h)));
            let w = match k {
                0 => 1.0,
                k if k == n => 1.0,
                k if k % 2 == 1 => 4.0,
                _ => 2.0,
            };
            acc += e * s * e.transpose() * w;
        }
        let want = acc * (h / 3.0);
        let (phi, qd) = van_loan(&f, &g, &qc, dt);
        assert!(rel_err(&phi, &crate::expm(&(f * dt))) < 1e-14);
        assert!(rel_err(&qd, &want) < 1e-12, "{qd} vs {want}");
    }

    /// Two decoupled channels with different noise inputs through a 2×2 G and
    /// a correlated Q_c: for F = 0, Q_d = G Q_c Gᵀ dt.
    #[test]
    fn pure_integration() {
        let g = Matrix2::new(1.0, 2.0, 0.0, -1.0);
        let qc = Matrix2::new(2.0, 0.5, 0.5, 1.0);
        let (phi, qd) = van_loan(&Matrix2::zeros(), &g, &qc, 0.25);
        assert_eq!(phi, Matrix2::identity());
        assert!(rel_err(&qd, &(g * qc * g.transpose() * 0.25)) < 1e-15);
    }

    #[test]
    fn degenerate_inputs() {
        let f = Matrix2::new(0.0, 1.0, -1.0, 0.0);
        let g = Vector2::new(0.0, 1.0);
        let (phi, qd) = van_loan(&f, &g, &Matrix1::new(1.0), 0.0);
        assert_eq!((phi, qd), (Matrix2::identity(), Matrix2::zeros()));
        let (phi, qd) = van_loan(&f, &g, &Matrix1::new(0.0), 1.0);
        assert_eq!(qd, Matrix2::zeros());
        assert!(rel_err(&phi, &crate::expm(&f)) < 1e-15);
        let (phi, qd) = van_loan(&f, &g, &Matrix1::new(f64::NAN), 1.0);
        assert!(phi[0].is_nan() && qd[0].is_nan());
        let (phi, qd) = van_loan(&(f * f64::INFINITY), &g, &Matrix1::new(1.0), 1.0);
        assert!(phi[0].is_nan() && qd[0].is_nan());
    }

    #[test]
    fn f32_constant_velocity() {
        let f = Matrix2::new(0.0_f32, 1.0, 0.0, 0.0);
        let (phi, qd) = van_loan(&f, &Vector2::new(0.0, 1.0), &Matrix1::new(2.0), 2.0);
        assert_eq!(phi, Matrix2::new(1.0, 2.0, 0.0, 1.0));
        let want = Matrix2::new(8.0 / 3.0, 2.0, 2.0, 2.0) * 2.0;
        assert!(
            (qd - want).norm() < 8.0 * f32::EPSILON * want.norm(),
            "{qd}"
        );
    }
}
