//! The INS side of a measurement.

use nalgebra::Vector3;

use crate::attitude::rotation_vector_to_quaternion;
use crate::earth::Ellipsoid;
use crate::state::NavState;

/// What every measurement model needs from the inertial solution: the
/// navigation state at the measurement time, the Earth model, and the
/// bias-corrected body angular rate `ω_ib^b` (rad/s) for lever-arm velocities.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
/// use kestrel_nav::measurement::InsContext;
/// let nav = NavState::new(10.0, Geodetic::from_degrees(30.0, 114.0, 0.0),
///     Vector3::new(10.0, 0.0, 0.0), Euler::default());
/// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
/// assert_eq!(ins.state.time, 10.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct InsContext {
    /// The Earth model of the navigation solution.
    pub earth: Ellipsoid,
    /// The navigation solution at the measurement time.
    pub state: NavState,
    /// The bias-corrected body angular rate, rad/s.
    pub omega_ib: Vector3<f64>,
}

impl InsContext {
    /// A context from its parts.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_nav::measurement::InsContext;
    /// let nav = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::z());
    /// assert_eq!(ins.omega_ib.z, 1.0);
    /// ```
    pub fn new(earth: Ellipsoid, state: NavState, omega_ib: Vector3<f64>) -> Self {
        Self {
            earth,
            state,
            omega_ib,
        }
    }

    /// The context moved forward by `dt` seconds (either sign, meant for
    /// less than one IMU period) at constant NED acceleration `accel_ned`
    /// (m/s²) and body rate: position by `v dt + a dt²/2`, velocity by
    /// `a dt`, attitude by the body rotation `ω dt`. This aligns an aiding
    /// epoch that falls between two IMU samples with the INS solution to
    /// first order; the neglected Earth and transport rotation over one IMU
    /// period is below 1e-8 rad.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_nav::measurement::InsContext;
    /// let e = Ellipsoid::wgs84();
    /// let nav = NavState::new(1.0, Geodetic::from_degrees(30.0, 114.0, 0.0),
    ///     Vector3::new(20.0, 0.0, 0.0), Euler::default());
    /// let later = InsContext::new(e, nav, Vector3::zeros())
    ///     .extrapolated(0.004, &Vector3::new(1.0, 0.0, 0.0));
    /// assert!((later.state.time - 1.004).abs() < 1e-12);
    /// assert!((later.state.vel.x - 20.004).abs() < 1e-12);
    /// let moved = e.ned_offset(&nav.pos, &later.state.pos);
    /// assert!((moved.x - (0.08 + 0.5 * 0.004 * 0.004)).abs() < 1e-8);
    /// ```
    pub fn extrapolated(&self, dt: f64, accel_ned: &Vector3<f64>) -> Self {
        if dt == 0.0 {
            return *self;
        }
        let s = &self.state;
        let mut state = *s;
        state.time = s.time + dt;
        state.pos = self
            .earth
            .displace(&s.pos, &(s.vel * dt + accel_ned * (0.5 * dt * dt)));
        state.vel = s.vel + accel_ned * dt;
        state.att = s.att * rotation_vector_to_quaternion(&(self.omega_ib * dt));
        Self { state, ..*self }
    }

    /// `C_b^n` as a rotation matrix.
    pub(crate) fn c_bn(&self) -> nalgebra::Matrix3<f64> {
        self.state.att.to_rotation_matrix().into_inner()
    }
}
