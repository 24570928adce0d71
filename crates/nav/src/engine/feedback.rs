//! Closed-loop feedback: the error-state estimate corrects the navigation
//! solution and the sensor-error estimates, then the error state is reset.

use kestrel_core::Real;
use nalgebra::{SVector, Vector3};

use crate::correction::{ImuBiases, NavError};
use crate::earth::Ellipsoid;
use crate::measurement::ErrorLayout;
use crate::state::NavState;
use kestrel_core::real::to_f64;

/// The sensor-error estimates accumulated by feedback, removed from every
/// later reading: `measured = true + error`, so an IMU increment is
/// corrected by subtracting the bias estimates and an odometer speed by
/// dividing by `1 + k̂`.
///
/// ```
/// use kestrel_nav::{ImuIncrement, nalgebra::Vector3};
/// use kestrel_nav::engine::SensorCorrections;
/// let mut c = SensorCorrections::default();
/// c.imu.gyro = Vector3::new(1e-4, 0.0, 0.0);
/// let raw = ImuIncrement::from_rates(0.01, 0.01, Vector3::new(1e-4, 0.0, 0.0), Vector3::zeros());
/// assert_eq!(c.imu.compensate(&raw).dtheta.x, 0.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SensorCorrections {
    /// Gyro (rad/s) and accelerometer (m/s²) bias estimates, body axes.
    pub imu: ImuBiases,
    /// Odometer scale-factor error estimate `k̂` (ratio).
    pub odometer_scale: f64,
}

impl SensorCorrections {
    /// An odometer speed (m/s) corrected for the scale-factor estimate.
    ///
    /// ```
    /// let c = kestrel_nav::engine::SensorCorrections { odometer_scale: 0.01, ..Default::default() };
    /// assert!((c.correct_speed(10.1) - 10.0).abs() < 1e-12);
    /// ```
    pub fn correct_speed(&self, speed: f64) -> f64 {
        speed / (1.0 + self.odometer_scale)
    }
}

/// Block `first..first + 3` of `dx` in `f64`.
fn block<T: Real, const N: usize>(dx: &SVector<T, N>, first: usize) -> Vector3<f64> {
    Vector3::new(
        to_f64(dx[first]),
        to_f64(dx[first + 1]),
        to_f64(dx[first + 2]),
    )
}

/// Applies the error-state estimate `dx` (layout `L`) to the navigation
/// solution and the sensor estimates, following the error definitions:
/// `C ← exp([φ×]) C`, `v ← v − δv`, `r ← r − δr` (NED displacement), each
/// sensor estimate (biases, scale factors) `← estimate + error` (a sum over
/// the layout's blocks).
/// The caller resets the error state to zero afterwards.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, nalgebra::{SVector, Vector3}};
/// use kestrel_nav::engine::{feed_back, Ins15, SensorCorrections};
/// let earth = Ellipsoid::wgs84();
/// let mut nav = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0),
///     Vector3::new(1.0, 0.0, 0.0), Euler::default());
/// let before = nav;
/// let mut dx = SVector::<f64, 15>::zeros();
/// dx[3] = 0.25;   // velocity north 0.25 m/s too large
/// dx[8] = -2.0;   // 2 m too high (down error negative)
/// dx[12] = 1e-3;  // accelerometer x bias
/// let mut c = SensorCorrections::default();
/// feed_back::<f64, 15, Ins15>(&dx, &earth, &mut nav, &mut c);
/// assert!((nav.vel.x - 0.75).abs() < 1e-12);
/// assert!((nav.pos.h - (before.pos.h - 2.0)).abs() < 1e-6);
/// assert_eq!(c.imu.accel.x, 1e-3);
/// ```
pub fn feed_back<T: Real, const N: usize, L: ErrorLayout<N>>(
    dx: &SVector<T, N>,
    earth: &Ellipsoid,
    nav: &mut NavState,
    corrections: &mut SensorCorrections,
) {
    const {
        assert!(
            crate::measurement::layout_fits::<N, L>(),
            "error layout does not fit the state"
        )
    };
    *nav = NavError::from_error_state(dx).correct(earth, nav);
    for &b in L::GYRO_BIAS {
        corrections.imu.gyro += block(dx, b);
    }
    for &b in L::ACCEL_BIAS {
        corrections.imu.accel += block(dx, b);
    }
    if let Some(i) = L::ODOMETER_SCALE {
        corrections.odometer_scale += to_f64(dx[i]);
    }
    if let Some(i) = L::GYRO_SCALE {
        corrections.imu.gyro_scale += block(dx, i);
    }
    if let Some(i) = L::ACCEL_SCALE {
        corrections.imu.accel_scale += block(dx, i);
    }
}
