//! The continuous-time dynamics of the navigation errors (attitude,
//! velocity, position), linearised about the current solution.

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::attitude::skew;
use crate::earth::Ellipsoid;
use crate::state::NavState;

/// The 9 × 9 matrix `F` of `d/dt [φ, δv, δr] = F [φ, δv, δr] + …` for the
/// error definitions of the crate (φ: `C(computed) = (I − [φ×]) C(true)`;
/// `δv = v(computed) − v(true)`; `δr`: NED displacement from the true to
/// the computed position, m), evaluated at `nav` with the specific force
/// `f_ned` (m/s², NED). Sensor-error inputs are added by the full models:
/// `φ̇ += −C_b^n δω_ib`, `δv̇ += C_b^n δf^b`.
///
/// With `ω_in = ω_ie + ω_en` (both functions of latitude `L`, height and
/// velocity; see [`Ellipsoid::transport_rate_ned`]):
///
/// ```text
/// φ̇  = −ω_in × φ + ∂ω_in/∂v δv + ∂ω_in/∂r δr
/// δv̇ = f^n × φ + ([v×] ∂ω_en/∂v − [(2ω_ie + ω_en)×]) δv
///      + ([v×] (2 ∂ω_ie/∂r + ∂ω_en/∂r) + ∂g/∂r) δr
/// δṙ = δv + F_rr δr
/// ```
///
/// where `∂/∂r` goes through `δL = δr_N / (R_M + h)` and `δh = −δr_D`, the
/// gravity gradient `∂g/∂r` is that of the crate's normal-gravity formula
/// (free-air term `≈ 2g/R` on the down axis, which makes the vertical
/// channel unstable, plus the small latitude term), and `F_rr` holds the
/// terms from the change of the curvature radii with height and of the
/// meridian convergence. The latitude derivatives of `R_M`, `R_N` (relative
/// size `e² ≈ 0.7 %` of already small terms) are neglected.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
/// use kestrel_nav::error_model::nav_error_dynamics;
/// let earth = Ellipsoid::wgs84();
/// let nav = NavState::new(0.0, Geodetic::from_degrees(45.0, 0.0, 0.0), Vector3::zeros(),
///     Euler::default());
/// let g = earth.gravity(nav.pos.lat, 0.0);
/// let f = nav_error_dynamics(&earth, &nav, &Vector3::new(0.0, 0.0, -g));
/// // At rest an east tilt error φ_E gives a north acceleration error g φ_E (f × φ).
/// assert!((f[(3, 1)] - g).abs() < 1e-12);
/// // Velocity error drives position error one to one.
/// assert_eq!(f[(6, 3)], 1.0);
/// ```
pub fn nav_error_dynamics(
    earth: &Ellipsoid,
    nav: &NavState,
    f_ned: &Vector3<f64>,
) -> SMatrix<f64, 9, 9> {
    let (sl, cl) = nav.pos.lat.sin_cos();
    let tl = sl / cl;
    let e2 = earth.e2();
    let w2 = 1.0 - e2 * sl * sl;
    let rn = earth.a / w2.sqrt();
    let rm = rn * (1.0 - e2) / w2;
    let (rmh, rnh) = (rm + nav.pos.h, rn + nav.pos.h);
    let om = earth.omega_ie;
    let v = nav.vel;
    let (vn, ve) = (v.x, v.y);

    let w_ie = Vector3::new(om * cl, 0.0, -om * sl);
    let w_en = Vector3::new(ve / rnh, -vn / rmh, -ve * tl / rnh);

    // Partial derivatives of the rates with respect to δv and δr.
    let dwen_dv = Matrix3::new(
        0.0,
        1.0 / rnh,
        0.0,
        -1.0 / rmh,
        0.0,
        0.0,
        0.0,
        -tl / rnh,
        0.0,
    );
    let mut dwie_dr = Matrix3::zeros();
    dwie_dr[(0, 0)] = -om * sl / rmh;
    dwie_dr[(2, 0)] = -om * cl / rmh;
    let mut dwen_dr = Matrix3::zeros();
    dwen_dr[(2, 0)] = -ve / (cl * cl * rnh * rmh);
    dwen_dr[(0, 2)] = ve / (rnh * rnh);
    dwen_dr[(1, 2)] = -vn / (rmh * rmh);
    dwen_dr[(2, 2)] = -ve * tl / (rnh * rnh);
    let (dg_dlat, dg_dh) = earth.normal_gravity().derivatives(sl, cl, nav.pos.h);
    let mut dg_dr = Matrix3::zeros();
    dg_dr[(2, 0)] = dg_dlat / rmh;
    dg_dr[(2, 2)] = -dg_dh;

    let vx = skew(&v);
    let mut f = SMatrix::<f64, 9, 9>::zeros();
    f.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(-skew(&(w_ie + w_en))));
    f.fixed_view_mut::<3, 3>(0, 3).copy_from(&dwen_dv);
    f.fixed_view_mut::<3, 3>(0, 6)
        .copy_from(&(dwie_dr + dwen_dr));
    f.fixed_view_mut::<3, 3>(3, 0).copy_from(&skew(f_ned));
    f.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(vx * dwen_dv - skew(&(2.0 * w_ie + w_en))));
    f.fixed_view_mut::<3, 3>(3, 6)
        .copy_from(&(vx * (2.0 * dwie_dr + dwen_dr) + dg_dr));
    f.fixed_view_mut::<3, 3>(6, 3)
        .copy_from(&Matrix3::identity());
    let vd = v.z;
    f[(6, 6)] = -vd / rmh;
    f[(6, 8)] = vn / rmh;
    f[(7, 6)] = ve * tl / rmh;
    f[(7, 7)] = -vd / rnh - vn * tl / rmh;
    f[(7, 8)] = ve / rnh;
    f
}
