//! Helpers shared by the inertial-navigation tests.
#![allow(dead_code)]

use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Ellipsoid, ImuIncrement, NavState};

/// The exact increments of a body at rest on the rotating Earth, consistent
/// with the mechanisation's normal gravity and Earth rate: the gyros see
/// `C_n^b ω_ie^n`, the accelerometers the support force `C_n^b [0, 0, −g]`.
pub fn stationary_increment(earth: &Ellipsoid, state: &NavState, dt: f64) -> ImuIncrement {
    let cnb = state.att.inverse();
    let w = cnb * earth.earth_rate_ned(state.pos.lat);
    let f = cnb * Vector3::new(0.0, 0.0, -earth.gravity(state.pos.lat, state.pos.h));
    ImuIncrement::from_rates(0.0, dt, w, f)
}
