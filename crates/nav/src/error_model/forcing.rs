//! Averages of the mechanisation's forcing over a propagation interval.

use nalgebra::{Matrix3, Vector3};

use crate::mechanisation::Strapdown;

/// Time-weighted means of the specific force (NED), the body rate and the
/// attitude matrix `C_b^n` over the IMU steps of one covariance-propagation
/// interval, to linearise an error model once per interval instead of once
/// per IMU sample.
///
/// The mean `C_b^n` (not orthonormal) is what maps constant sensor errors
/// over the interval exactly to first order, `∫ C_b^n dt · b = mean(C) Δt b`;
/// the attitude at either end of an interval would turn their effect by
/// `ω Δt / 2` when the vehicle turns.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState, Strapdown,
///     nalgebra::Vector3};
/// use kestrel_nav::error_model::ForcingMean;
/// let s = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let mut ins = Strapdown::new(Ellipsoid::wgs84(), s);
/// let mut mean = ForcingMean::default();
/// for k in 1..=10 {
///     let imu = ImuIncrement::from_rates(k as f64 * 0.01, 0.01, Vector3::zeros(),
///         Vector3::new(0.0, 0.0, -9.8));
///     ins.step(&imu);
///     mean.add(&ins, imu.dt);
/// }
/// assert!((mean.dt() - 0.1).abs() < 1e-15);
/// assert!((mean.f_ned().z + 9.8).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ForcingMean {
    f_sum: Vector3<f64>,
    w_sum: Vector3<f64>,
    c_sum: Matrix3<f64>,
    /// `Σ C_b^n diag(ω_ib^b) dt` and `Σ C_b^n diag(f^b) dt`: how gyro and
    /// accelerometer scale-factor errors enter over the interval.
    cw_sum: Matrix3<f64>,
    cf_sum: Matrix3<f64>,
    dt: f64,
    /// `C_b^n` after the last added step, kept across [`clear`](Self::clear)
    /// for the trapezoidal mean of the next step.
    last_c: Option<Matrix3<f64>>,
}

impl ForcingMean {
    /// Adds the last step of `ins`, which lasted `dt` seconds.
    ///
    /// ```
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown, nalgebra::Vector3};
    /// # use kestrel_nav::error_model::ForcingMean;
    /// # let s = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut mean = ForcingMean::default();
    /// mean.add(&Strapdown::new(Ellipsoid::wgs84(), s), 0.005);
    /// assert_eq!(mean.dt(), 0.005);
    /// ```
    pub fn add(&mut self, ins: &Strapdown, dt: f64) {
        let c = ins.state().att.to_rotation_matrix().into_inner();
        let start = self.last_c.unwrap_or(c);
        self.f_sum += ins.f_ned() * dt;
        self.w_sum += ins.omega_ib_body() * dt;
        self.c_sum += (start + c) * (0.5 * dt);
        let w = ins.omega_ib_body();
        let f_body = c.transpose() * ins.f_ned();
        self.cw_sum += c * Matrix3::from_diagonal(&w) * dt;
        self.cf_sum += c * Matrix3::from_diagonal(&f_body) * dt;
        self.dt += dt;
        self.last_c = Some(c);
    }

    /// The mean of `C_b^n diag(ω_ib^b)`: the attitude-error rate per unit
    /// gyro scale-factor error (zero when empty).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::error_model::ForcingMean::default().gyro_scale_gain()[(0, 0)], 0.0);
    /// ```
    pub fn gyro_scale_gain(&self) -> Matrix3<f64> {
        if self.dt > 0.0 {
            self.cw_sum / self.dt
        } else {
            Matrix3::zeros()
        }
    }

    /// The mean of `C_b^n diag(f^b)`: the velocity-error rate per unit
    /// accelerometer scale-factor error (zero when empty).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::error_model::ForcingMean::default().accel_scale_gain()[(2, 2)], 0.0);
    /// ```
    pub fn accel_scale_gain(&self) -> Matrix3<f64> {
        if self.dt > 0.0 {
            self.cf_sum / self.dt
        } else {
            Matrix3::zeros()
        }
    }

    /// The accumulated time, s.
    ///
    /// ```
    /// assert_eq!(kestrel_nav::error_model::ForcingMean::default().dt(), 0.0);
    /// ```
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The mean specific force in NED, m/s² (zero when empty).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::error_model::ForcingMean::default().f_ned().z, 0.0);
    /// ```
    pub fn f_ned(&self) -> Vector3<f64> {
        self.mean(&self.f_sum)
    }

    /// The mean body angular rate, rad/s (zero when empty).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::error_model::ForcingMean::default().omega_ib_body().x, 0.0);
    /// ```
    pub fn omega_ib_body(&self) -> Vector3<f64> {
        self.mean(&self.w_sum)
    }

    /// The mean attitude matrix `C_b^n` (trapezoidal over each step; the
    /// identity when empty).
    ///
    /// ```
    /// use kestrel_nav::nalgebra::Matrix3;
    /// assert_eq!(kestrel_nav::error_model::ForcingMean::default().c_bn(), Matrix3::identity());
    /// ```
    pub fn c_bn(&self) -> Matrix3<f64> {
        if self.dt > 0.0 {
            self.c_sum / self.dt
        } else {
            Matrix3::identity()
        }
    }

    /// Starts a new interval (the attitude after the last step is kept as
    /// the start of the next one).
    ///
    /// ```
    /// let mut m = kestrel_nav::error_model::ForcingMean::default();
    /// m.clear();
    /// assert_eq!(m.dt(), 0.0);
    /// ```
    pub fn clear(&mut self) {
        *self = Self {
            last_c: self.last_c,
            ..Self::default()
        };
    }

    fn mean(&self, sum: &Vector3<f64>) -> Vector3<f64> {
        if self.dt > 0.0 {
            sum / self.dt
        } else {
            Vector3::zeros()
        }
    }
}
