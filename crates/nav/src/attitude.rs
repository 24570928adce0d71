//! Attitude representations and small-angle error rotations.
//!
//! Conventions: `C_b^n` rotates body (forward-right-down) vectors into NED;
//! Euler angles are ZYX, `C_b^n = Rz(yaw) · Ry(pitch) · Rx(roll)`, yaw
//! measured from north towards east. A rotation vector `φ` stands for the
//! rotation `exp([φ×])`.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Roll, pitch and yaw in radians (ZYX order).
///
/// ```
/// use kestrel_nav::Euler;
/// let e = Euler::from_degrees(10.0, -20.0, 135.0);
/// let back = Euler::from_quaternion(&e.to_quaternion());
/// assert!((back.yaw - e.yaw).abs() < 1e-12 && (back.pitch - e.pitch).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Euler {
    /// Rotation about the body x (forward) axis, rad.
    pub roll: f64,
    /// Rotation about the body y (right) axis, rad.
    pub pitch: f64,
    /// Rotation about the down axis, from north towards east, rad.
    pub yaw: f64,
}

impl Euler {
    /// Angles in radians.
    ///
    /// ```
    /// let e = kestrel_nav::Euler::new(0.1, 0.2, 0.3);
    /// assert_eq!(e.pitch, 0.2);
    /// ```
    pub const fn new(roll: f64, pitch: f64, yaw: f64) -> Self {
        Self { roll, pitch, yaw }
    }

    /// Angles in degrees.
    ///
    /// ```
    /// let e = kestrel_nav::Euler::from_degrees(0.0, 0.0, 180.0);
    /// assert_eq!(e.yaw, std::f64::consts::PI);
    /// ```
    pub fn from_degrees(roll_deg: f64, pitch_deg: f64, yaw_deg: f64) -> Self {
        Self::new(
            roll_deg.to_radians(),
            pitch_deg.to_radians(),
            yaw_deg.to_radians(),
        )
    }

    /// The angles in degrees as `[roll, pitch, yaw]`.
    ///
    /// ```
    /// let d = kestrel_nav::Euler::from_degrees(1.0, 2.0, 3.0).to_degrees();
    /// assert!((d[2] - 3.0).abs() < 1e-12);
    /// ```
    pub fn to_degrees(&self) -> [f64; 3] {
        [
            self.roll.to_degrees(),
            self.pitch.to_degrees(),
            self.yaw.to_degrees(),
        ]
    }

    /// The quaternion of `C_b^n = Rz(yaw) Ry(pitch) Rx(roll)`.
    ///
    /// ```
    /// use kestrel_nav::{Euler, nalgebra::Vector3};
    /// // Yaw 90°: the body forward axis points east.
    /// let q = Euler::from_degrees(0.0, 0.0, 90.0).to_quaternion();
    /// assert!((q * Vector3::x() - Vector3::y()).norm() < 1e-15);
    /// ```
    pub fn to_quaternion(&self) -> UnitQuaternion<f64> {
        let (sr, cr) = (0.5 * self.roll).sin_cos();
        let (sp, cp) = (0.5 * self.pitch).sin_cos();
        let (sy, cy) = (0.5 * self.yaw).sin_cos();
        UnitQuaternion::new_unchecked(Quaternion::new(
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ))
    }

    /// The angles of a `C_b^n` quaternion; pitch in [−π/2, π/2], roll and
    /// yaw in (−π, π]. At pitch ±90° roll and yaw are not separable and the
    /// split returned is arbitrary but finite.
    ///
    /// ```
    /// use kestrel_nav::Euler;
    /// let q = Euler::new(0.3, -0.4, -2.5).to_quaternion();
    /// let e = Euler::from_quaternion(&q);
    /// assert!((e.roll - 0.3).abs() < 1e-12 && (e.yaw + 2.5).abs() < 1e-12);
    /// ```
    pub fn from_quaternion(q: &UnitQuaternion<f64>) -> Self {
        let (w, x, y, z) = (q.w, q.i, q.j, q.k);
        // C31 = 2(xz − wy) = −sin(pitch); clamp so rounding never yields NaN.
        let sp = (-2.0 * (x * z - w * y)).clamp(-1.0, 1.0);
        Self {
            roll: (2.0 * (y * z + w * x)).atan2(1.0 - 2.0 * (x * x + y * y)),
            pitch: sp.asin(),
            yaw: (2.0 * (x * y + w * z)).atan2(1.0 - 2.0 * (y * y + z * z)),
        }
    }
}

impl Euler {
    /// The direction cosine matrix `C_b^n = Rz(yaw) Ry(pitch) Rx(roll)`.
    ///
    /// ```
    /// use kestrel_nav::Euler;
    /// // Pitch 90°: C31 = −sin(pitch) = −1.
    /// let c = Euler::from_degrees(0.0, 90.0, 0.0).to_dcm();
    /// assert!((c[(2, 0)] + 1.0).abs() < 1e-15);
    /// ```
    pub fn to_dcm(&self) -> Matrix3<f64> {
        let (sr, cr) = self.roll.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let (sy, cy) = self.yaw.sin_cos();
        Matrix3::new(
            cp * cy,
            sr * sp * cy - cr * sy,
            cr * sp * cy + sr * sy,
            cp * sy,
            sr * sp * sy + cr * cy,
            cr * sp * sy - sr * cy,
            -sp,
            sr * cp,
            cr * cp,
        )
    }

    /// The angles of a direction cosine matrix `C_b^n` (same ranges as
    /// [`from_quaternion`](Self::from_quaternion)).
    ///
    /// ```
    /// use kestrel_nav::Euler;
    /// let e = Euler::new(-0.4, 0.7, 2.9);
    /// let back = Euler::from_dcm(&e.to_dcm());
    /// assert!((back.roll + 0.4).abs() < 1e-12 && (back.yaw - 2.9).abs() < 1e-12);
    /// ```
    pub fn from_dcm(c: &Matrix3<f64>) -> Self {
        Self {
            roll: c[(2, 1)].atan2(c[(2, 2)]),
            pitch: (-c[(2, 0)]).clamp(-1.0, 1.0).asin(),
            yaw: c[(1, 0)].atan2(c[(0, 0)]),
        }
    }
}

/// The skew-symmetric (cross-product) matrix: `skew(a) · b = a × b`.
///
/// ```
/// use kestrel_nav::{skew, nalgebra::Vector3};
/// let (a, b) = (Vector3::new(1.0, 2.0, 3.0), Vector3::new(-2.0, 0.5, 4.0));
/// assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
/// ```
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The unit quaternion of the rotation `exp([φ×])` (angle `|φ|` about
/// `φ/|φ|`). Exact; uses the Taylor series of `cos(|φ|/2)` and
/// `sin(|φ|/2)/|φ|` below 0.1 rad, where it is accurate to rounding and
/// avoids the trigonometric calls of the per-step mechanisation.
///
/// ```
/// use kestrel_nav::{rotation_vector_to_quaternion, nalgebra::Vector3};
/// let q = rotation_vector_to_quaternion(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
/// assert!((q * Vector3::x() - Vector3::y()).norm() < 1e-15);
/// ```
#[inline]
pub fn rotation_vector_to_quaternion(phi: &Vector3<f64>) -> UnitQuaternion<f64> {
    let n2 = phi.norm_squared();
    let (c, s) = if n2 < 1e-2 {
        // x = |φ|/2, x² = n2/4; terms up to x⁸ leave an error below 1e-19.
        let x2 = 0.25 * n2;
        let c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0)));
        // sin(x)/|φ| = (1/2)·sin(x)/x
        let s = 0.5 * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))));
        (c, s)
    } else {
        let n = n2.sqrt();
        let (sh, ch) = (0.5 * n).sin_cos();
        (ch, sh / n)
    };
    UnitQuaternion::new_unchecked(Quaternion::new(c, s * phi.x, s * phi.y, s * phi.z))
}

/// The rotation vector `φ` of a unit quaternion, with `|φ| ≤ π`
/// (the inverse of [`rotation_vector_to_quaternion`]).
///
/// ```
/// use kestrel_nav::{quaternion_to_rotation_vector, rotation_vector_to_quaternion,
///     nalgebra::Vector3};
/// let phi = Vector3::new(0.3, -1.2, 0.7);
/// let back = quaternion_to_rotation_vector(&rotation_vector_to_quaternion(&phi));
/// assert!((back - phi).norm() < 1e-14);
/// ```
pub fn quaternion_to_rotation_vector(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    // q and −q are the same rotation; pick w ≥ 0 so the angle is ≤ π.
    let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
    let (w, v) = (sign * q.w, sign * q.imag());
    let s2 = v.norm_squared();
    let scale = if s2 < 1e-12 {
        // 2·atan2(s, w)/s = (2/w)(1 − s²/(3w²) + …); w ≈ 1 here.
        2.0 / w * (1.0 - s2 / (3.0 * w * w))
    } else {
        let s = s2.sqrt();
        2.0 * s.atan2(w) / s
    };
    v * scale
}

/// The first-order error rotation `I − [φ×]`, which maps the true
/// `C_b^n` to a computed one tilted by the attitude error `φ` (NED, rad):
/// `C_b^n(computed) = (I − [φ×]) C_b^n(true)`.
///
/// ```
/// use kestrel_nav::{error_rotation, skew, nalgebra::{Matrix3, Vector3}};
/// let phi = Vector3::new(1e-3, 0.0, 0.0);
/// assert_eq!(error_rotation(&phi), Matrix3::identity() - skew(&phi));
/// ```
pub fn error_rotation(phi: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::identity() - skew(phi)
}

/// The attitude error `φ` (NED, rad) of a computed `C_b^n` with respect to
/// the true one, exact for any size: `C(computed) = exp(−[φ×]) C(true)`,
/// which is `(I − [φ×]) C(true)` to first order.
///
/// ```
/// use kestrel_nav::{attitude_error, Euler, nalgebra::Vector3};
/// let truth = Euler::from_degrees(0.0, 0.0, 30.0).to_quaternion();
/// let computed = Euler::from_degrees(0.0, 0.0, 30.1).to_quaternion();
/// // Yaw too large by 0.1°: the error about down is −0.1°.
/// let phi = attitude_error(&computed, &truth);
/// assert!((phi - Vector3::new(0.0, 0.0, -0.1_f64.to_radians())).norm() < 1e-12);
/// ```
pub fn attitude_error(computed: &UnitQuaternion<f64>, truth: &UnitQuaternion<f64>) -> Vector3<f64> {
    quaternion_to_rotation_vector(&(truth * computed.inverse()))
}

/// Removes an attitude error `φ` (NED, rad) from a computed `C_b^n`:
/// returns `exp([φ×]) C(computed)`, the inverse of [`attitude_error`].
///
/// ```
/// use kestrel_nav::{attitude_error, correct_attitude, Euler, nalgebra::Vector3};
/// let truth = Euler::new(0.1, 0.2, 0.3).to_quaternion();
/// let computed = Euler::new(0.1, 0.2, 0.31).to_quaternion();
/// let fixed = correct_attitude(&computed, &attitude_error(&computed, &truth));
/// assert!(fixed.angle_to(&truth) < 1e-14);
/// ```
pub fn correct_attitude(computed: &UnitQuaternion<f64>, phi: &Vector3<f64>) -> UnitQuaternion<f64> {
    let q = rotation_vector_to_quaternion(phi) * computed;
    UnitQuaternion::new_normalize(q.into_inner())
}
