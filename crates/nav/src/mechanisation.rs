//! Strapdown inertial mechanisation in the local NED frame.
//!
//! One [`Strapdown::step`] per IMU sample, in the structure of Savage's
//! algorithms: velocity, then position, then attitude, each with the
//! Earth-related terms evaluated at the middle of the interval.
//!
//! - Velocity: the body increment is corrected for rotation to second order
//!   (`½ Δθ × Δv + ⅙ Δθ × (Δθ × Δv)`) and for two-sample sculling
//!   (`(Δθ₋ × Δv + Δv₋ × Δθ) / 12`), rotated to NED
//!   with `C_b^n(k−1)` and the half-interval rotation of the NED frame
//!   `(I − ½[ζ×])`, `ζ = (ω_ie + ω_en) Δt`; gravity and Coriolis are added at
//!   the mid-interval position and velocity, extrapolated from the previous
//!   state, the current increment and the previous step's Coriolis
//!   acceleration (every term second-order accurate, so errors fall
//!   fourfold when the rate doubles).
//! - Position: latitude, longitude and height integrated with the mean of
//!   the old and new velocities (trapezoidal rule), curvature radii at the
//!   mid-interval latitude; latitude and longitude are summed with
//!   compensation (their sub-rounding parts are kept inside the navigator).
//! - Attitude: `q(k) = q(−ζ) ⊗ q(k−1) ⊗ q(Δθ + Δθ₋ × Δθ / 12)` (two-sample
//!   coning), `ζ` from the mid-interval position and the mean velocity.
//!
//! Each step costs one `sin_cos` and two square roots; the rotation vectors
//! are converted by series (see [`rotation_vector_to_quaternion`]).
//!
//! Latitude and longitude make the NED frame singular at the poles: the
//! mechanisation is valid away from them (|latitude| below about 89.9°).

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::attitude::rotation_vector_to_quaternion;
use crate::earth::{Ellipsoid, NormalGravity};
use crate::imu::ImuIncrement;
use crate::state::NavState;

/// A strapdown navigator: integrates IMU increments into a [`NavState`].
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState, Strapdown};
/// use kestrel_nav::nalgebra::Vector3;
/// let earth = Ellipsoid::wgs84();
/// let pos = Geodetic::from_degrees(30.0, 114.0, 0.0);
/// let start = NavState::new(0.0, pos, Vector3::new(10.0, 0.0, 0.0), Euler::default());
/// let mut ins = Strapdown::new(earth, start);
/// // Level flight north: the accelerometers feel only the support force.
/// let g = earth.gravity(pos.lat, pos.h);
/// for k in 1..=100 {
///     let imu = ImuIncrement::from_rates(k as f64 * 0.01, 0.01, Vector3::zeros(),
///         Vector3::new(0.0, 0.0, -g));
///     ins.step(&imu);
/// }
/// assert!((ins.state().time - 1.0).abs() < 1e-12);
/// assert!(ins.state().pos.lat > pos.lat);
/// ```
#[derive(Clone, Debug)]
pub struct Strapdown {
    earth: Ellipsoid,
    gravity: NormalGravity,
    e2: f64,
    state: NavState,
    prev_dtheta: Vector3<f64>,
    prev_dvel: Vector3<f64>,
    has_prev: bool,
    /// Coriolis and transport acceleration `(2 ω_ie + ω_en) × v` of the last
    /// step (or of the state set), m/s², to extrapolate the next
    /// mid-interval velocity.
    coriolis: Vector3<f64>,
    /// Meridian radius of the last step (or of the state set), m, to
    /// extrapolate the next mid-interval latitude.
    rm: f64,
    /// Rounding left over from the last latitude and longitude additions
    /// (compensated summation), rad.
    lat_lo: f64,
    lon_lo: f64,
    f_ned: Vector3<f64>,
    omega_ib: Vector3<f64>,
}

impl Strapdown {
    /// A navigator on `earth` starting from `state`.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown, nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let ins = Strapdown::new(Ellipsoid::krasovsky(), s);
    /// assert_eq!(ins.earth().a, 6_378_245.0);
    /// ```
    pub fn new(earth: Ellipsoid, state: NavState) -> Self {
        let mut ins = Self {
            earth,
            gravity: earth.normal_gravity(),
            e2: earth.e2(),
            state,
            prev_dtheta: Vector3::zeros(),
            prev_dvel: Vector3::zeros(),
            has_prev: false,
            coriolis: Vector3::zeros(),
            rm: earth.a,
            lat_lo: 0.0,
            lon_lo: 0.0,
            f_ned: Vector3::zeros(),
            omega_ib: Vector3::zeros(),
        };
        ins.set_state(state);
        ins
    }

    /// The current navigation solution.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown, nalgebra::Vector3};
    /// let s = NavState::new(3.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// assert_eq!(Strapdown::new(Ellipsoid::wgs84(), s).state().time, 3.0);
    /// ```
    pub fn state(&self) -> &NavState {
        &self.state
    }

    /// Mutable access to the navigation solution (feedback correction).
    /// The previous increments used by the coning and sculling corrections
    /// are kept, and so are the Coriolis acceleration and radius the next
    /// step extrapolates with (a correction changes them negligibly) and the
    /// sub-rounding part of latitude and longitude (below one unit in the
    /// last place). Use [`set_state`](Self::set_state) to restart elsewhere.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown, nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut ins = Strapdown::new(Ellipsoid::wgs84(), s);
    /// ins.state_mut().vel.x = 1.0;
    /// assert_eq!(ins.state().vel.x, 1.0);
    /// ```
    pub fn state_mut(&mut self) -> &mut NavState {
        &mut self.state
    }

    /// Replaces the navigation solution, keeping the IMU history; the
    /// Coriolis acceleration and meridian radius used for the next step's
    /// mid-interval extrapolation are recomputed from `state`, and the
    /// sub-rounding part of latitude and longitude carried by the
    /// compensated position summation is cleared.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown, nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut ins = Strapdown::new(Ellipsoid::wgs84(), s);
    /// ins.set_state(NavState { time: 5.0, ..s });
    /// assert_eq!(ins.state().time, 5.0);
    /// ```
    pub fn set_state(&mut self, state: NavState) {
        let e = &self.earth;
        let w =
            2.0 * e.earth_rate_ned(state.pos.lat) + e.transport_rate_ned(&state.pos, &state.vel);
        self.coriolis = w.cross(&state.vel);
        self.rm = e.meridian_radius(state.pos.lat);
        self.state = state;
        self.lat_lo = 0.0;
        self.lon_lo = 0.0;
    }

    /// The Earth model.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, Strapdown, nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// assert_eq!(*Strapdown::new(Ellipsoid::wgs84(), s).earth(), Ellipsoid::wgs84());
    /// ```
    pub fn earth(&self) -> &Ellipsoid {
        &self.earth
    }

    /// The specific force of the last step in NED (rotation- and
    /// sculling-compensated increment over `dt`), m/s². Zero before the first step.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState, Strapdown,
    ///     nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut ins = Strapdown::new(Ellipsoid::wgs84(), s);
    /// ins.step(&ImuIncrement::from_rates(0.01, 0.01, Vector3::zeros(), Vector3::new(0.0, 0.0, -9.8)));
    /// assert!((ins.f_ned().z + 9.8).abs() < 1e-12);
    /// ```
    pub fn f_ned(&self) -> Vector3<f64> {
        self.f_ned
    }

    /// The body angular rate of the last step, `Δθ / dt`, rad/s.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState, Strapdown,
    ///     nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut ins = Strapdown::new(Ellipsoid::wgs84(), s);
    /// ins.step(&ImuIncrement::from_rates(0.01, 0.01, Vector3::new(0.0, 0.0, 0.2), Vector3::zeros()));
    /// assert!((ins.omega_ib_body().z - 0.2).abs() < 1e-15);
    /// ```
    pub fn omega_ib_body(&self) -> Vector3<f64> {
        self.omega_ib
    }

    /// Advances the solution by one IMU sample; the state time becomes
    /// `imu.time`. Samples with `dt ≤ 0` (or not finite) only set the time.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, NavState, Strapdown,
    ///     nalgebra::Vector3};
    /// let s = NavState::new(0.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
    /// let mut ins = Strapdown::new(Ellipsoid::wgs84(), s);
    /// // Free fall: no specific force, so the body accelerates downwards.
    /// ins.step(&ImuIncrement::from_rates(0.01, 0.01, Vector3::zeros(), Vector3::zeros()));
    /// assert!(ins.state().vel.z > 0.09);
    /// ```
    pub fn step(&mut self, imu: &ImuIncrement) {
        let dt = imu.dt;
        if !dt.is_finite() || dt <= 0.0 {
            self.state.time = imu.time;
            return;
        }
        let (dth, dv) = (imu.dtheta, imu.dvel);
        let (pth, pdv) = if self.has_prev {
            (self.prev_dtheta, self.prev_dvel)
        } else {
            // No history: the corrections vanish as for constant rates.
            (dth, dv)
        };
        let s0 = self.state;
        let (a, omega) = (self.earth.a, self.earth.omega_ie);

        // Mid-interval latitude and height, extrapolated with the old
        // velocity and the previous step's meridian radius (a radius off by
        // the 0.3–1 % between the equatorial and meridian ones would bias
        // gravity, through its latitude dependence, by an amount
        // proportional to the step, which the vertical channel integrates).
        let lat_m = s0.pos.lat + 0.5 * dt * s0.vel.x / (self.rm + s0.pos.h);
        let h_m0 = s0.pos.h - 0.5 * dt * s0.vel.z;
        let (sl, cl) = lat_m.sin_cos();
        let s2 = sl * sl;
        let w2 = 1.0 - self.e2 * s2;
        let rn = a / w2.sqrt();
        let rm = rn * (1.0 - self.e2) / w2;
        let w_ie = Vector3::new(omega * cl, 0.0, -omega * sl);
        let g = Vector3::new(0.0, 0.0, self.gravity.at(s2, h_m0));

        // Velocity: body increment with rotation compensation to second order
        // (½ Δθ × Δv + ⅙ Δθ × (Δθ × Δv); the second term rectifies gravity
        // under angular vibration) and two-sample sculling.
        let half_rot = 0.5 * dth.cross(&dv);
        let dv_b =
            dv + half_rot + dth.cross(&half_rot) / 3.0 + (pth.cross(&dv) + pdv.cross(&dth)) / 12.0;
        let u = s0.att * dv_b;
        let zeta_ie = w_ie * dt;
        let u_ie = u - 0.5 * zeta_ie.cross(&u);
        let tan_l = sl / cl;
        let transport = |v: &Vector3<f64>, h: f64| {
            let (rmh, rnh) = (rm + h, rn + h);
            Vector3::new(v.y / rnh, -v.x / rmh, -v.y * tan_l / rnh)
        };
        // Mid-interval velocity for the transport rate and Coriolis terms,
        // with every acceleration of the first half-interval (the Coriolis
        // one from the previous step): leaving that out costs a first-order
        // error that the unstable vertical channel amplifies.
        let v_m = s0.vel + 0.5 * (u_ie + (g - self.coriolis) * dt);
        let w_en = transport(&v_m, h_m0);
        let dv_n = u_ie - 0.5 * (w_en * dt).cross(&u);
        let coriolis = (2.0 * w_ie + w_en).cross(&v_m);
        let v1 = s0.vel + dv_n + (g - coriolis) * dt;

        // Position: trapezoidal with the mean velocity.
        let v_avg = 0.5 * (s0.vel + v1);
        let h1 = s0.pos.h - v_avg.z * dt;
        let h_mid = 0.5 * (s0.pos.h + h1);
        let dlat = v_avg.x * dt / (rm + h_mid);
        // cos at the true mid latitude, corrected to first order from lat_m.
        let c_mid = cl - sl * (s0.pos.lat + 0.5 * dlat - lat_m);
        let dlon = v_avg.y * dt / ((rn + h_mid) * c_mid);
        let lat1 = two_sum(s0.pos.lat, dlat, &mut self.lat_lo);
        let mut lon1 = two_sum(s0.pos.lon, dlon, &mut self.lon_lo);
        if lon1 > std::f64::consts::PI {
            lon1 -= std::f64::consts::TAU;
        } else if lon1 < -std::f64::consts::PI {
            lon1 += std::f64::consts::TAU;
        }

        // Attitude: body rotation with coning, NED rotation over the interval.
        let zeta = (w_ie + transport(&v_avg, h_mid)) * dt;
        let q_bb = rotation_vector_to_quaternion(&(dth + pth.cross(&dth) / 12.0));
        let q_nn = rotation_vector_to_quaternion(&(-zeta));
        let q = q_nn.into_inner() * s0.att.into_inner() * q_bb.into_inner();
        let q = q / q.norm();

        self.state.time = imu.time;
        self.state.pos.lat = lat1;
        self.state.pos.lon = lon1;
        self.state.pos.h = h1;
        self.state.vel = v1;
        self.state.att = UnitQuaternion::new_unchecked(Quaternion::from(q.coords));
        self.coriolis = coriolis;
        self.rm = rm;
        self.prev_dtheta = dth;
        self.prev_dvel = dv;
        self.has_prev = true;
        self.f_ned = dv_n / dt;
        self.omega_ib = dth / dt;
    }
}

/// `hi + d` with the rounding carried in `lo` (compensated summation with
/// Knuth's two-sum, exact whatever the magnitudes, e.g. at the equator). On
/// a steady course the increment, and so its rounding, repeats every step:
/// plain summation loses about 30 µm in half an hour due east at 20 m/s and
/// 200 Hz, ten times that at 200 m/s.
#[inline]
fn two_sum(hi: f64, d: f64, lo: &mut f64) -> f64 {
    let y = d + *lo;
    let s = hi + y;
    let yy = s - hi;
    *lo = (hi - (s - yy)) + (y - yy);
    s
}
