//! Attitude, velocity and position from an external reference (m = 9).

use kestrel_core::Real;
use nalgebra::{Matrix3, SMatrix, SVector, UnitQuaternion, Vector3};

use super::context::InsContext;
use super::difference::ErrorMeasurement;
use super::gnss::{position_rows, velocity_rows, GnssAntenna, GnssFix};
use super::layout::{fits, ErrorLayout};
use crate::attitude::attitude_error;

/// An attitude reading `C_b^n` with its standard deviation per NED axis of
/// the attitude error (rad).
///
/// ```
/// use kestrel_nav::{Euler, nalgebra::Vector3};
/// use kestrel_nav::measurement::AttitudeFix;
/// let a = AttitudeFix::new(1.0, Euler::from_degrees(0.0, 0.0, 45.0).to_quaternion(),
///     Vector3::repeat(0.01_f64.to_radians()));
/// assert!(a.std.x > 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeFix {
    /// Time of validity, s.
    pub time: f64,
    /// The reference `C_b^n`.
    pub att: UnitQuaternion<f64>,
    /// Standard deviation of the attitude error about north, east, down, rad.
    pub std: Vector3<f64>,
}

impl AttitudeFix {
    /// A reading at `time` (s) of the attitude `att` with the standard
    /// deviations `std` of its error about north, east, down (rad).
    ///
    /// ```
    /// use kestrel_nav::nalgebra::{UnitQuaternion, Vector3};
    /// let a = kestrel_nav::measurement::AttitudeFix::new(2.0, UnitQuaternion::identity(),
    ///     Vector3::repeat(1e-3));
    /// assert_eq!((a.time, a.std.z), (2.0, 1e-3));
    /// ```
    pub fn new(time: f64, att: UnitQuaternion<f64>, std: Vector3<f64>) -> Self {
        Self { time, att, std }
    }
}

impl GnssAntenna {
    /// Attitude, velocity and position, `z = [φ; v_INS − v_ref; r_INS − r_ref]`
    /// (m = 9), `R = diag(att_std², vel_std², pos_std²)`.
    ///
    /// A reference system (a master INS, a multi-antenna GNSS attitude solution)
    /// gives the attitude `C_b^n(ref)` as well as a GNSS-like position and
    /// velocity at the antenna. The attitude part of `z` is the rotation vector
    ///
    /// ```text
    /// z_φ = φ with C_b^n(INS) = exp(−[φ×]) C_b^n(ref)
    /// ```
    ///
    /// (the crate's attitude-error definition, exact at any size), so its rows
    /// of `H` are `[I 0 0 …]`; velocity and position rows are those of
    /// [`position_velocity`](Self::position_velocity) with the same lever arm
    /// (NaN velocity rows for a fix without velocity). Row order
    /// follows paper 004: attitude (0..3), velocity (3..6), position (6..9).
    ///
    /// ```
    /// use kestrel_core::nalgebra::Vector3;
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::engine::Ins18;
    /// use kestrel_nav::measurement::{AttitudeFix, GnssAntenna, GnssFix, InsContext};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(32.3, 118.5, 1000.0),
    ///     Vector3::zeros(), Euler::from_degrees(0.0, 0.0, 45.0));
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// // The INS yaw is 0.1° smaller than the reference's: φ_D = +0.1°.
    /// let att = AttitudeFix::new(0.0, Euler::from_degrees(0.0, 0.0, 45.1).to_quaternion(),
    ///     Vector3::repeat(1e-3));
    /// let fix = GnssFix::new(0.0, nav.pos, Vector3::zeros());
    /// let m = GnssAntenna::new(Vector3::zeros()).attitude_velocity_position::<f64, 18, _>(
    ///     &Ins18::new(ImuSpec::perfect()), &ins, &att, &fix);
    /// assert!((m.z()[2] - 0.1_f64.to_radians()).abs() < 1e-9);
    /// ```
    pub fn attitude_velocity_position<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        _layout: &L,
        ins: &InsContext,
        att: &AttitudeFix,
        fix: &GnssFix,
    ) -> ErrorMeasurement<T, N, 9> {
        const { assert!(fits::<N, L>(), "error layout does not fit the state") };
        let mut h = SMatrix::<f64, 9, N>::zeros();
        h.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        let (zv, hv) = velocity_rows::<N, L>(ins, &self.lever_arm, &fix.vel);
        let (zr, hr) = position_rows::<N>(ins, &self.lever_arm, &fix.pos);
        h.fixed_rows_mut::<3>(3).copy_from(&hv);
        h.fixed_rows_mut::<3>(6).copy_from(&hr);
        let mut z = SVector::<f64, 9>::zeros();
        z.fixed_rows_mut::<3>(0)
            .copy_from(&attitude_error(&ins.state.att, &att.att));
        z.fixed_rows_mut::<3>(3).copy_from(&zv);
        z.fixed_rows_mut::<3>(6).copy_from(&zr);
        let mut var = SVector::<f64, 9>::zeros();
        var.fixed_rows_mut::<3>(0)
            .copy_from(&att.std.component_mul(&att.std));
        var.fixed_rows_mut::<3>(3)
            .copy_from(&fix.vel_std.component_mul(&fix.vel_std));
        var.fixed_rows_mut::<3>(6)
            .copy_from(&fix.pos_std.component_mul(&fix.pos_std));
        ErrorMeasurement::new(z, h, var)
    }
}
