//! First-order Gauss-Markov states (exponentially correlated noise).

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

/// `N` independent first-order Gauss-Markov processes
/// `ẋᵢ = −xᵢ / τᵢ + wᵢ`, parametrised by the correlation time `τᵢ > 0` (seconds)
/// and the steady-state standard deviation `σᵢ` (the white-noise density is
/// `2σᵢ² / τᵢ`). Over `dt`:
///
/// `Φ = diag(e^{−dt/τᵢ})`, `Q = diag(σᵢ² (1 − e^{−2dt/τᵢ}))`,
///
/// with `1 − e^{−2dt/τ}` evaluated through `expm1` so short steps keep full
/// relative accuracy. `τᵢ = ∞` gives a constant state (`Φ = 1`, `Q = 0`).
///
/// ```
/// use kestrel_models::GaussMarkov;
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::Vector1};
/// let gm = GaussMarkov::new(Vector1::new(2.0), Vector1::new(3.0)).unwrap();
/// let x = Vector1::new(1.0);
/// let e = (-0.5_f64).exp(); // dt / τ = 1 / 2
/// assert!((gm.propagate(&x, 1.0)[0] - e).abs() < 1e-15);
/// assert!((gm.transition(&x, 1.0)[0] - e).abs() < 1e-15);
/// assert!((gm.noise(&x, 1.0)[0] - 9.0 * (1.0 - e * e)).abs() < 1e-14);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussMarkov<T: Real, const N: usize> {
    /// The correlation times `τᵢ > 0`, in seconds.
    pub correlation_times: SVector<T, N>,
    /// The steady-state standard deviations `σᵢ`.
    pub std_devs: SVector<T, N>,
}

impl<T: Real, const N: usize> GaussMarkov<T, N> {
    /// Processes with correlation times `tau` and steady-state standard
    /// deviations `sigma`.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"tau"` unless every `τᵢ` is
    /// positive (`+∞` allowed), `"sigma"` unless every `σᵢ` is finite and `≥ 0`.
    pub fn new(tau: SVector<T, N>, sigma: SVector<T, N>) -> Result<Self, FilterError> {
        // NaN fails `> 0`; τ = +∞ is a random constant.
        if !tau.iter().all(|t| *t > T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "tau",
                valid: "greater than 0 for every state (+∞ for a random constant)",
            });
        }
        if !sigma.iter().all(|s| s.is_finite() && *s >= T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "sigma",
                valid: "finite and at least 0 for every state",
            });
        }
        Ok(Self {
            correlation_times: tau,
            std_devs: sigma,
        })
    }

    /// `N` identical processes (the same errors as [`new`](Self::new)).
    pub fn uniform(tau: T, sigma: T) -> Result<Self, FilterError> {
        Self::new(SVector::repeat(tau), SVector::repeat(sigma))
    }

    /// `e^{−dt/τᵢ}` for each state.
    fn decay(&self, dt: T) -> SVector<T, N> {
        self.correlation_times.map(|tau| (-dt / tau).exp())
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for GaussMarkov<T, N> {
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        self.decay(dt).component_mul(x)
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let two = T::one() + T::one();
        SMatrix::from_diagonal(
            &self
                .correlation_times
                .zip_map(&self.std_devs, |tau, s| -s * s * (-two * dt / tau).exp_m1()),
        )
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for GaussMarkov<T, N> {
    fn transition(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        SMatrix::from_diagonal(&self.decay(dt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix1, Matrix2, Vector1, Vector2};

    #[test]
    fn hand_computed() {
        // τ = dt / ln 2 halves the state per step; Q = σ² (1 − 1/4).
        let ln2 = core::f64::consts::LN_2;
        let gm = GaussMarkov::new(
            Vector2::new(1.0 / ln2, f64::INFINITY),
            Vector2::new(2.0, 5.0),
        )
        .unwrap();
        let x = Vector2::new(8.0, 3.0);
        let got = gm.propagate(&x, 1.0);
        assert!((got - Vector2::new(4.0, 3.0)).norm() < 1e-14, "{got}");
        let q = gm.noise(&x, 1.0);
        assert!((q - Matrix2::new(3.0, 0.0, 0.0, 0.0)).norm() < 1e-14, "{q}");
        assert_eq!(gm.transition(&x, 1.0)[(1, 1)], 1.0);
    }

    /// A short step keeps relative accuracy: Q ≈ 2σ² dt / τ.
    #[test]
    fn short_step() {
        let gm = GaussMarkov::<f64, 1>::uniform(100.0, 1.0).unwrap();
        let q = gm.noise(&Vector1::zeros(), 1e-9)[0];
        assert!((q / (2.0 * 1e-11) - 1.0).abs() < 1e-10, "{q}");
    }

    #[test]
    fn matches_van_loan() {
        let (tau, sigma, dt) = (3.0, 0.2, 1.3);
        let gm = GaussMarkov::<f64, 1>::uniform(tau, sigma).unwrap();
        let (phi, q) = crate::van_loan(
            &Matrix1::new(-1.0 / tau),
            &Matrix1::new(1.0),
            &Matrix1::new(2.0 * sigma * sigma / tau),
            dt,
        );
        assert!((phi[0] / gm.transition(&Vector1::zeros(), dt)[0] - 1.0).abs() < 1e-14);
        assert!((q[0] / gm.noise(&Vector1::zeros(), dt)[0] - 1.0).abs() < 1e-12);
    }
}
