//! The coordinated-turn model with unknown turn rate.

use kestrel_core::nalgebra::{Matrix5, SMatrix, SVector, Vector5};
use kestrel_core::real::{epsilon, lit};
use kestrel_core::{FilterError, LinearizedProcess, ProcessModel, Real};

/// A target turning at a constant but unknown rate in the plane, the state
/// `[x, vₓ, y, v_y, ω]` (position, velocity, turn rate in rad/s), after
/// Bar-Shalom, Li & Kirubarajan (2001), *Estimation with Applications to
/// Tracking and Navigation*, §11.7.
///
/// Over `dt`, with `u = ω dt`, the velocity rotates by `u` and the position
/// moves along the arc (exact for a constant `ω`):
///
/// `x⁺ = x + (sin u / ω) vₓ − ((1 − cos u) / ω) v_y`,
/// `y⁺ = y + ((1 − cos u) / ω) vₓ + (sin u / ω) v_y`,
/// `v⁺ = R(u) v`, `ω⁺ = ω`.
///
/// The coefficients and their derivatives in `ω` are taken from their
/// Taylor series when `|u| < ε^{1/6}` (so `ω = 0` is the constant-velocity
/// limit and no cancellation occurs in `f32`), from `sin` and
/// `1 − cos u = 2 sin²(u/2)` otherwise. The process noise is white
/// acceleration of density `accel_density` [m²/s³] on each axis and a
/// random-walk turn rate of density `turn_density` [rad²/s³].
///
/// The model is generic over the scalar (its parameters are `f64`), so it
/// also runs on dual numbers: `AutoJacobian` (feature `autodiff`) checks
/// its hand-derived Jacobian exactly.
///
/// ```
/// use kestrel_models::CoordinatedTurn;
/// use kestrel_core::{ProcessModel, nalgebra::Vector5};
/// use core::f64::consts::FRAC_PI_2;
/// let ct = CoordinatedTurn::new(0.1, 1e-4).unwrap();
/// // A quarter turn at 10 m/s and π/20 rad/s takes 10 s and ends at
/// // (R, R) for the radius R = v / ω.
/// let omega = FRAC_PI_2 / 10.0;
/// let x = ct.propagate(&Vector5::new(0.0, 10.0, 0.0, 0.0, omega), 10.0);
/// let r = 10.0 / omega;
/// assert!((x[0] - r).abs() < 1e-9 && (x[2] - r).abs() < 1e-9);
/// assert!(x[1].abs() < 1e-12 && (x[3] - 10.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoordinatedTurn {
    accel_density: f64,
    turn_density: f64,
}

impl CoordinatedTurn {
    /// The model with acceleration density `accel_density` [m²/s³] per axis
    /// and turn-rate density `turn_density` [rad²/s³].
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] naming the density unless it is
    /// finite and `≥ 0`.
    pub fn new(accel_density: f64, turn_density: f64) -> Result<Self, FilterError> {
        for (name, v) in [
            ("accel_density", accel_density),
            ("turn_density", turn_density),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(FilterError::InvalidParameter {
                    name,
                    valid: "finite and at least 0",
                });
            }
        }
        Ok(Self {
            accel_density,
            turn_density,
        })
    }

    /// The acceleration density [m²/s³].
    pub fn accel_density(&self) -> f64 {
        self.accel_density
    }

    /// The turn-rate density [rad²/s³].
    pub fn turn_density(&self) -> f64 {
        self.turn_density
    }
}

/// `sin u / ω`, `(1 − cos u) / ω`, `cos u`, `sin u` and the derivatives
/// of the first two in `ω`, for `u = ω dt`.
struct Arc<T> {
    s: T,
    c: T,
    cos: T,
    sin: T,
    ds: T,
    dc: T,
}

fn arc<T: Real>(omega: T, dt: T) -> Arc<T> {
    if (omega * dt).abs() < epsilon::<T>().powf(lit(1.0 / 6.0)) {
        series(omega, dt)
    } else {
        closed_form(omega, dt)
    }
}

/// The Taylor series in `u` to `u⁷` (the next terms are below `ε`).
fn series<T: Real>(omega: T, dt: T) -> Arc<T> {
    let u = omega * dt;
    let (sin, cos) = u.sin_cos();
    let (o, u2, dt2) = (T::one(), u * u, dt * dt);
    let s = dt * (o - u2 / lit(6.0) * (o - u2 / lit(20.0) * (o - u2 / lit(42.0))));
    let c = dt * u * (lit::<T>(0.5) - u2 / lit(24.0) * (o - u2 / lit(30.0) * (o - u2 / lit(56.0))));
    let ds = dt2 * u * (-o / lit(3.0) + u2 / lit(30.0) - u2 * u2 / lit(840.0));
    let dc =
        dt2 * (lit::<T>(0.5) - u2 / lit(8.0) + u2 * u2 / lit(144.0) - u2 * u2 * u2 / lit(5760.0));
    Arc {
        s,
        c,
        cos,
        sin,
        ds,
        dc,
    }
}

/// The closed form, with `1 − cos u = 2 sin²(u/2)` to avoid cancellation.
fn closed_form<T: Real>(omega: T, dt: T) -> Arc<T> {
    let u = omega * dt;
    let (sin, cos) = u.sin_cos();
    let half = (u * lit(0.5)).sin();
    let one_minus_cos = half * half * lit(2.0);
    let w2 = omega * omega;
    Arc {
        s: sin / omega,
        c: one_minus_cos / omega,
        cos,
        sin,
        ds: (u * cos - sin) / w2,
        dc: (u * sin - one_minus_cos) / w2,
    }
}

impl<T: Real> ProcessModel<T, 5> for CoordinatedTurn {
    fn propagate(&self, x: &SVector<T, 5>, dt: T) -> SVector<T, 5> {
        let (vx, vy, omega) = (x[1], x[3], x[4]);
        let a = arc(omega, dt);
        Vector5::new(
            x[0] + a.s * vx - a.c * vy,
            a.cos * vx - a.sin * vy,
            x[2] + a.c * vx + a.s * vy,
            a.sin * vx + a.cos * vy,
            omega,
        )
    }

    fn noise(&self, _x: &SVector<T, 5>, dt: T) -> SMatrix<T, 5, 5> {
        let qa: T = lit(self.accel_density);
        let (d2, d3) = (dt * dt, dt * dt * dt);
        let (pp, pv, vv) = (qa * d3 / lit(3.0), qa * d2 * lit(0.5), qa * dt);
        let z = T::zero();
        #[rustfmt::skip]
        let q = Matrix5::new(
            pp, pv, z,  z,  z,
            pv, vv, z,  z,  z,
            z,  z,  pp, pv, z,
            z,  z,  pv, vv, z,
            z,  z,  z,  z,  lit::<T>(self.turn_density) * dt,
        );
        q
    }
}

impl<T: Real> LinearizedProcess<T, 5> for CoordinatedTurn {
    fn transition(&self, x: &SVector<T, 5>, dt: T) -> SMatrix<T, 5, 5> {
        let (vx, vy, omega) = (x[1], x[3], x[4]);
        let a = arc(omega, dt);
        let (o, z) = (T::one(), T::zero());
        // ∂/∂ω of cos u and sin u are −dt sin u and dt cos u.
        let dcos = -dt * a.sin;
        let dsin = dt * a.cos;
        #[rustfmt::skip]
        let phi = Matrix5::new(
            o, a.s,   z, -a.c,   a.ds * vx - a.dc * vy,
            z, a.cos, z, -a.sin, dcos * vx - dsin * vy,
            z, a.c,   o, a.s,    a.dc * vx + a.ds * vy,
            z, a.sin, z, a.cos,  dsin * vx + dcos * vy,
            z, z,     z, z,      o,
        );
        phi
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{check_process_jacobian, ConstantVelocity2d};
    use kestrel_core::nalgebra::Vector4;

    /// ω = 0 is the constant-velocity model exactly, in Φ and Q.
    #[test]
    fn zero_turn_rate_is_constant_velocity() {
        let ct = CoordinatedTurn::new(0.3, 0.0).unwrap();
        let cv = ConstantVelocity2d::new(0.3).unwrap();
        let x = Vector5::new(1.0, 2.0, 3.0, -4.0, 0.0);
        let p = ct.propagate(&x, 0.7);
        let q = cv.propagate(&Vector4::new(1.0, 2.0, 3.0, -4.0), 0.7);
        assert!((p.fixed_rows::<4>(0) - q).norm() < 1e-15);
        let qct = ct.noise(&x, 0.7);
        let qcv = cv.noise(&Vector4::zeros(), 0.7);
        assert!((qct.fixed_view::<4, 4>(0, 0) - qcv).norm() < 1e-15);
    }

    /// The hand Jacobian against central differences, on both sides of the
    /// series threshold and at ω = 0, in f64 and f32.
    #[test]
    fn jacobian_matches_finite_differences() {
        let ct = CoordinatedTurn::new(0.1, 0.01).unwrap();
        for omega in [0.0, 1e-7, 1e-3, 2.5e-3, 0.05, -0.4, 1.3] {
            let x = Vector5::new(10.0, 12.0, -5.0, 3.0, omega);
            let check = check_process_jacobian(&ct, &x, 0.9);
            assert!(check.passes(1e-7), "ω = {omega}: {check:?}");
        }
        let x = Vector5::new(10.0_f32, 12.0, -5.0, 3.0, 0.02);
        assert!(check_process_jacobian(&ct, &x, 0.9).passes(2e-2));
    }

    /// The series and the closed form agree at the threshold, to the
    /// closed form's own rounding there (`ε / u²` relative for the
    /// derivatives, `ε` for the coefficients).
    #[test]
    fn series_and_closed_form_agree_at_the_threshold() {
        let dt = 1.7;
        let omega = f64::EPSILON.powf(1.0 / 6.0) / dt;
        let (a, b) = (series(omega, dt), closed_form(omega, dt));
        let u2 = (omega * dt).powi(2);
        for (x, y, tol) in [
            (a.s, b.s, 4.0 * f64::EPSILON),
            (a.c, b.c, 4.0 * f64::EPSILON),
            (a.ds, b.ds, 8.0 * f64::EPSILON / u2),
            (a.dc, b.dc, 8.0 * f64::EPSILON / u2),
        ] {
            assert!((x - y).abs() <= tol * x.abs(), "{x} vs {y}");
        }
    }

    #[test]
    fn refuses_negative_densities() {
        assert!(CoordinatedTurn::new(-1.0, 0.0).is_err());
        assert!(CoordinatedTurn::new(1.0, f64::NAN).is_err());
    }
}
