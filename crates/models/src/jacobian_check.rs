//! Finite-difference Jacobians, to check hand-written ones.
//!
//! Central differences with a step `hᵢ = ε^{1/3} max(|xᵢ|, 1)` per state: the
//! truncation error is `O(h²)` and the rounding error `O(ε/h)`, both about
//! `ε^{2/3}` (≈ 4·10⁻¹¹ in `f64`) relative to the function's scale. A
//! correct analytic Jacobian therefore agrees to about `10⁻⁸` in `f64`
//! (curvature and large values widen this); a wrong entry is typically off
//! by its own size. Measurement differences go through
//! [`MeasurementModel::residual`], so a bearing that wraps at ±π does not
//! produce a spurious `2π / 2h`.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::real::{epsilon, lit};
use kestrel_core::{LinearizedMeasurement, LinearizedProcess, Real};

/// How far an analytic Jacobian is from the finite-difference one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianCheck<T: Real> {
    /// The largest `|Jₐ − J_fd| / max(1, |J_fd|)` over all entries.
    pub max_error: T,
    /// Its row (measurement or state component).
    pub row: usize,
    /// Its column (state component differentiated).
    pub col: usize,
    /// The analytic entry there.
    pub analytic: T,
    /// The finite-difference entry there.
    pub numeric: T,
}

impl<T: Real> JacobianCheck<T> {
    /// Whether every entry agrees to `tolerance` (relative to `max(1, |J|)`).
    pub fn passes(&self, tolerance: T) -> bool {
        self.max_error <= tolerance
    }
}

/// The finite-difference Jacobian of `f` at `x`: column `j` is
/// `diff(f(x + hⱼ eⱼ), f(x − hⱼ eⱼ)) / 2hⱼ`.
///
/// ```
/// use kestrel_models::finite_difference_jacobian;
/// use kestrel_core::nalgebra::{Vector1, Vector2};
/// let j = finite_difference_jacobian(
///     |x: &Vector2<f64>| Vector1::new(x[0] * x[1]),
///     |a, b| a - b,
///     &Vector2::new(2.0, 3.0),
/// );
/// assert!((j[(0, 0)] - 3.0).abs() < 1e-9 && (j[(0, 1)] - 2.0).abs() < 1e-9);
/// ```
pub fn finite_difference_jacobian<T, const N: usize, const K: usize>(
    f: impl Fn(&SVector<T, N>) -> SVector<T, K>,
    diff: impl Fn(&SVector<T, K>, &SVector<T, K>) -> SVector<T, K>,
    x: &SVector<T, N>,
) -> SMatrix<T, K, N>
where
    T: Real,
{
    let root = epsilon::<T>().cbrt();
    let mut j = SMatrix::<T, K, N>::zeros();
    for c in 0..N {
        let h = root * x[c].abs().max(T::one());
        let (mut plus, mut minus) = (*x, *x);
        plus[c] += h;
        minus[c] -= h;
        // The step actually taken, after rounding of x ± h.
        let span = plus[c] - minus[c];
        j.set_column(c, &(diff(&f(&plus), &f(&minus)) / span));
    }
    j
}

/// Compares `analytic` with `numeric` entry by entry.
fn compare<T: Real, const K: usize, const N: usize>(
    analytic: &SMatrix<T, K, N>,
    numeric: &SMatrix<T, K, N>,
) -> JacobianCheck<T> {
    let mut worst = JacobianCheck {
        max_error: T::zero(),
        row: 0,
        col: 0,
        analytic: analytic[(0, 0)],
        numeric: numeric[(0, 0)],
    };
    for c in 0..N {
        for r in 0..K {
            let (a, n) = (analytic[(r, c)], numeric[(r, c)]);
            let e = (a - n).abs() / n.abs().max(T::one());
            // NaN anywhere is the worst error.
            if !e.is_finite() || e > worst.max_error {
                worst = JacobianCheck {
                    max_error: if e.is_finite() { e } else { lit(f64::INFINITY) },
                    row: r,
                    col: c,
                    analytic: a,
                    numeric: n,
                };
            }
        }
    }
    worst
}

/// Checks a measurement model's [`LinearizedMeasurement::jacobian`] at `x`
/// against central differences of its prediction.
///
/// ```
/// use kestrel_models::{check_measurement_jacobian, RangeBearing};
/// use kestrel_core::nalgebra::{Matrix2, Vector4};
/// let radar = RangeBearing::<f64, 4>::new(0, 2, Matrix2::identity()).unwrap();
/// let check = check_measurement_jacobian(&radar, &Vector4::new(300.0, 5.0, -40.0, 1.0));
/// assert!(check.passes(1e-8), "{check:?}");
/// ```
pub fn check_measurement_jacobian<T, H, const N: usize, const M: usize>(
    model: &H,
    x: &SVector<T, N>,
) -> JacobianCheck<T>
where
    T: Real,
    H: LinearizedMeasurement<T, N, M>,
{
    let numeric = finite_difference_jacobian(|x| model.predict(x), |a, b| model.residual(a, b), x);
    compare(&model.jacobian(x), &numeric)
}

/// Checks a process model's [`LinearizedProcess::transition`] at `x` over
/// `dt` against central differences of its propagation.
///
/// ```
/// use kestrel_models::{check_process_jacobian, ConstantVelocity2d};
/// use kestrel_core::nalgebra::Vector4;
/// let cv = ConstantVelocity2d::new(0.1).unwrap();
/// assert!(check_process_jacobian(&cv, &Vector4::new(1.0, 2.0, 3.0, 4.0), 0.5).passes(1e-9));
/// ```
pub fn check_process_jacobian<T, P, const N: usize>(
    model: &P,
    x: &SVector<T, N>,
    dt: T,
) -> JacobianCheck<T>
where
    T: Real,
    P: LinearizedProcess<T, N>,
{
    let numeric = finite_difference_jacobian(|x| model.propagate(x, dt), |a, b| a - b, x);
    compare(&model.transition(x, dt), &numeric)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix1, Matrix1x2, Vector1, Vector2};
    use kestrel_core::MeasurementModel;

    /// `h(x) = x₀ x₁` with a Jacobian that is right, then one that is wrong
    /// in entry (0, 1).
    struct Product(bool);
    impl MeasurementModel<f64, 2, 1> for Product {
        fn predict(&self, x: &Vector2<f64>) -> Vector1<f64> {
            Vector1::new(x[0] * x[1])
        }
        fn noise(&self) -> Matrix1<f64> {
            Matrix1::new(1.0)
        }
    }
    impl LinearizedMeasurement<f64, 2, 1> for Product {
        fn jacobian(&self, x: &Vector2<f64>) -> Matrix1x2<f64> {
            let d1 = if self.0 { x[0] } else { 2.0 * x[0] };
            Matrix1x2::new(x[1], d1)
        }
    }

    #[test]
    fn finds_the_wrong_entry() {
        let x = Vector2::new(3.0, -2.0);
        assert!(check_measurement_jacobian(&Product(true), &x).passes(1e-9));
        let bad = check_measurement_jacobian(&Product(false), &x);
        assert_eq!((bad.row, bad.col), (0, 1));
        assert!((bad.analytic - 6.0).abs() < 1e-12 && (bad.numeric - 3.0).abs() < 1e-6);
        assert!((bad.max_error - 1.0).abs() < 1e-6, "{bad:?}");
    }

    /// A bearing residual that wraps: the check differences through it.
    #[test]
    fn a_wrapping_bearing_is_differenced_through_the_residual() {
        let radar =
            crate::RangeBearing::<f64, 2>::new(0, 1, kestrel_core::nalgebra::Matrix2::identity())
                .unwrap();
        // On the negative x axis the bearing jumps from +π to −π.
        let check = check_measurement_jacobian(&radar, &Vector2::new(-10.0, 0.0));
        assert!(check.passes(1e-8), "{check:?}");
    }
}
