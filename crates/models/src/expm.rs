//! The matrix exponential.

use kestrel_core::nalgebra::SMatrix;
use kestrel_core::Real;

use crate::pade::{nan, scaled_pade};

/// The matrix exponential `e^A` by scaling and squaring with a diagonal Padé
/// approximant (Higham 2005): the smallest degree `m ∈ {3, 5, 7, 9, 13}`
/// whose backward error stays below the unit roundoff for `‖A‖₁` is used
/// directly; above the degree-13 bound, `A` is halved `s` times, `r₁₃(A/2ˢ)`
/// evaluated and squared `s` times. `f32` uses the single-precision bounds
/// (top degree 7).
///
/// Cost: 2 (degree 3) to 6 (degree 13) matrix products, one LU solve, plus
/// `s` squarings.
/// Allocation-free. A non-finite `A` (or, impossible in exact arithmetic, a
/// singular Padé denominator) gives a matrix of NaN, which a filter rejects
/// as a non-finite transition.
///
/// ```
/// use kestrel_models::expm;
/// use kestrel_core::nalgebra::Matrix2;
/// // A rotation generator exponentiates to a rotation by w.
/// let w = 0.3_f64;
/// let r = expm(&Matrix2::new(0.0, -w, w, 0.0));
/// assert!((r - Matrix2::new(w.cos(), -w.sin(), w.sin(), w.cos())).norm() < 1e-15);
/// ```
pub fn expm<T: Real, const N: usize>(a: &SMatrix<T, N, N>) -> SMatrix<T, N, N> {
    match scaled_pade(a) {
        Some((mut r, s)) => {
            for _ in 0..s {
                r = r * r;
            }
            r
        }
        None => SMatrix::from_element(nan::<T>()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix2, Matrix3, Matrix4};

    fn rel_err<const N: usize>(got: &SMatrix<f64, N, N>, want: &SMatrix<f64, N, N>) -> f64 {
        (got - want).norm() / want.norm()
    }

    /// Rotation generators across every degree band and with squarings.
    #[test]
    fn rotation_generator() {
        // The top of each degree's band (θ₃ … θ₁₃), inside the degree-13 band,
        // and with 1, 5 and 3 squarings.
        for w in [
            0.0149, 0.2539, 0.9504, 1.5, 2.0978, 3.0, 5.3719, 10.0, 100.0, -7.0,
        ] {
            let (s, c) = f64::sin_cos(w);
            let got = expm(&Matrix2::new(0.0, -w, w, 0.0));
            let want = Matrix2::new(c, -s, s, c);
            // Squaring a rotation 2ˢ times amplifies the rounding by about 2ˢ
            // (s = 5 for w = 100), the conditioning of e^A itself.
            let tol = if w.abs() > 50.0 {
                1e-13 * w.abs()
            } else {
                1e-14
            };
            assert!(rel_err(&got, &want) < tol, "w = {w}: {got}");
        }
    }

    /// A nilpotent matrix: the exponential is the finite series I + N + N²/2.
    #[test]
    fn nilpotent() {
        for t in [0.01, 0.7, 3.0, 40.0] {
            let n = Matrix3::new(0.0, t, 2.0 * t, 0.0, 0.0, -t, 0.0, 0.0, 0.0);
            let want = Matrix3::identity() + n + n * n / 2.0;
            // N² = [[0, 0, −t²], 0, 0].
            assert_eq!((n * n)[(0, 2)], -t * t);
            assert!(rel_err(&expm(&n), &want) < 1e-12, "t = {t}");
        }
    }

    #[test]
    fn diagonal() {
        let d: [f64; 4] = [-20.0, -1.0, 0.25, 3.0];
        let got = expm(&Matrix4::from_diagonal(&d.into()));
        for (i, di) in d.iter().enumerate() {
            assert!((got[(i, i)] / di.exp() - 1.0).abs() < 1e-13, "{i}");
        }
        assert_eq!(got.sum() - got.trace(), 0.0);
    }

    /// A Jordan block (defective, non-normal): e^{J} = e^λ [[1, 1, ½], [0, 1, 1], [0, 0, 1]].
    #[test]
    fn jordan_block() {
        for l in [-3.0, 0.0, 0.4, 2.0] {
            let j = Matrix3::new(l, 1.0, 0.0, 0.0, l, 1.0, 0.0, 0.0, l);
            let want = Matrix3::new(1.0, 1.0, 0.5, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0) * f64::exp(l);
            assert!(rel_err(&expm(&j), &want) < 1e-13, "λ = {l}");
        }
    }

    /// Upper triangular with distinct eigenvalues a, c:
    /// e^A = [[eᵃ, b (eᵃ − eᶜ)/(a − c)], [0, eᶜ]].
    #[test]
    fn triangular_distinct() {
        let (a, b, c): (f64, f64, f64) = (1.3, -4.0, -0.6);
        let want = Matrix2::new(a.exp(), b * (a.exp() - c.exp()) / (a - c), 0.0, c.exp());
        assert!(rel_err(&expm(&Matrix2::new(a, b, 0.0, c)), &want) < 1e-13);
    }

    #[test]
    fn f32_accuracy() {
        let w = 2.0_f32;
        let got = expm(&Matrix2::new(0.0, -w, w, 0.0));
        let want = Matrix2::new(w.cos(), -w.sin(), w.sin(), w.cos());
        assert!((got - want).norm() < 4.0 * f32::EPSILON, "{got}");
        let n = Matrix2::new(0.0_f32, 3.0, 0.0, 0.0);
        assert!((expm(&n) - Matrix2::new(1.0, 3.0, 0.0, 1.0)).norm() < 4.0 * f32::EPSILON);
    }

    #[test]
    fn zero_and_non_finite() {
        assert_eq!(expm(&Matrix3::<f64>::zeros()), Matrix3::identity());
        let mut a = Matrix2::new(0.0, 1.0, 0.0, 0.0);
        a[(1, 0)] = f64::NAN;
        assert!(expm(&a).iter().all(|v| v.is_nan()));
        a[(1, 0)] = f64::INFINITY;
        assert!(expm(&a).iter().all(|v| v.is_nan()));
        // A huge finite norm squares to overflow instead of panicking.
        let big = expm(&Matrix2::new(1e300_f64, 0.0, 0.0, 1.0));
        assert!(big[(0, 0)].is_infinite() || big[(0, 0)].is_nan());
    }

    /// e^A e^{−A} = I for a dense matrix (degree 13 with squarings).
    #[test]
    fn inverse_identity() {
        let a = Matrix3::new(0.3, -2.0, 1.1, 4.0, -0.5, 0.2, -1.0, 3.0, 0.9);
        let p = expm(&a) * expm(&-a);
        assert!((p - Matrix3::identity()).norm() < 1e-11, "{p}");
    }
}
