//! Odometer speed and the non-holonomic constraint in the vehicle frame.

use kestrel_core::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};

use super::context::InsContext;
use super::difference::ErrorMeasurement;
use super::layout::{fits, ErrorLayout};
use crate::attitude::skew;

/// One odometer reading: the speed along the vehicle's forward axis.
///
/// ```
/// let r = kestrel_nav::measurement::OdometerReading::new(0.1, 19.9);
/// assert_eq!(r.speed, 19.9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometerReading {
    /// Time of validity, s.
    pub time: f64,
    /// Measured forward speed, m/s (negative when reversing).
    pub speed: f64,
}

impl OdometerReading {
    /// A reading at `time` (s) of `speed` (m/s).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::measurement::OdometerReading::new(2.0, 3.0).time, 2.0);
    /// ```
    pub fn new(time: f64, speed: f64) -> Self {
        Self { time, speed }
    }
}

/// An odometer and the vehicle's motion constraint: mounting, lever arm and
/// noise; builds the per-epoch vehicle-frame velocity measurements.
///
/// The vehicle (odometer) frame `v` is the body frame rotated by the
/// mounting angles, calibrated parameters: `C_v^b = R_z(yaw_m) R_y(pitch_m)`
/// (the vehicle's forward axis is the body's pitched up by `pitch_m` and
/// turned right by `yaw_m`; the simulation's
/// `TrajectorySpec::mounting` (in `kestrel-sim`) with
/// these pitch and yaw), `C_b^v = (C_v^b)ᵀ`. With `C = C_b^n`, `l` the
/// lever arm from the IMU to the odometer reference point (body, m),
/// `ω = ω_ib^b` the bias-corrected body rate and `ω_ie` the Earth rate
/// (NED), the INS predicts the vehicle-frame velocity of that point
/// relative to the Earth
///
/// ```text
/// v^v = C_b^v (Cᵀ v^n + ω_eb × l),   ω_eb = ω − Cᵀ ω_ie
/// ```
///
/// The odometer reads `s = (1 + k) s_true` (scale-factor error `k`); with the
/// estimate `k̂` fed back, the corrected speed is `ŝ = s / (1 + k̂)` and the
/// scale state is `δk = k − k̂`. The measurement is `z = v^v − [ŝ, 0, 0]`:
/// row 0 compares the forward speed with the odometer, rows 1 and 2 are the
/// non-holonomic constraint (no lateral or vertical motion of the vehicle).
/// With the crate's error definitions, to first order,
///
/// ```text
/// z = −C_b^v (Cᵀ [v^n×] + [l×] Cᵀ [ω_ie×]) φ + C_b^v Cᵀ δv − C_b^v [l×] b_g
///     − e₁ v̂/(1 + k̂) δk
/// ```
///
/// (`e₁ = [1, 0, 0]ᵀ`). With `s = (1 + k) s_true + n` (`n` the reading's
/// noise), `ŝ = s_true (1 + δk/(1 + k̂)) + n/(1 + k̂)`, so the scale column
/// is `−s_true/(1 + k̂)`, taken at the linearisation point: `v̂ = v^v_x`, the
/// INS's forward speed (the prior's estimate of the true speed). Not at
/// the measured `ŝ`: that would put the reading's noise into the gain, and
/// the gain times the innovation, both carrying `n`, would move `k̂` by
/// about `σ_n² P_kk / C` per update on average — on paper 003's drive
/// (`σ_n` 0.05 m/s, 10 Hz, 1 h) a bias of +4·10⁻⁴ in `k̂`, as large as its
/// σ (`crates/app/tests/suite/sins_dr.rs`). The scale
/// column exists only when the layout has an odometer scale state; without
/// one the scale is taken as known. Forward plus constraint (m = 3) equals
/// the navigation-frame velocity match `v_INS − C_b^n C_v^b [ŝ, 0, 0]ᵀ` of
/// paper 003, rotated into the vehicle frame.
///
/// ```
/// use kestrel_core::nalgebra::Vector3;
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
/// use kestrel_nav::measurement::{InsContext, Odometer, OdometerReading};
/// use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess};
/// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0),
///     Vector3::new(0.0, 20.0, 0.0), Euler::from_degrees(0.0, 0.0, 90.0));
/// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
/// let layout = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
/// let odo = Odometer::new(0.02, 0.1);
/// // The odometer reads 1 % fast.
/// let m = odo.forward_nhc::<f64, 16, _>(&layout, &ins, &OdometerReading::new(0.0, 20.2), 0.0);
/// assert!((m.z()[0] + 0.2).abs() < 1e-9);
/// assert!(m.z()[1].abs() < 1e-9 && m.z()[2].abs() < 1e-9);
/// // The scale column: −(the INS's forward speed)/(1 + k̂), not the reading.
/// assert!((m.h()[(0, 15)] + 20.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Odometer {
    /// Mounting pitch of the vehicle frame w.r.t. the body, rad.
    pub mount_pitch: f64,
    /// Mounting yaw of the vehicle frame w.r.t. the body, rad.
    pub mount_yaw: f64,
    /// IMU to the odometer reference point, body axes, m.
    pub lever_arm: Vector3<f64>,
    /// Standard deviation of the odometer speed, m/s.
    pub speed_std: f64,
    /// Standard deviation of the lateral and vertical vehicle velocity
    /// allowed by the non-holonomic constraint, m/s.
    pub nhc_std: Vector2<f64>,
}

impl Odometer {
    /// An odometer aligned with the body at the IMU, with speed noise
    /// `speed_std` and constraint noise `nhc_std` on both axes (m/s).
    ///
    /// ```
    /// let o = kestrel_nav::measurement::Odometer::new(0.05, 0.1);
    /// assert_eq!(o.nhc_std.y, 0.1);
    /// ```
    pub fn new(speed_std: f64, nhc_std: f64) -> Self {
        Self {
            mount_pitch: 0.0,
            mount_yaw: 0.0,
            lever_arm: Vector3::zeros(),
            speed_std,
            nhc_std: Vector2::repeat(nhc_std),
        }
    }

    /// The same odometer with calibrated mounting angles (rad).
    ///
    /// ```
    /// let o = kestrel_nav::measurement::Odometer::new(0.05, 0.1).with_mounting(0.01, -0.02);
    /// assert_eq!(o.mount_yaw, -0.02);
    /// ```
    pub fn with_mounting(self, pitch: f64, yaw: f64) -> Self {
        Self {
            mount_pitch: pitch,
            mount_yaw: yaw,
            ..self
        }
    }

    /// The same odometer at `lever_arm` (body, m).
    ///
    /// ```
    /// use kestrel_nav::nalgebra::Vector3;
    /// let o = kestrel_nav::measurement::Odometer::new(0.05, 0.1)
    ///     .with_lever_arm(Vector3::new(-1.0, 0.0, 1.2));
    /// assert_eq!(o.lever_arm.x, -1.0);
    /// ```
    pub fn with_lever_arm(self, lever_arm: Vector3<f64>) -> Self {
        Self { lever_arm, ..self }
    }

    /// `C_b^v`, body to vehicle frame.
    ///
    /// ```
    /// use kestrel_nav::nalgebra::Vector3;
    /// let o = kestrel_nav::measurement::Odometer::new(0.05, 0.1)
    ///     .with_mounting(0.0, std::f64::consts::FRAC_PI_2);
    /// // Vehicle forward is body right.
    /// assert!((o.body_to_vehicle() * Vector3::y() - Vector3::x()).norm() < 1e-15);
    /// ```
    pub fn body_to_vehicle(&self) -> Matrix3<f64> {
        let (sp, cp) = self.mount_pitch.sin_cos();
        let (sy, cy) = self.mount_yaw.sin_cos();
        let rz = Matrix3::new(cy, -sy, 0.0, sy, cy, 0.0, 0.0, 0.0, 1.0);
        let ry = Matrix3::new(cp, 0.0, sp, 0.0, 1.0, 0.0, -sp, 0.0, cp);
        (rz * ry).transpose()
    }

    /// Forward speed only (m = 1): `z = v^v_x − ŝ`, `R = speed_std²`.
    /// `scale` is the current estimate `k̂` of the scale-factor error.
    ///
    /// ```
    /// use kestrel_core::nalgebra::Vector3;
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::measurement::{InsContext, Odometer, OdometerReading};
    /// use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0),
    ///     Vector3::new(10.0, 0.0, 0.0), Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// let layout = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
    /// // A known 1 % scale error: the corrected speed matches.
    /// let m = Odometer::new(0.02, 0.1).forward::<f32, 16, _>(&layout, &ins,
    ///     &OdometerReading::new(0.0, 10.1), 0.01);
    /// assert!(m.z()[0].abs() < 1e-5);
    /// ```
    pub fn forward<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        layout: &L,
        ins: &InsContext,
        reading: &OdometerReading,
        scale: f64,
    ) -> ErrorMeasurement<T, N, 1> {
        self.rows::<T, N, L, 1>(layout, ins, reading.speed, scale, 0)
    }

    /// The non-holonomic constraint only (m = 2): `z = [v^v_y, v^v_z]`,
    /// `R = diag(nhc_std²)`; needs no odometer.
    ///
    /// ```
    /// use kestrel_core::nalgebra::Vector3;
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::engine::Ins15;
    /// use kestrel_nav::measurement::{InsContext, Odometer};
    /// // Heading north but moving north-east: 1 m/s of side slip to the right.
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0),
    ///     Vector3::new(10.0, 1.0, 0.0), Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// let m = Odometer::new(0.02, 0.1).nhc::<f64, 15, _>(&Ins15::new(ImuSpec::perfect()), &ins);
    /// assert!((m.z()[0] - 1.0).abs() < 1e-12);
    /// ```
    pub fn nhc<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        layout: &L,
        ins: &InsContext,
    ) -> ErrorMeasurement<T, N, 2> {
        self.rows::<T, N, L, 2>(layout, ins, 0.0, 0.0, 1)
    }

    /// Forward speed and the constraint (m = 3): `z = v^v − [ŝ, 0, 0]`,
    /// `R = diag(speed_std², nhc_std²)`.
    ///
    /// ```
    /// use kestrel_core::nalgebra::Vector3;
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState};
    /// use kestrel_nav::measurement::{InsContext, Odometer, OdometerReading};
    /// use kestrel_nav::odometer::{InsOdometer16, ScaleFactorProcess};
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0),
    ///     Vector3::new(10.0, 0.0, 0.0), Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// let layout = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
    /// let m = Odometer::new(0.02, 0.1).forward_nhc::<f64, 16, _>(&layout, &ins,
    ///     &OdometerReading::new(0.0, 10.0), 0.0);
    /// assert!((m.noise_covariance()[(1, 1)] - 0.01).abs() < 1e-15);
    /// ```
    pub fn forward_nhc<T: Real, const N: usize, L: ErrorLayout<N>>(
        &self,
        layout: &L,
        ins: &InsContext,
        reading: &OdometerReading,
        scale: f64,
    ) -> ErrorMeasurement<T, N, 3> {
        self.rows::<T, N, L, 3>(layout, ins, reading.speed, scale, 0)
    }

    /// Rows `first..first + M` of the full vehicle-frame measurement.
    fn rows<T: Real, const N: usize, L: ErrorLayout<N>, const M: usize>(
        &self,
        _layout: &L,
        ins: &InsContext,
        speed: f64,
        scale: f64,
        first: usize,
    ) -> ErrorMeasurement<T, N, M> {
        const { assert!(fits::<N, L>(), "error layout does not fit the state") };
        let c = ins.c_bn();
        let v = ins.state.vel;
        let cbv = self.body_to_vehicle();
        let cnv = cbv * c.transpose();
        let corrected = speed / (1.0 + scale);
        let w_ie = ins.earth.earth_rate_ned(ins.state.pos.lat);
        let w_eb = ins.omega_ib - c.transpose() * w_ie;
        let mut z = cnv * v + cbv * w_eb.cross(&self.lever_arm);
        // The INS's forward speed: the true speed's estimate at the
        // linearisation point (the prior), for the scale column.
        let forward = z.x;
        z.x -= corrected;
        let lx = skew(&self.lever_arm);
        let mut h = SMatrix::<f64, 3, N>::zeros();
        h.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-cnv * skew(&v) - cbv * lx * c.transpose() * skew(&w_ie)));
        h.fixed_view_mut::<3, 3>(0, 3).copy_from(&cnv);
        let hb = -cbv * lx;
        for &col in L::GYRO_BIAS {
            h.fixed_view_mut::<3, 3>(0, col).copy_from(&hb);
        }
        if let Some(col) = L::ODOMETER_SCALE {
            h[(0, col)] = -forward / (1.0 + scale);
        }
        let var = Vector3::new(
            self.speed_std * self.speed_std,
            self.nhc_std.x * self.nhc_std.x,
            self.nhc_std.y * self.nhc_std.y,
        );
        ErrorMeasurement::new(
            z.fixed_rows::<M>(first).into_owned(),
            h.fixed_rows::<M>(first).into_owned(),
            SVector::<f64, M>::from_iterator(var.iter().skip(first).copied()),
        )
    }
}
