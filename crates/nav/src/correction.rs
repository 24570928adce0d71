//! Closed-loop feedback: removing estimated errors from the navigation
//! solution and the IMU, and measuring the error between two solutions.

use kestrel_core::Real;
use nalgebra::{SVector, Vector3};

use crate::attitude::{attitude_error, correct_attitude};
use crate::earth::Ellipsoid;
use crate::error_model::{ins15, ins18};
use crate::imu::ImuIncrement;
use crate::state::NavState;
use kestrel_core::real::to_f64;

/// Navigation errors `[φ, δv, δr]` with the definitions of
/// [`error_model`](crate::error_model): attitude (NED, rad), velocity
/// (NED, m/s), position (NED displacement from true to computed, m).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavError, NavState, nalgebra::Vector3};
/// let earth = Ellipsoid::wgs84();
/// let truth = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 10.0),
///     Vector3::new(5.0, 0.0, 0.0), Euler::from_degrees(1.0, 2.0, 30.0));
/// let err = NavError {
///     phi: Vector3::new(1e-3, -2e-3, 5e-3),
///     dv: Vector3::new(0.1, -0.2, 0.05),
///     dr: Vector3::new(3.0, -4.0, 1.0),
/// };
/// let computed = err.apply(&earth, &truth);
/// let back = NavError::between(&earth, &computed, &truth);
/// // ECEF coordinates round to ~1e-9 m.
/// assert!((back.to_vector() - err.to_vector()).norm() < 1e-8);
/// let fixed = err.correct(&earth, &computed);
/// assert!(fixed.att.angle_to(&truth.att) < 1e-15);
/// assert!(earth.ned_offset(&truth.pos, &fixed.pos).norm() < 1e-4);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NavError {
    /// Attitude error φ, NED, rad.
    pub phi: Vector3<f64>,
    /// Velocity error δv, NED, m/s.
    pub dv: Vector3<f64>,
    /// Position error δr, NED, m.
    pub dr: Vector3<f64>,
}

impl NavError {
    /// The first nine components `[φ, δv, δr]` of an error state
    /// (any model of this crate; `N ≥ 9` is checked at compile time).
    ///
    /// ```
    /// use kestrel_nav::{NavError, nalgebra::SVector};
    /// let x = SVector::<f32, 15>::from_fn(|i, _| i as f32);
    /// let e = NavError::from_error_state(&x);
    /// assert_eq!((e.phi.x, e.dv.x, e.dr.z), (0.0, 3.0, 8.0));
    /// ```
    pub fn from_error_state<T: Real, const N: usize>(x: &SVector<T, N>) -> Self {
        const { assert!(N >= 9, "an error state holds at least [φ, δv, δr]") };
        let v = |i: usize| Vector3::new(to_f64(x[i]), to_f64(x[i + 1]), to_f64(x[i + 2]));
        Self {
            phi: v(ins15::ATT),
            dv: v(ins15::VEL),
            dr: v(ins15::POS),
        }
    }

    /// The errors as one vector `[φ, δv, δr]`.
    ///
    /// ```
    /// let v = kestrel_nav::NavError::default().to_vector();
    /// assert_eq!(v.len(), 9);
    /// ```
    pub fn to_vector(&self) -> SVector<f64, 9> {
        let mut v = SVector::<f64, 9>::zeros();
        v.fixed_rows_mut::<3>(0).copy_from(&self.phi);
        v.fixed_rows_mut::<3>(3).copy_from(&self.dv);
        v.fixed_rows_mut::<3>(6).copy_from(&self.dr);
        v
    }

    /// The error of `computed` with respect to `truth` (exact for the
    /// attitude, chord through ECEF for the position, expressed in the NED
    /// frame at the true position).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavError, NavState, nalgebra::Vector3};
    /// let earth = Ellipsoid::wgs84();
    /// let t = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// let c = NavState { vel: Vector3::new(0.0, 0.2, 0.0), ..t };
    /// assert_eq!(NavError::between(&earth, &c, &t).dv.y, 0.2);
    /// ```
    pub fn between(earth: &Ellipsoid, computed: &NavState, truth: &NavState) -> Self {
        Self {
            phi: attitude_error(&computed.att, &truth.att),
            dv: computed.vel - truth.vel,
            dr: earth.ned_offset(&truth.pos, &computed.pos),
        }
    }

    /// `truth` with these errors added (the computed solution they describe).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavError, NavState, nalgebra::Vector3};
    /// let earth = Ellipsoid::wgs84();
    /// let t = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// let e = NavError { dr: Vector3::new(0.0, 0.0, 2.0), ..Default::default() };
    /// assert!((e.apply(&earth, &t).pos.h + 2.0).abs() < 1e-8);
    /// ```
    pub fn apply(&self, earth: &Ellipsoid, truth: &NavState) -> NavState {
        let phi = -self.phi;
        NavState {
            time: truth.time,
            pos: earth.displace(&truth.pos, &self.dr),
            vel: truth.vel + self.dv,
            att: correct_attitude(&truth.att, &phi),
        }
    }

    /// `computed` with these errors removed: `C ← exp([φ×]) C`,
    /// `v ← v − δv`, position displaced by `−δr` (the feedback correction).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavError, NavState, nalgebra::Vector3};
    /// let earth = Ellipsoid::wgs84();
    /// let c = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
    /// let e = NavError { dv: Vector3::new(0.1, 0.0, 0.0), ..Default::default() };
    /// assert_eq!(e.correct(&earth, &c).vel.x, -0.1);
    /// ```
    pub fn correct(&self, earth: &Ellipsoid, computed: &NavState) -> NavState {
        NavState {
            time: computed.time,
            pos: earth.displace(&computed.pos, &(-self.dr)),
            vel: computed.vel - self.dv,
            att: correct_attitude(&computed.att, &self.phi),
        }
    }
}

/// Estimated IMU biases, subtracted from every increment before the
/// mechanisation (`measured = true + bias`).
///
/// ```
/// use kestrel_nav::{ImuBiases, ImuIncrement, nalgebra::Vector3};
/// let b = ImuBiases { gyro: Vector3::new(1e-4, 0.0, 0.0), accel: Vector3::new(0.0, 0.0, 0.01),
///     ..Default::default() };
/// let raw = ImuIncrement::from_rates(0.01, 0.01, Vector3::new(1e-4, 0.0, 0.0), Vector3::zeros());
/// let c = b.compensate(&raw);
/// assert_eq!(c.dtheta.x, 0.0);
/// assert!((c.dvel.z + 1e-4).abs() < 1e-18);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuBiases {
    /// Gyro bias, body, rad/s.
    pub gyro: Vector3<f64>,
    /// Accelerometer bias, body, m/s².
    pub accel: Vector3<f64>,
    /// Gyro scale-factor error per body axis, ratio (`measured = (1 + s) ·
    /// true + bias`).
    pub gyro_scale: Vector3<f64>,
    /// Accelerometer scale-factor error per body axis, ratio.
    pub accel_scale: Vector3<f64>,
}

impl ImuBiases {
    /// The increment with the biases removed and the scale factors divided
    /// out: `true = (measured − bias) / (1 + s)` per axis.
    ///
    /// ```
    /// use kestrel_nav::{ImuBiases, ImuIncrement, nalgebra::Vector3};
    /// let raw = ImuIncrement::from_rates(1.0, 0.5, Vector3::x(), Vector3::y());
    /// assert_eq!(ImuBiases::default().compensate(&raw), raw);
    /// let b = ImuBiases { gyro_scale: Vector3::repeat(1e-3), ..Default::default() };
    /// assert!((b.compensate(&raw).dtheta.x - 0.5 / 1.001).abs() < 1e-15);
    /// ```
    pub fn compensate(&self, imu: &ImuIncrement) -> ImuIncrement {
        let unscale = |v: Vector3<f64>, s: &Vector3<f64>| {
            if *s == Vector3::zeros() {
                v
            } else {
                v.component_div(&s.add_scalar(1.0))
            }
        };
        ImuIncrement {
            dtheta: unscale(imu.dtheta - self.gyro * imu.dt, &self.gyro_scale),
            dvel: unscale(imu.dvel - self.accel * imu.dt, &self.accel_scale),
            ..*imu
        }
    }
}

/// Feeds a 15-state estimate `[φ, δv, δr, b_g, b_a]` back: corrects `state`
/// and adds the bias errors to `biases`. The caller then resets the filter
/// state to zero.
///
/// ```
/// use kestrel_nav::{feedback_ins15, Ellipsoid, Euler, Geodetic, ImuBiases, NavState,
///     nalgebra::{SVector, Vector3}};
/// let earth = Ellipsoid::wgs84();
/// let mut s = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let mut b = ImuBiases::default();
/// let mut dx = SVector::<f64, 15>::zeros();
/// dx[9] = 1e-5;
/// dx[5] = 0.5;
/// feedback_ins15(&earth, &mut s, &mut b, &dx);
/// assert_eq!((b.gyro.x, s.vel.z), (1e-5, -0.5));
/// ```
pub fn feedback_ins15<T: Real>(
    earth: &Ellipsoid,
    state: &mut NavState,
    biases: &mut ImuBiases,
    dx: &SVector<T, 15>,
) {
    *state = NavError::from_error_state(dx).correct(earth, state);
    biases.gyro += sub3(dx, ins15::GYRO_BIAS);
    biases.accel += sub3(dx, ins15::ACCEL_BIAS);
}

/// Feeds an 18-state estimate `[φ, δv, δr, ε_c, ε_r, ∇]` back: corrects
/// `state`, adds `ε_c + ε_r` to the gyro bias and `∇` to the accelerometer
/// bias. The Markov part of the fed-back gyro estimate is held constant
/// between feedbacks (the model lets it decay with `τ`; the difference per
/// interval is `Δt/τ` of the estimate, negligible for `τ` of an hour).
///
/// ```
/// use kestrel_nav::{feedback_ins18, Ellipsoid, Euler, Geodetic, ImuBiases, NavState,
///     nalgebra::{SVector, Vector3}};
/// let earth = Ellipsoid::wgs84();
/// let mut s = NavState::new(0.0, Geodetic::new(0.5, 0.0, 0.0), Vector3::zeros(), Euler::default());
/// let mut b = ImuBiases::default();
/// let mut dx = SVector::<f64, 18>::zeros();
/// dx[9] = 1e-5;
/// dx[12] = 2e-5;
/// dx[17] = 1e-3;
/// feedback_ins18(&earth, &mut s, &mut b, &dx);
/// assert!((b.gyro.x - 3e-5).abs() < 1e-20 && b.accel.z == 1e-3);
/// ```
pub fn feedback_ins18<T: Real>(
    earth: &Ellipsoid,
    state: &mut NavState,
    biases: &mut ImuBiases,
    dx: &SVector<T, 18>,
) {
    *state = NavError::from_error_state(dx).correct(earth, state);
    biases.gyro += sub3(dx, ins18::GYRO_CONST) + sub3(dx, ins18::GYRO_MARKOV);
    biases.accel += sub3(dx, ins18::ACCEL_BIAS);
}

fn sub3<T: Real, const N: usize>(x: &SVector<T, N>, i: usize) -> Vector3<f64> {
    Vector3::new(to_f64(x[i]), to_f64(x[i + 1]), to_f64(x[i + 2]))
}
