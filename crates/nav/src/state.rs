//! The navigation solution.

use nalgebra::{UnitQuaternion, Vector3};

use crate::attitude::Euler;
use crate::geodetic::Geodetic;

/// Position, velocity and attitude at one instant.
///
/// Velocity is in the local NED frame; `att` is the body-to-NED rotation
/// `C_b^n` (body axes forward-right-down). Everything is `f64` (see
/// [`Geodetic`] for why latitude needs it).
///
/// ```
/// use kestrel_nav::{Euler, Geodetic, NavState};
/// use kestrel_nav::nalgebra::Vector3;
/// let s = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 20.0),
///     Vector3::new(10.0, 0.0, 0.0), Euler::from_degrees(0.0, 0.0, 90.0));
/// assert!((s.euler().yaw.to_degrees() - 90.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct NavState {
    /// Time of validity, s.
    pub time: f64,
    /// Geodetic position.
    pub pos: Geodetic,
    /// Velocity north, east, down, m/s.
    pub vel: Vector3<f64>,
    /// Attitude `C_b^n` (body to NED).
    pub att: UnitQuaternion<f64>,
}

impl NavState {
    /// A state from time, position, NED velocity and Euler attitude.
    ///
    /// ```
    /// use kestrel_nav::{Euler, Geodetic, NavState, nalgebra::Vector3};
    /// let s = NavState::new(1.0, Geodetic::new(0.0, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// assert_eq!(s.time, 1.0);
    /// ```
    pub fn new(time: f64, pos: Geodetic, vel: Vector3<f64>, euler: Euler) -> Self {
        Self {
            time,
            pos,
            vel,
            att: euler.to_quaternion(),
        }
    }

    /// The attitude as roll, pitch, yaw.
    ///
    /// ```
    /// use kestrel_nav::{Euler, Geodetic, NavState, nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.0, 0.0, 0.0), Vector3::zeros(),
    ///     Euler::new(0.1, -0.2, 0.3));
    /// assert!((s.euler().pitch + 0.2).abs() < 1e-12);
    /// ```
    pub fn euler(&self) -> Euler {
        Euler::from_quaternion(&self.att)
    }
}
