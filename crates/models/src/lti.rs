//! Linear time-invariant continuous models, discretised on demand.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{LinearizedProcess, ProcessModel, Real};

use crate::{expm, van_loan, LinearProcess};

/// A continuous linear time-invariant process `ẋ = F x + G w` with white
/// noise `w` of spectral density `Q_c` (`W × W`), discretised for the `dt` of
/// each call: `propagate` is `Φ x`, `transition` is `Φ = e^{F dt}` (by
/// [`expm`]) and `noise` is Van Loan's `Q_d` (by [`van_loan`]).
///
/// Cost: an EKF predict calls `propagate`, `transition` and `noise`, i.e.
/// two matrix exponentials of size `N` and one Van Loan discretisation
/// (roughly 30 `N × N` products in all for moderate `‖F dt‖`). For a fixed
/// step, discretise once with [`discretize`](Self::discretize) and filter
/// with the resulting [`LinearProcess`].
///
/// ```
/// use kestrel_models::Lti;
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::{Matrix1, Matrix2, Vector2}};
/// // A harmonic oscillator of angular frequency ω, forced by white noise.
/// let w = 2.0_f64;
/// let lti = Lti::new(Matrix2::new(0.0, 1.0, -w * w, 0.0), Vector2::new(0.0, 1.0), Matrix1::new(0.1));
/// let dt = 0.25;
/// let x = Vector2::new(1.0, 0.0);
/// // From rest at x = 1: position cos(ωt), velocity −ω sin(ωt).
/// let want = Vector2::new((w * dt).cos(), -w * (w * dt).sin());
/// assert!((lti.propagate(&x, dt) - want).norm() < 1e-14);
/// assert!((lti.transition(&x, dt) * x - want).norm() < 1e-14);
/// // A fixed-step model computed once.
/// let fixed = lti.discretize(dt);
/// assert_eq!(fixed.noise, lti.noise(&x, dt));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lti<T: Real, const N: usize, const W: usize> {
    /// The system matrix `F`.
    pub system: SMatrix<T, N, N>,
    /// The noise input matrix `G`.
    pub input: SMatrix<T, N, W>,
    /// The noise spectral density `Q_c` (symmetric positive semi-definite).
    pub density: SMatrix<T, W, W>,
}

impl<T: Real, const N: usize, const W: usize> Lti<T, N, W> {
    /// The model `ẋ = F x + G w`, `E[w wᵀ] = Q_c δ`.
    pub fn new(f: SMatrix<T, N, N>, g: SMatrix<T, N, W>, qc: SMatrix<T, W, W>) -> Self {
        Self {
            system: f,
            input: g,
            density: qc,
        }
    }

    /// The discrete model for a fixed step `dt`: `(Φ, Q_d)` from
    /// [`van_loan`], as a [`LinearProcess`] that costs nothing per step.
    pub fn discretize(&self, dt: T) -> LinearProcess<T, N> {
        let (phi, q) = van_loan(&self.system, &self.input, &self.density, dt);
        LinearProcess::new(phi, q)
    }
}

impl<T: Real, const N: usize, const W: usize> ProcessModel<T, N> for Lti<T, N, W> {
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        expm(&(self.system * dt)) * x
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        van_loan(&self.system, &self.input, &self.density, dt).1
    }
}

impl<T: Real, const N: usize, const W: usize> LinearizedProcess<T, N> for Lti<T, N, W> {
    fn transition(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        expm(&(self.system * dt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ConstantVelocity1d;
    use kestrel_core::nalgebra::{Matrix1, Matrix2, Vector2};

    #[test]
    fn reproduces_constant_velocity() {
        let lti = Lti::new(
            Matrix2::new(0.0, 1.0, 0.0, 0.0),
            Vector2::new(0.0, 1.0),
            Matrix1::new(0.8),
        );
        let cv = ConstantVelocity1d::new(0.8).unwrap();
        let x = Vector2::new(2.0, -3.0);
        for dt in [0.01, 1.0, 6.0] {
            assert!((lti.propagate(&x, dt) - cv.propagate(&x, dt)).norm() < 1e-13);
            assert!((lti.transition(&x, dt) - cv.transition(&x, dt)).norm() < 1e-13);
            let want = cv.noise(&x, dt);
            assert!((lti.noise(&x, dt) - want).norm() < 1e-12 * want.norm());
            let fixed = lti.discretize(dt);
            assert_eq!(
                fixed.transition,
                van_loan(&lti.system, &lti.input, &lti.density, dt).0
            );
        }
    }

    /// Φ from Van Loan and from expm agree (they take different paths).
    #[test]
    fn transitions_agree() {
        let lti = Lti::new(
            Matrix2::new(-0.3, 2.0, -1.0, -0.1),
            Matrix2::new(1.0, 0.0, 0.5, 1.0),
            Matrix2::new(1.0, 0.2, 0.2, 0.5),
        );
        for dt in [0.1_f64, 2.0, 30.0] {
            let phi = lti.transition(&Vector2::zeros(), dt);
            let d = lti.discretize(dt);
            assert!(
                (d.transition - phi).norm() < 1e-13 * phi.norm().max(1.0_f64),
                "dt {dt}"
            );
        }
    }
}
