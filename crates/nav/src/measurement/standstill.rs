//! Measurements of a vehicle standing still: zero velocity (ZUPT) and zero
//! angular rate against the Earth (ZARU).

use kestrel_core::Real;
use nalgebra::{SMatrix, SVector, Vector3};

use super::layout::fits;
use super::{ErrorLayout, ErrorMeasurement, InsContext};

/// A zero-velocity update: the INS velocity is its error,
/// `z = v̂ⁿ`, `H = [0 I 0 …]` on `δv`, `R = velocity_std² I`.
///
/// ```
/// use kestrel_core::nalgebra::Vector3;
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
/// use kestrel_nav::engine::Ins15;
/// use kestrel_nav::measurement::{InsContext, ZeroVelocity};
/// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0),
///     Vector3::new(0.02, -0.01, 0.0), Euler::default());
/// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
/// let m = ZeroVelocity::new(0.01).measurement::<f64, 15, _>(&Ins15::new(ImuSpec::perfect()), &ins);
/// assert_eq!(m.z()[0], 0.02);
/// assert_eq!(m.noise_covariance()[(2, 2)], 1e-4);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZeroVelocity {
    /// σ of the zero-velocity measurement, m/s (vibration, creep).
    pub velocity_std: f64,
}

impl ZeroVelocity {
    /// A ZUPT with standard deviation `velocity_std` (m/s).
    pub fn new(velocity_std: f64) -> Self {
        Self { velocity_std }
    }

    /// The measurement at the INS solution `ins` for layout `L`.
    pub fn measurement<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        _layout: &L,
        ins: &InsContext,
    ) -> ErrorMeasurement<T, N, 3> {
        identity_rows::<T, N, L>(ins.state.vel, &[3], self.velocity_std)
    }
}

/// A zero-angular-rate update: standing still, the body turns only with
/// the Earth, so the bias-corrected gyro rate minus the Earth rate is the
/// remaining gyro error, `z = ω̂_ib^b − Ĉ_nᵇ ω_ie^n`, `H = I` on every gyro
/// bias block, `R = angular_rate_std² I`. The attitude error's effect on the
/// Earth-rate term (`|ω_ie| |φ|`, below 10⁻⁶ rad/s for φ < 1°) is left out.
///
/// ```
/// use kestrel_core::nalgebra::Vector3;
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
/// use kestrel_nav::engine::Ins15;
/// use kestrel_nav::measurement::{InsContext, ZeroAngularRate};
/// let earth = Ellipsoid::wgs84();
/// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0), Vector3::zeros(),
///     Euler::default());
/// // Level and facing north: the body axes are NED; a 1e-4 rad/s x-gyro error.
/// let w = earth.earth_rate_ned(nav.pos.lat) + Vector3::new(1e-4, 0.0, 0.0);
/// let ins = InsContext::new(earth, nav, w);
/// let m = ZeroAngularRate::new(1e-5).measurement::<f64, 15, _>(&Ins15::new(ImuSpec::perfect()), &ins);
/// assert!((m.z()[0] - 1e-4).abs() < 1e-15 && m.z()[2].abs() < 1e-15);
/// assert_eq!(m.h()[(0, 9)], 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZeroAngularRate {
    /// σ of the zero-angular-rate measurement, rad/s.
    pub angular_rate_std: f64,
}

impl ZeroAngularRate {
    /// A ZARU with standard deviation `angular_rate_std` (rad/s).
    pub fn new(angular_rate_std: f64) -> Self {
        Self { angular_rate_std }
    }

    /// The measurement at the INS solution `ins` for layout `L`.
    pub fn measurement<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        _layout: &L,
        ins: &InsContext,
    ) -> ErrorMeasurement<T, N, 3> {
        let w_ie = ins.earth.earth_rate_ned(ins.state.pos.lat);
        let z: Vector3<f64> = ins.omega_ib - ins.c_bn().transpose() * w_ie;
        identity_rows::<T, N, L>(z, L::GYRO_BIAS, self.angular_rate_std)
    }
}

/// A 3-row measurement `z` of the sum of the 3-blocks at `blocks`
/// (`H = [… I … I …]`) with standard deviation `std` on each row.
fn identity_rows<T: Real, const N: usize, L: ErrorLayout<N>>(
    z: Vector3<f64>,
    blocks: &[usize],
    std: f64,
) -> ErrorMeasurement<T, N, 3> {
    const { assert!(fits::<N, L>(), "error layout does not fit the state") };
    let mut h = SMatrix::<f64, 3, N>::zeros();
    for &col in blocks {
        h.fixed_view_mut::<3, 3>(0, col)
            .copy_from(&nalgebra::Matrix3::identity());
    }
    ErrorMeasurement::new(z, h, SVector::repeat(std * std))
}
