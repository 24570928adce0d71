//! The Singer model: acceleration as a first-order Gauss-Markov process.

use kestrel_core::nalgebra::{Matrix3, SMatrix, SVector};
use kestrel_core::real::lit;
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

use crate::axes::{apply_per_axis, block_diagonal};
use crate::sizes::{AccelerationAxes, Size};
use crate::van_loan;

/// The Singer manoeuvring-target model (Singer 1970, *Estimating Optimal
/// Tracking Filter Performance for Manned Maneuvering Targets*, IEEE
/// Trans. AES-6(4)): per axis `[p, v, a]` with `ȧ = −a/τ + w`, the
/// acceleration exponentially correlated with time constant `τ` and
/// steady-state standard deviation `σ` (`E[w w] = 2σ²/τ δ`).
///
/// `Φ` and `Q` are the exact discretisation (Van Loan's matrix exponential,
/// [`van_loan`](crate::van_loan)), so they hold for every `dt / τ` without
/// the cancellation of Singer's closed-form `Q` at small `dt / τ`. In
/// closed form, `Φ = [[1, dt, τ²(e^{−dt/τ} − 1 + dt/τ)], [0, 1,
/// τ(1 − e^{−dt/τ})], [0, 0, e^{−dt/τ}]]` and `Q_aa = σ²(1 − e^{−2dt/τ})`.
/// For `τ → ∞` with `2σ²/τ` fixed it becomes
/// [`ConstantAcceleration`](crate::ConstantAcceleration).
///
/// The state is interleaved per axis like `ConstantAcceleration`: `N` is 3,
/// 6 or 9.
///
/// ```
/// use kestrel_models::Singer;
/// use kestrel_core::{LinearizedProcess, ProcessModel, nalgebra::Vector3};
/// let singer = Singer::<f64, 3>::new(2.0, 3.0).unwrap();
/// let q = singer.noise(&Vector3::zeros(), 1.0);
/// assert!((q[(2, 2)] - 9.0 * (1.0 - (-1.0_f64).exp())).abs() < 1e-12);
/// let phi = singer.transition(&Vector3::zeros(), 1.0);
/// assert!((phi[(2, 2)] - (-0.5_f64).exp()).abs() < 1e-14);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Singer<T: Real, const N: usize>
where
    Size<N>: AccelerationAxes,
{
    tau: T,
    sigma: T,
}

impl<T: Real, const N: usize> Singer<T, N>
where
    Size<N>: AccelerationAxes,
{
    /// The model with manoeuvre time constant `tau` (s) and acceleration
    /// standard deviation `sigma` [unit/s²], the same on every axis.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] `"tau"` unless finite and `> 0`,
    /// `"sigma"` unless finite and `≥ 0`.
    pub fn new(tau: T, sigma: T) -> Result<Self, FilterError> {
        if !(tau.is_finite() && tau > T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "tau",
                valid: "finite and greater than 0",
            });
        }
        if !(sigma.is_finite() && sigma >= T::zero()) {
            return Err(FilterError::InvalidParameter {
                name: "sigma",
                valid: "finite and at least 0",
            });
        }
        Ok(Self { tau, sigma })
    }

    /// The manoeuvre time constant `τ` (s).
    pub fn tau(&self) -> T {
        self.tau
    }

    /// The acceleration standard deviation `σ`.
    pub fn sigma(&self) -> T {
        self.sigma
    }

    /// `(Φ, Q)` of one axis over `dt`.
    fn axis(&self, dt: T) -> (Matrix3<T>, Matrix3<T>) {
        let z = T::zero();
        let f = Matrix3::new(z, T::one(), z, z, z, T::one(), z, z, -self.tau.recip());
        let g = SMatrix::<T, 3, 1>::new(z, z, T::one());
        let qc = SMatrix::<T, 1, 1>::new(self.sigma * self.sigma * lit(2.0) / self.tau);
        van_loan(&f, &g, &qc, dt)
    }
}

impl<T: Real, const N: usize> ProcessModel<T, N> for Singer<T, N>
where
    Size<N>: AccelerationAxes,
{
    fn propagate(&self, x: &SVector<T, N>, dt: T) -> SVector<T, N> {
        apply_per_axis::<T, N, 3>(&self.axis(dt).0, x)
    }

    fn noise(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let q = self.axis(dt).1;
        block_diagonal::<T, N, 3>(|_| q)
    }
}

impl<T: Real, const N: usize> LinearizedProcess<T, N> for Singer<T, N>
where
    Size<N>: AccelerationAxes,
{
    fn transition(&self, _x: &SVector<T, N>, dt: T) -> SMatrix<T, N, N> {
        let phi = self.axis(dt).0;
        block_diagonal::<T, N, 3>(|_| phi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ConstantAcceleration1d;
    use kestrel_core::nalgebra::{Vector3, Vector6};

    #[test]
    fn closed_form_transition_and_acceleration_variance() {
        let (tau, sigma, dt) = (4.0, 1.5, 0.8_f64);
        let s = Singer::<f64, 3>::new(tau, sigma).unwrap();
        let phi = s.transition(&Vector3::zeros(), dt);
        let e = (-dt / tau).exp();
        let want = Matrix3::new(
            1.0,
            dt,
            tau * tau * (e - 1.0 + dt / tau),
            0.0,
            1.0,
            tau * (1.0 - e),
            0.0,
            0.0,
            e,
        );
        assert!((phi - want).norm() < 1e-13, "{phi}");
        let q = s.noise(&Vector3::zeros(), dt);
        let qaa = sigma * sigma * (1.0 - (-2.0 * dt / tau).exp());
        assert!((q[(2, 2)] - qaa).abs() < 1e-13);
        // Steady state: with dt ≫ τ, Q_aa → σ².
        let q = s.noise(&Vector3::zeros(), 200.0);
        assert!((q[(2, 2)] - sigma * sigma).abs() < 1e-9);
    }

    /// A very long time constant with 2σ²/τ fixed is the constant-
    /// acceleration model with jerk density 2σ²/τ.
    #[test]
    fn long_time_constant_is_constant_acceleration() {
        let (density, tau) = (0.3, 1e7);
        let sigma = (density * tau / 2.0_f64).sqrt();
        let s = Singer::<f64, 3>::new(tau, sigma).unwrap();
        let ca = ConstantAcceleration1d::new(density).unwrap();
        let x = Vector3::new(1.0, 2.0, 3.0);
        let (qs, qc) = (s.noise(&x, 1.5), ca.noise(&x, 1.5));
        assert!((qs - qc).norm() < 1e-6 * qc.norm(), "{qs} vs {qc}");
        assert!((s.propagate(&x, 1.5) - ca.propagate(&x, 1.5)).norm() < 1e-6);
    }

    #[test]
    fn axes_are_independent_and_parameters_checked() {
        let s = Singer::<f64, 6>::new(2.0, 1.0).unwrap();
        let q = s.noise(&Vector6::zeros(), 1.0);
        assert_eq!(q[(0, 3)], 0.0);
        assert_eq!(q.fixed_view::<3, 3>(0, 0), q.fixed_view::<3, 3>(3, 3));
        assert!(Singer::<f64, 3>::new(0.0, 1.0).is_err());
        assert!(Singer::<f64, 3>::new(1.0, -1.0).is_err());
    }
}
