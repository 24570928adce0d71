//! The true errors of one simulated IMU, per axis.

use nalgebra::Vector3;

use super::rng::{normal3, SimRng};
use kestrel_nav::imu_spec::ImuSpec;

/// The errors a simulated IMU really has (as opposed to the [`ImuSpec`] a
/// filter assumes), per body axis (x forward, y right, z down), SI units:
///
/// ```text
/// Δθ = (1 + s_g) ∘ Δθ_true + (b_g + m_g) Δt + arw ∘ √Δt n
/// Δv = (1 + s_a) ∘ Δv_true + (b_a + m_a) Δt + vrw ∘ √Δt n
/// ```
///
/// with `m` first-order Gauss–Markov drifts (σ, τ per axis) and `n` unit
/// white noise.
///
/// ```
/// use kestrel_nav::{ImuSpec};
/// use kestrel_sim::ImuErrors;
/// let spec = ImuSpec::perfect().with_gyro_bias_deg_per_h(0.01).with_accel_bias_ug(50.0);
/// let e = ImuErrors::from_spec(&spec);
/// assert_eq!(e.gyro_bias.x, spec.gyro_bias);
/// assert_eq!(e.accel_bias.z, spec.accel_bias);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuErrors {
    /// Gyro constant bias, rad/s.
    pub gyro_bias: Vector3<f64>,
    /// Gyro angle random walk (white rate-noise density), rad/√s.
    pub gyro_arw: Vector3<f64>,
    /// Gyro Gauss–Markov drift steady-state σ, rad/s.
    pub gyro_markov_sigma: Vector3<f64>,
    /// Gyro Gauss–Markov correlation time, s.
    pub gyro_markov_tau: Vector3<f64>,
    /// Gyro scale-factor error, ratio.
    pub gyro_scale: Vector3<f64>,
    /// Accelerometer constant bias, m/s².
    pub accel_bias: Vector3<f64>,
    /// Accelerometer velocity random walk (white noise density), m/s/√s.
    pub accel_vrw: Vector3<f64>,
    /// Accelerometer Gauss–Markov bias steady-state σ, m/s².
    pub accel_markov_sigma: Vector3<f64>,
    /// Accelerometer Gauss–Markov correlation time, s.
    pub accel_markov_tau: Vector3<f64>,
    /// Accelerometer scale-factor error, ratio.
    pub accel_scale: Vector3<f64>,
}

impl Default for ImuErrors {
    fn default() -> Self {
        Self::perfect()
    }
}

impl ImuErrors {
    /// No errors at all.
    ///
    /// ```
    /// assert_eq!(kestrel_sim::ImuErrors::perfect().gyro_arw.x, 0.0);
    /// ```
    pub fn perfect() -> Self {
        Self::from_spec(&ImuSpec::perfect())
    }

    /// The magnitudes of `spec` taken literally on every axis: constant
    /// biases and scale factors equal to `+1σ` (what a paper means by
    /// "gyro constant drift 0.01°/h"), noise and Markov terms as given.
    ///
    /// ```
    /// use kestrel_nav::{ImuSpec};
    /// use kestrel_sim::ImuErrors;
    /// let spec = ImuSpec::perfect().with_gyro_scale_ppm(500.0);
    /// assert_eq!(ImuErrors::from_spec(&spec).gyro_scale.y, 5e-4);
    /// ```
    pub fn from_spec(spec: &ImuSpec) -> Self {
        let r = Vector3::repeat;
        Self {
            gyro_bias: r(spec.gyro_bias),
            gyro_arw: r(spec.gyro_arw),
            gyro_markov_sigma: r(spec.gyro_markov_sigma),
            gyro_markov_tau: r(spec.gyro_markov_tau),
            gyro_scale: r(spec.gyro_scale),
            accel_bias: r(spec.accel_bias),
            accel_vrw: r(spec.accel_vrw),
            accel_markov_sigma: r(spec.accel_markov_sigma),
            accel_markov_tau: r(spec.accel_markov_tau),
            accel_scale: r(spec.accel_scale),
        }
    }

    /// One random IMU of the population `spec` describes: constant biases
    /// and scale factors drawn `N(0, σ²)` per axis; noise and Markov terms
    /// as given.
    ///
    /// ```
    /// use kestrel_nav::{ImuSpec};
    /// use kestrel_sim::{sensor_rng, ImuErrors, SensorStream};
    /// let spec = ImuSpec::perfect().with_accel_bias_mg(1.0);
    /// let a = ImuErrors::sample(&spec, &mut sensor_rng(5, SensorStream::Constants));
    /// let b = ImuErrors::sample(&spec, &mut sensor_rng(5, SensorStream::Constants));
    /// assert_eq!(a, b);
    /// assert!(a.accel_bias.x != a.accel_bias.y);
    /// ```
    pub fn sample(spec: &ImuSpec, rng: &mut SimRng) -> Self {
        let mut e = Self::from_spec(spec);
        e.gyro_bias = normal3(rng) * spec.gyro_bias;
        e.accel_bias = normal3(rng) * spec.accel_bias;
        e.gyro_scale = normal3(rng) * spec.gyro_scale;
        e.accel_scale = normal3(rng) * spec.accel_scale;
        e
    }
}
