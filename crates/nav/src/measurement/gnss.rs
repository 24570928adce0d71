//! GNSS position and velocity with an antenna lever arm.

use kestrel_core::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::context::InsContext;
use super::difference::ErrorMeasurement;
use super::layout::{fits, ErrorLayout};
use crate::attitude::skew;
use crate::geodetic::Geodetic;

/// One GNSS solution at the antenna: position, NED velocity (if the
/// receiver outputs one) and their standard deviations. Fixes without
/// velocity serve [`GnssAntenna::position`]; the velocity rows of the other
/// builders are then NaN, which every filter refuses.
///
/// ```
/// use kestrel_nav::{Geodetic, nalgebra::Vector3};
/// use kestrel_nav::measurement::GnssFix;
/// let fix = GnssFix::new(1.0, Geodetic::from_degrees(30.0, 114.0, 20.0), Vector3::zeros())
///     .with_std(Vector3::new(3.0, 3.0, 5.0), Vector3::repeat(0.1));
/// assert_eq!(fix.pos_std.z, 5.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GnssFix {
    /// Time of validity, s.
    pub time: f64,
    /// Antenna position.
    pub pos: Geodetic,
    /// Antenna velocity north, east, down, m/s; `None` from a
    /// position-only receiver.
    pub vel: Option<Vector3<f64>>,
    /// Position standard deviation north, east, down, m.
    pub pos_std: Vector3<f64>,
    /// Velocity standard deviation north, east, down, m/s (unused without
    /// a velocity).
    pub vel_std: Vector3<f64>,
}

impl GnssFix {
    /// A fix with standard deviations of 1 m and 0.1 m/s (set them with
    /// [`with_std`](Self::with_std)).
    ///
    /// ```
    /// use kestrel_nav::{Geodetic, nalgebra::Vector3};
    /// let fix = kestrel_nav::measurement::GnssFix::new(2.0, Geodetic::new(0.5, 2.0, 0.0),
    ///     Vector3::x());
    /// assert_eq!((fix.vel, fix.vel_std.x), (Some(Vector3::x()), 0.1));
    /// ```
    pub fn new(time: f64, pos: Geodetic, vel: Vector3<f64>) -> Self {
        Self {
            time,
            pos,
            vel: Some(vel),
            pos_std: Vector3::repeat(1.0),
            vel_std: Vector3::repeat(0.1),
        }
    }

    /// A fix without velocity, position σ 1 m (set it with
    /// [`with_std`](Self::with_std)).
    ///
    /// ```
    /// use kestrel_nav::Geodetic;
    /// let fix = kestrel_nav::measurement::GnssFix::position_only(2.0, Geodetic::new(0.5, 2.0, 0.0));
    /// assert!(fix.vel.is_none());
    /// ```
    pub fn position_only(time: f64, pos: Geodetic) -> Self {
        Self {
            vel: None,
            ..Self::new(time, pos, Vector3::zeros())
        }
    }

    /// The same fix with position (m) and velocity (m/s) standard deviations,
    /// north, east, down.
    ///
    /// ```
    /// use kestrel_nav::{Geodetic, nalgebra::Vector3};
    /// let fix = kestrel_nav::measurement::GnssFix::new(0.0, Geodetic::new(0.5, 2.0, 0.0),
    ///     Vector3::zeros()).with_std(Vector3::repeat(5.0), Vector3::repeat(0.3));
    /// assert_eq!(fix.pos_std.x, 5.0);
    /// ```
    pub fn with_std(self, pos_std: Vector3<f64>, vel_std: Vector3<f64>) -> Self {
        Self {
            pos_std,
            vel_std,
            ..self
        }
    }
}

/// A GNSS antenna at `lever_arm` (body axes forward-right-down, m, from the
/// IMU to the antenna phase centre): builds the per-epoch GNSS measurements.
///
/// With `C = C_b^n` of the INS, `l` the lever arm (body, IMU to antenna
/// phase centre), `ω = ω_ib^b` the bias-corrected body rate and `ω_ie`
/// the Earth rate (NED), the INS predicts the antenna at
///
/// ```text
/// r_ant = r + C l,        v_ant = v + C (ω × l) − ω_ie × (C l)
/// ```
///
/// (the velocity is `v + C (ω_eb × l)`, the antenna's motion relative to
/// the Earth, with `ω_eb = ω − Cᵀ ω_ie`)
///
/// and the measurement is `z = INS − GNSS` (position as the NED offset from
/// the GNSS fix to the INS antenna, m; velocity NED, m/s). Differentiating
/// with the crate's error definitions (`C̃ = (I − [φ×]) C`, `ω̃ = ω + b_g`)
/// gives, to first order,
///
/// ```text
/// z_r = δr + [(C l)×] φ
/// z_v = δv + ([(C (ω × l))×] − [ω_ie×][(C l)×]) φ − C [l×] b_g
/// ```
///
/// so `H` has `[(C l)×]` and `I` in the attitude and position columns of the
/// position rows; the velocity rows have the attitude block above, `I` for
/// δv and `−C [l×]` in every gyro-error block of the layout. The dependence
/// of `ω_ie` on the latitude error (1e-11 per metre of position error and
/// of lever arm) is neglected.
///
/// ```
/// use kestrel_core::Ekf;
/// use kestrel_core::nalgebra::{SMatrix, SVector, Vector3};
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
/// use kestrel_nav::engine::Ins15;
/// use kestrel_nav::measurement::{GnssAntenna, GnssFix, InsContext};
///
/// let nav = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
///     Euler::default());
/// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
/// // The GNSS fix is 3 m north of the INS antenna position.
/// let antenna = GnssAntenna::new(Vector3::new(0.0, 0.0, -1.0));
/// let above = Ellipsoid::wgs84().displace(&nav.pos, &Vector3::new(3.0, 0.0, -1.0));
/// let fix = GnssFix::new(0.0, above, Vector3::zeros());
/// let m = antenna.position_velocity::<f64, 15, _>(&Ins15::new(ImuSpec::perfect()), &ins, &fix);
/// assert!((m.z()[0] + 3.0).abs() < 1e-6);
/// // Attitude known to 1e-2 rad, position to 10 m.
/// let mut p0 = SMatrix::<f64, 15, 15>::identity() * 1e-4;
/// (6..9).for_each(|i| p0[(i, i)] = 100.0);
/// let mut kf = Ekf::new(SVector::<f64, 15>::zeros(), p0).unwrap();
/// kf.update(&m, &m.z()).unwrap();
/// assert!(kf.state()[6] < -2.9); // INS north too small: δr_N ≈ −3 m
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GnssAntenna {
    /// IMU to antenna phase centre, body axes, m.
    pub lever_arm: Vector3<f64>,
}

impl GnssAntenna {
    /// An antenna at `lever_arm` (body, m).
    ///
    /// ```
    /// let a = kestrel_nav::measurement::GnssAntenna::new(kestrel_nav::nalgebra::Vector3::z());
    /// assert_eq!(a.lever_arm.z, 1.0);
    /// ```
    pub fn new(lever_arm: Vector3<f64>) -> Self {
        Self { lever_arm }
    }

    /// Position and velocity, `z = [r_INS − r_GNSS; v_INS − v_GNSS]` (m = 6),
    /// `R = diag(pos_std², vel_std²)`. A fix without velocity gives NaN
    /// velocity rows of `z`, which the filters refuse
    /// ([`FilterError::NonFinite`](kestrel_core::FilterError::NonFinite)).
    ///
    /// ```
    /// use kestrel_core::nalgebra::Vector3;
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::engine::Ins15;
    /// use kestrel_nav::measurement::{GnssAntenna, GnssFix, InsContext};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0),
    ///     Vector3::new(1.0, 0.0, 0.0), Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// let fix = GnssFix::new(0.0, nav.pos, Vector3::zeros());
    /// let m = GnssAntenna::new(Vector3::zeros())
    ///     .position_velocity::<f32, 15, _>(&Ins15::new(ImuSpec::perfect()), &ins, &fix);
    /// assert!((m.z()[3] - 1.0).abs() < 1e-6);
    /// assert_eq!(m.h()[(3, 3)], 1.0);
    /// ```
    pub fn position_velocity<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        _layout: &L,
        ins: &InsContext,
        fix: &GnssFix,
    ) -> ErrorMeasurement<T, N, 6> {
        const { assert!(fits::<N, L>(), "error layout does not fit the state") };
        let mut h = SMatrix::<f64, 6, N>::zeros();
        let (zr, hr) = position_rows::<N>(ins, &self.lever_arm, &fix.pos);
        let (zv, hv) = velocity_rows::<N, L>(ins, &self.lever_arm, &fix.vel);
        h.fixed_rows_mut::<3>(0).copy_from(&hr);
        h.fixed_rows_mut::<3>(3).copy_from(&hv);
        let mut z = SVector::<f64, 6>::zeros();
        z.fixed_rows_mut::<3>(0).copy_from(&zr);
        z.fixed_rows_mut::<3>(3).copy_from(&zv);
        let mut var = SVector::<f64, 6>::zeros();
        var.fixed_rows_mut::<3>(0)
            .copy_from(&fix.pos_std.component_mul(&fix.pos_std));
        var.fixed_rows_mut::<3>(3)
            .copy_from(&fix.vel_std.component_mul(&fix.vel_std));
        ErrorMeasurement::new(z, h, var)
    }

    /// Position only, `z = r_INS − r_GNSS` (m = 3, NED m),
    /// `R = diag(pos_std²)`.
    ///
    /// ```
    /// use kestrel_core::nalgebra::Vector3;
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::engine::Ins15;
    /// use kestrel_nav::measurement::{GnssAntenna, GnssFix, InsContext};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    ///     Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// let fix = GnssFix::new(0.0, nav.pos, Vector3::zeros());
    /// // An antenna 2 m forward of the IMU, heading north: INS antenna 2 m north.
    /// let m = GnssAntenna::new(Vector3::new(2.0, 0.0, 0.0))
    ///     .position::<f64, 15, _>(&Ins15::new(ImuSpec::perfect()), &ins, &fix);
    /// assert!((m.z()[0] - 2.0).abs() < 1e-9);
    /// ```
    pub fn position<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        _layout: &L,
        ins: &InsContext,
        fix: &GnssFix,
    ) -> ErrorMeasurement<T, N, 3> {
        const { assert!(fits::<N, L>(), "error layout does not fit the state") };
        let (z, h) = position_rows::<N>(ins, &self.lever_arm, &fix.pos);
        ErrorMeasurement::new(z, h, fix.pos_std.component_mul(&fix.pos_std))
    }
}

/// `r_INS,antenna − r_GNSS` (NED, m) and its rows of `H`.
pub(crate) fn position_rows<const N: usize>(
    ins: &InsContext,
    lever: &Vector3<f64>,
    fix_pos: &Geodetic,
) -> (Vector3<f64>, SMatrix<f64, 3, N>) {
    let cl = ins.c_bn() * lever;
    let z = ins.earth.ned_offset(fix_pos, &ins.state.pos) + cl;
    let mut h = SMatrix::<f64, 3, N>::zeros();
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(&skew(&cl));
    h.fixed_view_mut::<3, 3>(0, 6)
        .copy_from(&Matrix3::identity());
    (z, h)
}

/// `v_INS,antenna − v_GNSS` (NED, m/s; NaN without a GNSS velocity) and its
/// rows of `H`.
pub(crate) fn velocity_rows<const N: usize, L: ErrorLayout<N>>(
    ins: &InsContext,
    lever: &Vector3<f64>,
    fix_vel: &Option<Vector3<f64>>,
) -> (Vector3<f64>, SMatrix<f64, 3, N>) {
    let fix_vel = fix_vel.unwrap_or(Vector3::repeat(f64::NAN));
    let c = ins.c_bn();
    let s = &ins.state;
    let cl = c * lever;
    let cwl = c * ins.omega_ib.cross(lever);
    let w_ie = ins.earth.earth_rate_ned(s.pos.lat);
    let z = s.vel + cwl - w_ie.cross(&cl) - fix_vel;
    let mut h = SMatrix::<f64, 3, N>::zeros();
    h.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(skew(&cwl) - skew(&w_ie) * skew(&cl)));
    h.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&Matrix3::identity());
    let hb = -c * skew(lever);
    for &col in L::GYRO_BIAS {
        h.fixed_view_mut::<3, 3>(0, col).copy_from(&hb);
    }
    (z, h)
}
