//! First-order Gauss–Markov processes, discretised exactly.

use nalgebra::Vector3;

use super::rng::{normal, SimRng};

/// A scalar first-order Gauss–Markov process `ẋ = −x/τ + w` with
/// steady-state standard deviation `σ`, sampled exactly:
/// `x_k = e^{−Δt/τ} x_{k−1} + σ √(1 − e^{−2Δt/τ}) n_k`.
/// It starts in its steady state (`x₀ ~ N(0, σ²)`). `σ = 0` or a
/// non-finite or non-positive `τ` make it identically zero.
///
/// ```
/// use kestrel_sim::{sensor_rng, GaussMarkov, SensorStream};
/// let mut rng = sensor_rng(1, SensorStream::Imu);
/// let mut m = GaussMarkov::new(0.5, 100.0, &mut rng);
/// let x0 = m.value();
/// m.step(1e-9, &mut rng);
/// assert!((m.value() - x0).abs() < 1e-4);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussMarkov {
    sigma: f64,
    tau: f64,
    x: f64,
}

impl GaussMarkov {
    /// A process with steady-state σ `sigma` and correlation time `tau`
    /// (s), its initial value drawn from `rng`.
    ///
    /// ```
    /// use kestrel_sim::{sensor_rng, GaussMarkov, SensorStream};
    /// let m = GaussMarkov::new(0.0, 10.0, &mut sensor_rng(1, SensorStream::Imu));
    /// assert_eq!(m.value(), 0.0);
    /// ```
    pub fn new(sigma: f64, tau: f64, rng: &mut SimRng) -> Self {
        let active = sigma.is_finite() && sigma > 0.0 && tau.is_finite() && tau > 0.0;
        let sigma = if active { sigma } else { 0.0 };
        let x = if active { sigma * normal(rng) } else { 0.0 };
        Self { sigma, tau, x }
    }

    /// The current value.
    ///
    /// ```
    /// use kestrel_sim::{sensor_rng, GaussMarkov, SensorStream};
    /// let m = GaussMarkov::new(1.0, 10.0, &mut sensor_rng(3, SensorStream::Imu));
    /// assert!(m.value().is_finite());
    /// ```
    pub fn value(&self) -> f64 {
        self.x
    }

    /// Advances by `dt` (s); returns the mean of the old and new values
    /// (the process integrated over the step, to second order).
    ///
    /// ```
    /// use kestrel_sim::{sensor_rng, GaussMarkov, SensorStream};
    /// let mut rng = sensor_rng(2, SensorStream::Imu);
    /// let mut m = GaussMarkov::new(1.0, 10.0, &mut rng);
    /// let (x0, mean) = (m.value(), m.step(0.01, &mut rng));
    /// assert!((mean - 0.5 * (x0 + m.value())).abs() < 1e-15);
    /// ```
    pub fn step(&mut self, dt: f64, rng: &mut SimRng) -> f64 {
        if self.sigma == 0.0 {
            return 0.0;
        }
        let phi = (-dt / self.tau).exp();
        let old = self.x;
        // 1 − φ² computed without cancellation for small steps.
        let q = -(-2.0 * dt / self.tau).exp_m1();
        self.x = phi * old + self.sigma * q.sqrt() * normal(rng);
        0.5 * (old + self.x)
    }
}

/// Three independent [`GaussMarkov`] processes (one per axis).
///
/// ```
/// use kestrel_sim::{sensor_rng, GaussMarkov3, SensorStream};
/// use kestrel_nav::nalgebra::Vector3;
/// let mut rng = sensor_rng(1, SensorStream::Imu);
/// let m = GaussMarkov3::new(&Vector3::new(1.0, 0.0, 1.0), &Vector3::repeat(60.0), &mut rng);
/// assert_eq!(m.value().y, 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussMarkov3 {
    axes: [GaussMarkov; 3],
}

impl GaussMarkov3 {
    /// Per-axis σ and τ (s).
    ///
    /// ```
    /// use kestrel_sim::{sensor_rng, GaussMarkov3, SensorStream};
    /// use kestrel_nav::nalgebra::Vector3;
    /// let m = GaussMarkov3::new(&Vector3::zeros(), &Vector3::repeat(1.0), &mut sensor_rng(1, SensorStream::Imu));
    /// assert_eq!(m.value(), Vector3::zeros());
    /// ```
    pub fn new(sigma: &Vector3<f64>, tau: &Vector3<f64>, rng: &mut SimRng) -> Self {
        Self {
            axes: [0, 1, 2].map(|i| GaussMarkov::new(sigma[i], tau[i], rng)),
        }
    }

    /// The current values.
    ///
    /// ```
    /// use kestrel_sim::{sensor_rng, GaussMarkov3, SensorStream};
    /// use kestrel_nav::nalgebra::Vector3;
    /// let m = GaussMarkov3::new(&Vector3::repeat(1.0), &Vector3::repeat(5.0), &mut sensor_rng(1, SensorStream::Imu));
    /// assert!(m.value().norm() > 0.0);
    /// ```
    pub fn value(&self) -> Vector3<f64> {
        Vector3::new(
            self.axes[0].value(),
            self.axes[1].value(),
            self.axes[2].value(),
        )
    }

    /// Advances by `dt` (s); returns the per-axis mean over the step.
    ///
    /// ```
    /// use kestrel_sim::{sensor_rng, GaussMarkov3, SensorStream};
    /// use kestrel_nav::nalgebra::Vector3;
    /// let mut rng = sensor_rng(1, SensorStream::Imu);
    /// let mut m = GaussMarkov3::new(&Vector3::repeat(1.0), &Vector3::repeat(5.0), &mut rng);
    /// assert!(m.step(0.005, &mut rng).norm().is_finite());
    /// ```
    pub fn step(&mut self, dt: f64, rng: &mut SimRng) -> Vector3<f64> {
        Vector3::new(
            self.axes[0].step(dt, rng),
            self.axes[1].step(dt, rng),
            self.axes[2].step(dt, rng),
        )
    }
}
