//! IMU error specification in SI units, built from datasheet units.

/// Standard gravity used to convert µg / mg, m/s².
pub const G0: f64 = 9.806_65;

const DEG_PER_H: f64 = std::f64::consts::PI / 180.0 / 3600.0;

/// One µg in m/s², rounded once: a value in µg converts with a single
/// rounding, so every decimal in m/s² has a µg value that converts to it
/// exactly (15 mGal = 1.5e-4 m/s² is 15.295743194668921 µg).
const UG: f64 = 1e-6 * G0;

/// IMU error magnitudes (all 1σ, SI units), per axis, identical on the three
/// axes.
///
/// - `*_bias`: turn-on bias, a random constant.
/// - `gyro_arw`, `accel_vrw`: white noise densities of the rates.
/// - `*_markov_sigma`, `*_markov_tau`: a first-order Gauss-Markov bias
///   (steady-state σ, correlation time); `tau = ∞` or `sigma = 0` means none.
/// - `*_scale`: scale-factor error (ratio, 1e-6 = 1 ppm).
///
/// ```
/// use kestrel_nav::ImuSpec;
/// // The SPAN-FSAS figures of paper 002.
/// let s = ImuSpec::perfect()
///     .with_gyro_bias_deg_per_h(0.75)
///     .with_gyro_arw_deg_per_sqrt_h(0.1)
///     .with_accel_bias_mg(1.0)
///     .with_accel_vrw_ug_per_sqrt_hz(50.0);
/// assert!((s.gyro_arw - 0.1_f64.to_radians() / 60.0).abs() < 1e-15);
/// assert!((s.accel_vrw - 50e-6 * 9.80665).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSpec {
    /// Gyro constant bias, rad/s.
    pub gyro_bias: f64,
    /// Gyro angle random walk, rad/√s.
    pub gyro_arw: f64,
    /// Gyro Gauss-Markov bias steady-state σ, rad/s.
    pub gyro_markov_sigma: f64,
    /// Gyro Gauss-Markov correlation time, s.
    pub gyro_markov_tau: f64,
    /// Accelerometer constant bias, m/s².
    pub accel_bias: f64,
    /// Accelerometer velocity random walk, m/s/√s.
    pub accel_vrw: f64,
    /// Accelerometer Gauss-Markov bias steady-state σ, m/s².
    pub accel_markov_sigma: f64,
    /// Accelerometer Gauss-Markov correlation time, s.
    pub accel_markov_tau: f64,
    /// Gyro scale-factor error, ratio.
    pub gyro_scale: f64,
    /// Accelerometer scale-factor error, ratio.
    pub accel_scale: f64,
    /// Gyro bias random walk (rate random walk) density, rad/s/√s: the
    /// bias model when there is no Gauss-Markov one.
    pub gyro_bias_rw: f64,
    /// Accelerometer bias random walk density, m/s²/√s.
    pub accel_bias_rw: f64,
}

impl Default for ImuSpec {
    fn default() -> Self {
        Self::perfect()
    }
}

impl ImuSpec {
    /// An error-free IMU (all zero; infinite correlation times).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::ImuSpec::perfect().gyro_arw, 0.0);
    /// ```
    pub const fn perfect() -> Self {
        Self {
            gyro_bias: 0.0,
            gyro_arw: 0.0,
            gyro_markov_sigma: 0.0,
            gyro_markov_tau: f64::INFINITY,
            accel_bias: 0.0,
            accel_vrw: 0.0,
            accel_markov_sigma: 0.0,
            accel_markov_tau: f64::INFINITY,
            gyro_scale: 0.0,
            accel_scale: 0.0,
            gyro_bias_rw: 0.0,
            accel_bias_rw: 0.0,
        }
    }

    /// Gyro constant bias in °/h.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_gyro_bias_deg_per_h(3600.0);
    /// assert!((s.gyro_bias - 1f64.to_radians()).abs() < 1e-15);
    /// ```
    pub const fn with_gyro_bias_deg_per_h(mut self, deg_per_h: f64) -> Self {
        self.gyro_bias = deg_per_h * DEG_PER_H;
        self
    }

    /// Gyro angle random walk in °/√h.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(60.0);
    /// assert!((s.gyro_arw - 1f64.to_radians()).abs() < 1e-15);
    /// ```
    pub const fn with_gyro_arw_deg_per_sqrt_h(mut self, deg_per_sqrt_h: f64) -> Self {
        // 1 °/√h = (π/180) rad / √(3600 s) = (π/180)/60 rad/√s.
        self.gyro_arw = deg_per_sqrt_h * std::f64::consts::PI / 180.0 / 60.0;
        self
    }

    /// Gyro Gauss-Markov bias: steady-state σ in °/h and correlation time in s.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_gyro_markov_deg_per_h(0.005, 3600.0);
    /// assert_eq!(s.gyro_markov_tau, 3600.0);
    /// ```
    pub const fn with_gyro_markov_deg_per_h(mut self, sigma_deg_per_h: f64, tau_s: f64) -> Self {
        self.gyro_markov_sigma = sigma_deg_per_h * DEG_PER_H;
        self.gyro_markov_tau = tau_s;
        self
    }

    /// Accelerometer constant bias in µg.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_bias_ug(100.0);
    /// assert!((s.accel_bias - 100e-6 * 9.80665).abs() < 1e-18);
    /// ```
    pub const fn with_accel_bias_ug(mut self, ug: f64) -> Self {
        self.accel_bias = ug * UG;
        self
    }

    /// Accelerometer constant bias in mg.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_bias_mg(1.0);
    /// assert!((s.accel_bias - 1e-3 * 9.80665).abs() < 1e-18);
    /// ```
    pub const fn with_accel_bias_mg(mut self, mg: f64) -> Self {
        self.accel_bias = mg * 1e-3 * G0;
        self
    }

    /// Accelerometer velocity random walk in m/s/√h.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_vrw_m_s_per_sqrt_h(0.6);
    /// assert!((s.accel_vrw - 0.01).abs() < 1e-15);
    /// ```
    pub const fn with_accel_vrw_m_s_per_sqrt_h(mut self, m_s_per_sqrt_h: f64) -> Self {
        self.accel_vrw = m_s_per_sqrt_h / 60.0;
        self
    }

    /// Accelerometer white noise density in µg/√Hz (numerically equal to
    /// µg·√s, so it converts to m/s/√s by the factor `1e-6 g₀`).
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_vrw_ug_per_sqrt_hz(50.0);
    /// assert!((s.accel_vrw - 4.903325e-4).abs() < 1e-15);
    /// ```
    pub const fn with_accel_vrw_ug_per_sqrt_hz(mut self, ug_per_sqrt_hz: f64) -> Self {
        self.accel_vrw = ug_per_sqrt_hz * 1e-6 * G0;
        self
    }

    /// Accelerometer Gauss-Markov bias: steady-state σ in µg and correlation
    /// time in s.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_markov_ug(50.0, 1800.0);
    /// assert!((s.accel_markov_sigma - 50e-6 * 9.80665).abs() < 1e-18);
    /// ```
    pub const fn with_accel_markov_ug(mut self, sigma_ug: f64, tau_s: f64) -> Self {
        self.accel_markov_sigma = sigma_ug * UG;
        self.accel_markov_tau = tau_s;
        self
    }

    /// Gyro scale-factor error in ppm.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_gyro_scale_ppm(500.0);
    /// assert!((s.gyro_scale - 5e-4).abs() < 1e-18);
    /// ```
    pub const fn with_gyro_scale_ppm(mut self, ppm: f64) -> Self {
        self.gyro_scale = ppm * 1e-6;
        self
    }

    /// Accelerometer scale-factor error in ppm.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_scale_ppm(3000.0);
    /// assert!((s.accel_scale - 3e-3).abs() < 1e-18);
    /// ```
    pub const fn with_accel_scale_ppm(mut self, ppm: f64) -> Self {
        self.accel_scale = ppm * 1e-6;
        self
    }

    /// Gyro bias random walk (rate random walk) in °/h/√h, the datasheet
    /// unit.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_gyro_bias_rw_deg_per_h_per_sqrt_h(60.0);
    /// // 60 °/h/√h = 1 °/h/√s.
    /// assert!((s.gyro_bias_rw - 1f64.to_radians() / 3600.0).abs() < 1e-18);
    /// ```
    pub const fn with_gyro_bias_rw_deg_per_h_per_sqrt_h(mut self, x: f64) -> Self {
        self.gyro_bias_rw = x * (core::f64::consts::PI / 180.0) / 3600.0 / 60.0;
        self
    }

    /// Accelerometer bias random walk in µg/√h.
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_accel_bias_rw_ug_per_sqrt_h(60.0);
    /// assert!((s.accel_bias_rw - 1e-6 * 9.80665).abs() < 1e-18);
    /// ```
    pub const fn with_accel_bias_rw_ug_per_sqrt_h(mut self, x: f64) -> Self {
        self.accel_bias_rw = x * 1e-6 * G0 / 60.0;
        self
    }

    /// Whether the gyro has a Gauss-Markov bias (σ > 0 and a finite,
    /// positive correlation time).
    ///
    /// ```
    /// let s = kestrel_nav::ImuSpec::perfect().with_gyro_markov_deg_per_h(0.01, 3600.0);
    /// assert!(s.has_gyro_markov() && !s.has_accel_markov());
    /// ```
    pub fn has_gyro_markov(&self) -> bool {
        markov(self.gyro_markov_sigma, self.gyro_markov_tau)
    }

    /// Whether the accelerometer has a Gauss-Markov bias.
    ///
    /// ```
    /// assert!(!kestrel_nav::ImuSpec::perfect().has_accel_markov());
    /// ```
    pub fn has_accel_markov(&self) -> bool {
        markov(self.accel_markov_sigma, self.accel_markov_tau)
    }
}

fn markov(sigma: f64, tau: f64) -> bool {
    sigma > 0.0 && tau > 0.0 && tau.is_finite()
}
