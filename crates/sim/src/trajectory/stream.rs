//! Streaming truth and exact IMU increments.
//!
//! The increments are integrals over each sampling interval of
//!
//! ```text
//! ω_ib^b = C_v^b ω_nv^v + C_n^b (ω_ie^n + ω_en^n)
//! f^b    = C_n^b (v̇^n + (2 ω_ie^n + ω_en^n) × v^n − g^n)
//! ```
//!
//! in the IMU body frame `b`, fixed to the vehicle frame `v` by the
//! trajectory's mounting (`C_n^b = C_v^b C_n^v`), where velocity, its rate,
//! the vehicle attitude and `ω_nv^v` are closed forms of the profiles and
//! the Earth terms are evaluated at the integrated position.
//! The quadrature is four-point Gauss–Lobatto (exact for polynomials of
//! degree 5; local error O(h⁷)), applied separately on each side of every
//! breakpoint so it only ever sees analytic integrands. The position uses
//! the same nodes (the node positions come from a trapezoid predictor; the
//! integrands depend on position only through slowly varying Earth terms).
//! Lobatto nodes include both ends, so each epoch evaluates three new
//! instants and reuses the previous end.
//!
//! Why quadrature of the continuous motion rather than inverting a discrete
//! mechanisation: the increments are then what a perfect sensor would
//! measure, independent of any particular integration algorithm, so a
//! perfect-IMU run tests the mechanisation (coning, sculling, position
//! update) instead of reproducing it by construction.

use nalgebra::Vector3;

use super::motion::Motion;
use super::path::Trajectory;
use kestrel_nav::earth::NormalGravity;
use kestrel_nav::geodetic::Geodetic;
use kestrel_nav::imu::ImuIncrement;
use kestrel_nav::state::NavState;

/// Interior Gauss–Lobatto abscissae on [0, 1]: (1 ∓ 1/√5) / 2.
const LOBATTO_1: f64 = 0.276_393_202_250_021;
const LOBATTO_2: f64 = 0.723_606_797_749_979;

/// Everything needed at one quadrature node.
#[derive(Clone, Copy, Debug)]
struct Node {
    t: f64,
    pos: Geodetic,
    motion: Motion,
    /// ω_ib^b, rad/s.
    omega_ib: Vector3<f64>,
    /// f^b, m/s².
    force: Vector3<f64>,
    /// (lat', lon', h'), rad/s, rad/s, m/s.
    pos_rate: Vector3<f64>,
    /// `R_M + h` and `(R_N + h) cos L`, m, for predicting nearby positions.
    rm_h: f64,
    rn_h_cos: f64,
}

/// An iterator over `(truth, IMU increment)` from the first sampling
/// interval to the end of a [`Trajectory`]; nothing is stored per epoch,
/// so an hour at 200 Hz costs no memory.
///
/// `truth.time == imu.time` is the end of the increment's interval; the
/// truth attitude and the increments are those of the IMU body (see
/// [`TrajectorySpec::mounting`](super::TrajectorySpec::mounting)).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Geodetic};
/// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
/// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::from_degrees(34.0, 120.0, 0.0), 0.0, 0.0)
///     .then(Segment::Stationary { duration: 1.0 });
/// let traj = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap();
/// let (_, imu) = traj.stream(100.0).unwrap().next().unwrap();
/// // At rest the accelerometers feel gravity upwards (−z) and the gyros
/// // the Earth's rotation.
/// let g = traj.earth().gravity(34f64.to_radians(), 0.0);
/// assert!((imu.dvel.z + g * 0.01).abs() < 1e-12);
/// assert!((imu.dtheta.norm() - 7.292115e-5 * 0.01).abs() < 1e-15);
/// ```
#[derive(Clone, Debug)]
pub struct ImuStream {
    traj: Trajectory,
    gravity: NormalGravity,
    rate: f64,
    k: u64,
    n: u64,
    cursors: [usize; 4],
    /// Index of the first breakpoint after the current time.
    bp: usize,
    node: Node,
    /// Rounding carried by the compensated position summation.
    carry: Vector3<f64>,
}

impl ImuStream {
    pub(crate) fn new(traj: Trajectory, rate: f64) -> Self {
        let gravity = traj.earth.normal_gravity();
        let n = (traj.duration * rate + 1e-6).floor().max(0.0) as u64;
        let mut s = Self {
            gravity,
            rate,
            k: 0,
            n,
            cursors: [0; 4],
            bp: 0,
            carry: Vector3::zeros(),
            node: Node {
                t: 0.0,
                pos: traj.start,
                motion: traj.motion_at(0.0),
                omega_ib: Vector3::zeros(),
                force: Vector3::zeros(),
                pos_rate: Vector3::zeros(),
                rm_h: 1.0,
                rn_h_cos: 1.0,
            },
            traj,
        };
        let m = s.traj.motion_at(0.0);
        s.node = s.node_at(0.0, m, s.traj.start);
        s
    }

    /// Sampling rate, Hz.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0);
    /// assert_eq!(Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(125.0).unwrap().rate(), 125.0);
    /// ```
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// The trajectory being flown.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 0.0)
    ///     .then(Segment::Stationary { duration: 3.0 });
    /// let s = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(100.0).unwrap();
    /// assert_eq!(s.trajectory().duration(), 3.0);
    /// ```
    pub fn trajectory(&self) -> &Trajectory {
        &self.traj
    }

    /// The motion at the latest epoch (time 0 before the first one): exact
    /// velocity, acceleration, vehicle and body attitude and `ω_nb^b`, e.g.
    /// for lever arms and the odometer.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 5.0)
    ///     .then(Segment::turn_rate_deg(10.0, 90.0));
    /// let mut s = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(100.0).unwrap();
    /// s.nth(299); // t = 3 s, mid-turn at the full rate
    /// assert!((s.motion().omega_nb.z - 10f64.to_radians()).abs() < 1e-12);
    /// ```
    pub fn motion(&self) -> &Motion {
        &self.node.motion
    }

    /// Angular rate `ω_ib^b` (rad/s) at the latest epoch.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.0, 0.0, 0.0), 0.0, 0.0)
    ///     .then(Segment::Stationary { duration: 1.0 });
    /// let s = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(100.0).unwrap();
    /// assert!((s.angular_rate().x - 7.292115e-5).abs() < 1e-18);
    /// ```
    pub fn angular_rate(&self) -> Vector3<f64> {
        self.node.omega_ib
    }

    /// Specific force `f^b` (m/s²) at the latest epoch.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// use kestrel_sim::{Segment, Trajectory, TrajectorySpec, Vehicle};
    /// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.0, 0.0, 0.0), 0.0, 0.0)
    ///     .then(Segment::Stationary { duration: 1.0 });
    /// let s = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().stream(100.0).unwrap();
    /// assert!(s.specific_force().z < -9.7);
    /// ```
    pub fn specific_force(&self) -> Vector3<f64> {
        self.node.force
    }

    /// The Earth terms and increments' integrands at `t` for the motion
    /// `motion` and the position `pos`.
    fn node_at(&self, t: f64, motion: Motion, pos: Geodetic) -> Node {
        let e = &self.traj.earth;
        let (sl, cl) = pos.lat.sin_cos();
        let e2 = e.e2();
        let w2 = 1.0 - e2 * sl * sl;
        let w = w2.sqrt();
        // The radii of `Ellipsoid::meridian_radius` / `prime_vertical_radius`
        // from one sin/cos.
        let rm_h = e.a * (1.0 - e2) / (w2 * w) + pos.h;
        let rn_h = e.a / w + pos.h;
        let v = motion.vel;
        let w_ie = Vector3::new(e.omega_ie * cl, 0.0, -e.omega_ie * sl);
        let w_en = Vector3::new(v.y / rn_h, -v.x / rm_h, -v.y * sl / (cl * rn_h));
        let g = self.gravity.at(sl * sl, pos.h);
        let c_nb = motion.c_bn.transpose();
        let omega_ib = motion.omega_nb + c_nb * (w_ie + w_en);
        let f_n = motion.acc + (2.0 * w_ie + w_en).cross(&v) - Vector3::new(0.0, 0.0, g);
        Node {
            t,
            pos,
            motion,
            omega_ib,
            force: c_nb * f_n,
            pos_rate: Vector3::new(v.x / rm_h, v.y / (rn_h * cl), -v.z),
            rm_h,
            rn_h_cos: rn_h * cl,
        }
    }

    /// Position at `t` predicted from node `a` by the trapezoid rule on the
    /// velocities (radii held at `a`).
    fn predict(a: &Node, t: f64, vel: &Vector3<f64>) -> Geodetic {
        let tau = t - a.t;
        let rate_t = Vector3::new(vel.x / a.rm_h, vel.y / a.rn_h_cos, -vel.z);
        let d = (a.pos_rate + rate_t) * (0.5 * tau);
        Geodetic::new(a.pos.lat + d.x, a.pos.lon + d.y, a.pos.h + d.z)
    }

    /// Integrates from the current node to `t`, which must not lie beyond
    /// the next breakpoint; accumulates the increments.
    fn advance(&mut self, t: f64, dtheta: &mut Vector3<f64>, dvel: &mut Vector3<f64>) {
        let a = self.node;
        let h = t - a.t;
        let mut nodes = [a; 3];
        for (node, x) in nodes.iter_mut().zip([LOBATTO_1, LOBATTO_2, 1.0]) {
            let ti = if x == 1.0 { t } else { a.t + x * h };
            let motion = self.traj.channels.motion(
                ti,
                self.traj.vehicle,
                &self.traj.c_vb,
                &mut self.cursors,
            );
            let pos = Self::predict(&a, ti, &motion.vel);
            *node = self.node_at(ti, motion, pos);
        }
        let [n1, n2, mut b] = nodes;
        let w = h / 12.0;
        let quad = |f: fn(&Node) -> Vector3<f64>| (f(&a) + f(&b) + 5.0 * (f(&n1) + f(&n2))) * w;
        *dtheta += quad(|n| n.omega_ib);
        *dvel += quad(|n| n.force);
        // Compensated (Kahan) summation: an hour of 200 Hz steps would
        // otherwise lose up to ~1 mm to rounding of latitude and longitude.
        let dp = quad(|n| n.pos_rate) - self.carry;
        let p0 = Vector3::new(a.pos.lat, a.pos.lon, a.pos.h);
        let p1 = p0 + dp;
        self.carry = (p1 - p0) - dp;
        b.pos = Geodetic::new(p1.x, p1.y, p1.z);
        self.node = b;
    }

    /// Time of epoch `k`, s.
    fn time(&self, k: u64) -> f64 {
        k as f64 / self.rate
    }
}

impl Iterator for ImuStream {
    type Item = (NavState, ImuIncrement);

    fn next(&mut self) -> Option<Self::Item> {
        if self.k >= self.n {
            return None;
        }
        let t0 = self.node.t;
        let t1 = self.time(self.k + 1);
        let mut dtheta = Vector3::zeros();
        let mut dvel = Vector3::zeros();
        let bps = &self.traj.breakpoints;
        while self.bp < bps.len() && bps[self.bp] <= t0 + 1e-9 {
            self.bp += 1;
        }
        while self.bp < self.traj.breakpoints.len() && self.traj.breakpoints[self.bp] < t1 - 1e-9 {
            let tb = self.traj.breakpoints[self.bp];
            self.advance(tb, &mut dtheta, &mut dvel);
            self.bp += 1;
        }
        self.advance(t1, &mut dtheta, &mut dvel);
        self.k += 1;
        let n = &self.node;
        let truth = NavState {
            time: t1,
            pos: n.pos,
            vel: n.motion.vel,
            att: self.traj.body_attitude(&n.motion),
        };
        let imu = ImuIncrement {
            time: t1,
            dt: t1 - t0,
            dtheta,
            dvel,
        };
        Some((truth, imu))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = (self.n - self.k) as usize;
        (left, Some(left))
    }
}

impl ExactSizeIterator for ImuStream {}
