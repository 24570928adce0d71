//! Velocity, acceleration, attitude and body rate at one instant, in
//! closed form from the channel profiles.

use nalgebra::{Matrix3, Vector3};

use super::compile::Channels;
use super::segment::Vehicle;
use kestrel_nav::attitude::Euler;
use kestrel_nav::imu_spec::G0;

/// The exact motion at one instant (position excluded: it is integrated):
/// of the vehicle frame `v` that the segments describe, and of the IMU body
/// frame `b` fixed to it by the trajectory's
/// [`mounting`](super::TrajectorySpec::mounting) (`C_v^b`, constant, so
/// `ω_nb^b = C_v^b ω_nv^v`).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Geodetic};
/// use kestrel_sim::{Trajectory, TrajectorySpec, Vehicle};
/// let spec = TrajectorySpec::new(Vehicle::Ground, Geodetic::new(0.5, 2.0, 0.0), 0.0, 10.0);
/// let m = Trajectory::new(&spec, Ellipsoid::wgs84()).unwrap().motion_at(0.0);
/// assert_eq!(m.vel.x, 10.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Velocity, NED, m/s.
    pub vel: Vector3<f64>,
    /// Time derivative of the NED velocity components, m/s².
    pub acc: Vector3<f64>,
    /// The vehicle's roll, pitch, yaw.
    pub euler: Euler,
    /// `C_v^n`, vehicle to NED.
    pub c_vn: Matrix3<f64>,
    /// `C_b^n = C_v^n C_b^v`, IMU body to NED.
    pub c_bn: Matrix3<f64>,
    /// Angular rate of the IMU body with respect to NED, body axes, rad/s.
    pub omega_nb: Vector3<f64>,
}

impl Channels {
    /// The motion at `t` with the body mounted by `c_vb` (`C_v^b`);
    /// `cursors` speed up the piece search (see
    /// [`Channel::eval`](super::profile::Channel::eval)).
    pub(crate) fn motion(
        &self,
        t: f64,
        vehicle: Vehicle,
        c_vb: &Matrix3<f64>,
        cursors: &mut [usize; 4],
    ) -> Motion {
        let v = self.speed.eval(t, &mut cursors[0]);
        let chi = self.track.eval(t, &mut cursors[1]);
        let gam = self.path.eval(t, &mut cursors[2]);
        let beta = self.slip.eval(t, &mut cursors[3]);

        let (sg, cg) = gam.x.sin_cos();
        let (sc, cc) = chi.x.sin_cos();
        let dir = Vector3::new(cg * cc, cg * sc, -sg);
        let vel = dir * v.x;
        // d(dir)/dt through the path angle and the track.
        let ddir = Vector3::new(
            -sg * gam.dx * cc - cg * sc * chi.dx,
            -sg * gam.dx * sc + cg * cc * chi.dx,
            -cg * gam.dx,
        );
        let acc = dir * v.dx + ddir * v.x;

        // Coordinated bank: tan φ = V χ' / g₀, differentiated exactly.
        let (roll, droll) = match vehicle {
            Vehicle::Ground => (0.0, 0.0),
            Vehicle::Aircraft => {
                let u = v.x * chi.dx / G0;
                let du = (v.dx * chi.dx + v.x * chi.ddx) / G0;
                (u.atan(), du / (1.0 + u * u))
            }
        };
        let (pitch, dpitch) = (gam.x, gam.dx);
        let (yaw, dyaw) = (chi.x - beta.x, chi.dx - beta.dx);

        let (sr, cr) = roll.sin_cos();
        let (sy, cy) = if beta.x == 0.0 {
            (sc, cc)
        } else {
            yaw.sin_cos()
        };
        let (sp, cp) = (sg, cg);
        // C_v^n = Rz(yaw) Ry(pitch) Rx(roll).
        let c_vn = Matrix3::new(
            cp * cy,
            -cr * sy + sr * sp * cy,
            sr * sy + cr * sp * cy,
            cp * sy,
            cr * cy + sr * sp * sy,
            -sr * cy + cr * sp * sy,
            -sp,
            sr * cp,
            cr * cp,
        );
        // Vehicle rates from ZYX Euler-angle rates.
        let omega_nv = Vector3::new(
            droll - dyaw * sp,
            dpitch * cr + dyaw * sr * cp,
            -dpitch * sr + dyaw * cr * cp,
        );
        Motion {
            vel,
            acc,
            euler: Euler::new(roll, pitch, yaw),
            c_vn,
            c_bn: c_vn * c_vb.transpose(),
            omega_nb: c_vb * omega_nv,
        }
    }
}
