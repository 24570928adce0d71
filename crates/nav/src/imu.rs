//! Inertial measurement increments.

use nalgebra::Vector3;

/// One IMU sample as increments over the interval `(time − dt, time]`:
/// integrated angular rate (rad) and integrated specific force (m/s),
/// both in body axes (forward-right-down).
///
/// ```
/// use kestrel_nav::{ImuIncrement, nalgebra::Vector3};
/// let s = ImuIncrement::from_rates(0.01, 0.01, Vector3::new(0.0, 0.0, 0.1),
///     Vector3::new(0.0, 0.0, -9.8));
/// assert!((s.dvel.z + 0.098).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuIncrement {
    /// End of the integration interval, s.
    pub time: f64,
    /// Length of the interval, s.
    pub dt: f64,
    /// Angle increment, rad, body axes.
    pub dtheta: Vector3<f64>,
    /// Velocity increment (integrated specific force), m/s, body axes.
    pub dvel: Vector3<f64>,
}

impl ImuIncrement {
    /// Increments from rates held constant over the interval: angular rate
    /// in rad/s and specific force in m/s².
    ///
    /// ```
    /// use kestrel_nav::{ImuIncrement, nalgebra::Vector3};
    /// let s = ImuIncrement::from_rates(2.0, 0.5, Vector3::x(), Vector3::zeros());
    /// assert_eq!(s.dtheta.x, 0.5);
    /// ```
    pub fn from_rates(
        time: f64,
        dt: f64,
        omega: Vector3<f64>,
        specific_force: Vector3<f64>,
    ) -> Self {
        Self {
            time,
            dt,
            dtheta: omega * dt,
            dvel: specific_force * dt,
        }
    }
}
