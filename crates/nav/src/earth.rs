//! The Earth model: reference ellipsoid, curvature radii, normal gravity,
//! Earth and transport rates, and ECEF / NED conversions.
//!
//! Normal gravity is Somigliana's closed formula on the ellipsoid with the
//! second-order height correction of the WGS-84 definition (NIMA TR8350.2,
//! eq. 4-1 and 4-3):
//!
//! ```text
//! γ₀(L)   = γ_e (1 + k sin²L) / √(1 − e² sin²L),   k = b γ_p / (a γ_e) − 1
//! γ(L, h) = γ₀(L) [1 − (2/a)(1 + f + m − 2 f sin²L) h + (3/a²) h²],
//! m       = ω² a² b / GM
//! ```
//!
//! `γ_e`, `γ_p` (equatorial and polar normal gravity) follow from the four
//! defining constants `a, f, ω, GM` by the closed formulas of the level
//! ellipsoid (Moritz, Geodetic Reference System 1980), so any ellipsoid
//! given by its parameters gets a consistent field; for WGS-84 they give
//! γ_e = 9.7803253359 m/s² and γ_p = 9.8321849378 m/s².

use nalgebra::{Matrix3, Vector3};

use crate::geodetic::Geodetic;

/// A reference ellipsoid with its rotation rate and gravitational constant.
///
/// ```
/// use kestrel_nav::{Ellipsoid, Geodetic};
/// let wgs = Ellipsoid::wgs84();
/// let g = wgs.gravity(0.0, 0.0);
/// assert!((g - 9.7803253359).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Semi-major axis, m.
    pub a: f64,
    /// Flattening (dimensionless).
    pub f: f64,
    /// Earth rotation rate, rad/s.
    pub omega_ie: f64,
    /// Geocentric gravitational constant, m³/s².
    pub gm: f64,
}

impl Default for Ellipsoid {
    fn default() -> Self {
        Self::wgs84()
    }
}

impl Ellipsoid {
    /// WGS-84: a = 6 378 137 m, f = 1/298.257223563,
    /// ω = 7.292115e-5 rad/s, GM = 3.986004418e14 m³/s².
    ///
    /// ```
    /// assert_eq!(kestrel_nav::Ellipsoid::wgs84().a, 6_378_137.0);
    /// ```
    pub const fn wgs84() -> Self {
        Self {
            a: 6_378_137.0,
            f: 1.0 / 298.257_223_563,
            omega_ie: 7.292_115e-5,
            gm: 3.986_004_418e14,
        }
    }

    /// Krasovsky 1940 (used by paper 000): a = 6 378 245 m, f = 1/298.3,
    /// with the WGS-84 rotation rate and gravitational constant (the
    /// ellipsoid defines no field of its own).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::Ellipsoid::krasovsky().a, 6_378_245.0);
    /// ```
    pub const fn krasovsky() -> Self {
        Self {
            a: 6_378_245.0,
            f: 1.0 / 298.3,
            omega_ie: 7.292_115e-5,
            gm: 3.986_004_418e14,
        }
    }

    /// GRS-80: a = 6 378 137 m, f = 1/298.257222101, ω = 7.292115e-5 rad/s,
    /// GM = 3.986005e14 m³/s².
    ///
    /// ```
    /// assert!(kestrel_nav::Ellipsoid::grs80().f > kestrel_nav::Ellipsoid::wgs84().f);
    /// ```
    pub const fn grs80() -> Self {
        Self {
            a: 6_378_137.0,
            f: 1.0 / 298.257_222_101,
            omega_ie: 7.292_115e-5,
            gm: 3.986_005e14,
        }
    }

    /// First eccentricity squared, `e² = f (2 − f)`.
    ///
    /// ```
    /// let e2 = kestrel_nav::Ellipsoid::wgs84().e2();
    /// assert!((e2 - 0.00669437999014).abs() < 1e-14);
    /// ```
    #[inline]
    pub fn e2(&self) -> f64 {
        self.f * (2.0 - self.f)
    }

    /// Semi-minor axis `b = a (1 − f)`, m.
    ///
    /// ```
    /// let b = kestrel_nav::Ellipsoid::wgs84().b();
    /// assert!((b - 6_356_752.314245).abs() < 1e-6);
    /// ```
    #[inline]
    pub fn b(&self) -> f64 {
        self.a * (1.0 - self.f)
    }

    /// Meridian radius of curvature `R_M = a (1 − e²) / (1 − e² sin²L)^{3/2}`, m.
    ///
    /// ```
    /// let e = kestrel_nav::Ellipsoid::wgs84();
    /// assert!((e.meridian_radius(0.0) - 6_335_439.327).abs() < 1e-3);
    /// ```
    pub fn meridian_radius(&self, lat: f64) -> f64 {
        let e2 = self.e2();
        let w2 = 1.0 - e2 * lat.sin().powi(2);
        self.a * (1.0 - e2) / (w2 * w2.sqrt())
    }

    /// Prime-vertical radius of curvature `R_N = a / √(1 − e² sin²L)`, m.
    ///
    /// ```
    /// let e = kestrel_nav::Ellipsoid::wgs84();
    /// assert_eq!(e.prime_vertical_radius(0.0), e.a);
    /// ```
    pub fn prime_vertical_radius(&self, lat: f64) -> f64 {
        self.a / (1.0 - self.e2() * lat.sin().powi(2)).sqrt()
    }

    /// The normal-gravity constants of this ellipsoid (see the module
    /// documentation), for repeated evaluation.
    ///
    /// ```
    /// let n = kestrel_nav::Ellipsoid::wgs84().normal_gravity();
    /// assert!((n.gamma_p - 9.8321849378).abs() < 1e-9);
    /// ```
    pub fn normal_gravity(&self) -> NormalGravity {
        NormalGravity::new(self)
    }

    /// Normal gravity magnitude at latitude `lat` (rad) and height `h` (m),
    /// m/s², positive.
    ///
    /// ```
    /// let e = kestrel_nav::Ellipsoid::wgs84();
    /// assert!(e.gravity(0.5, 1000.0) < e.gravity(0.5, 0.0));
    /// ```
    pub fn gravity(&self, lat: f64, h: f64) -> f64 {
        self.normal_gravity().at(lat.sin().powi(2), h)
    }

    /// The normal gravity vector in NED, `[0, 0, g]`, m/s².
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// let g = Ellipsoid::wgs84().gravity_ned(&Geodetic::new(0.0, 0.0, 0.0));
    /// assert!(g.x == 0.0 && g.y == 0.0 && g.z > 9.78);
    /// ```
    pub fn gravity_ned(&self, pos: &Geodetic) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, self.gravity(pos.lat, pos.h))
    }

    /// The Earth rotation rate in NED, `ω_ie^n = [ω cos L, 0, −ω sin L]`, rad/s.
    ///
    /// ```
    /// let w = kestrel_nav::Ellipsoid::wgs84().earth_rate_ned(0.0);
    /// assert_eq!(w.x, 7.292115e-5);
    /// ```
    pub fn earth_rate_ned(&self, lat: f64) -> Vector3<f64> {
        let (s, c) = lat.sin_cos();
        Vector3::new(self.omega_ie * c, 0.0, -self.omega_ie * s)
    }

    /// The transport rate (rotation of NED over the ellipsoid),
    /// `ω_en^n = [v_E/(R_N+h), −v_N/(R_M+h), −v_E tan L/(R_N+h)]`, rad/s.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic, nalgebra::Vector3};
    /// let e = Ellipsoid::wgs84();
    /// let w = e.transport_rate_ned(&Geodetic::new(0.0, 0.0, 0.0), &Vector3::new(100.0, 0.0, 0.0));
    /// assert!((w.y + 100.0 / e.meridian_radius(0.0)).abs() < 1e-18);
    /// ```
    pub fn transport_rate_ned(&self, pos: &Geodetic, vel_ned: &Vector3<f64>) -> Vector3<f64> {
        let rm = self.meridian_radius(pos.lat) + pos.h;
        let rn = self.prime_vertical_radius(pos.lat) + pos.h;
        Vector3::new(
            vel_ned.y / rn,
            -vel_ned.x / rm,
            -vel_ned.y * pos.lat.tan() / rn,
        )
    }

    /// Earth-centred Earth-fixed coordinates of a geodetic position, m.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// let e = Ellipsoid::wgs84();
    /// let x = e.to_ecef(&Geodetic::from_degrees(90.0, 0.0, 0.0));
    /// assert!((x.z - e.b()).abs() < 1e-6 && x.x.abs() < 1e-6);
    /// ```
    pub fn to_ecef(&self, pos: &Geodetic) -> Vector3<f64> {
        let (sl, cl) = pos.lat.sin_cos();
        let (so, co) = pos.lon.sin_cos();
        let e2 = self.e2();
        let n = self.a / (1.0 - e2 * sl * sl).sqrt();
        Vector3::new(
            (n + pos.h) * cl * co,
            (n + pos.h) * cl * so,
            (n * (1.0 - e2) + pos.h) * sl,
        )
    }

    /// The geodetic position of an ECEF point (m), by Bowring's formula
    /// refined twice: far below 1 µm from the surface to satellite heights.
    /// Points near the Earth's centre have no meaningful geodetic position;
    /// the result there is finite but arbitrary.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// let e = Ellipsoid::wgs84();
    /// let p = Geodetic::from_degrees(40.1, 118.6, 100.0);
    /// let back = e.from_ecef(&e.to_ecef(&p));
    /// assert!((back.lat - p.lat).abs() < 1e-14 && (back.h - p.h).abs() < 1e-8);
    /// ```
    pub fn from_ecef(&self, ecef: &Vector3<f64>) -> Geodetic {
        let (a, b, e2) = (self.a, self.b(), self.e2());
        let ep2 = e2 / (1.0 - e2);
        let p = ecef.x.hypot(ecef.y);
        let z = ecef.z;
        // Parametric latitude guess, then Bowring's update; each refinement
        // raises the accuracy roughly to the third power.
        let mut beta = (a * z).atan2(b * p);
        let mut lat = 0.0;
        for _ in 0..3 {
            let (sb, cb) = beta.sin_cos();
            lat = (z + ep2 * b * sb * sb * sb).atan2(p - e2 * a * cb * cb * cb);
            beta = ((1.0 - self.f) * lat.sin()).atan2(lat.cos());
        }
        let (sl, cl) = lat.sin_cos();
        let n = a / (1.0 - e2 * sl * sl).sqrt();
        // Stable at every latitude (no division by cos L).
        let h = p * cl + z * sl - n * (1.0 - e2 * sl * sl);
        Geodetic::new(lat, ecef.y.atan2(ecef.x), h)
    }

    /// The rotation `C_n^e` from the NED frame at `pos` to ECEF.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic, nalgebra::Vector3};
    /// let c = Ellipsoid::wgs84().ned_to_ecef(&Geodetic::new(0.0, 0.0, 0.0));
    /// // At (0°, 0°) north is +z and down is −x.
    /// assert_eq!(c * Vector3::x(), Vector3::z());
    /// assert_eq!(c * Vector3::z(), -Vector3::x());
    /// ```
    pub fn ned_to_ecef(&self, pos: &Geodetic) -> Matrix3<f64> {
        let (sl, cl) = pos.lat.sin_cos();
        let (so, co) = pos.lon.sin_cos();
        Matrix3::new(
            -sl * co,
            -so,
            -cl * co,
            -sl * so,
            co,
            -cl * so,
            cl,
            0.0,
            -sl,
        )
    }

    /// The vector from `from` to `to` in the NED frame at `from`, m
    /// (a straight chord through ECEF, exact at any distance).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic};
    /// let e = Ellipsoid::wgs84();
    /// let a = Geodetic::from_degrees(30.0, 114.0, 0.0);
    /// let b = Geodetic::new(a.lat, a.lon, a.h - 5.0);
    /// assert!((e.ned_offset(&a, &b).z - 5.0).abs() < 1e-9);
    /// ```
    pub fn ned_offset(&self, from: &Geodetic, to: &Geodetic) -> Vector3<f64> {
        let d = self.to_ecef(to) - self.to_ecef(from);
        self.ned_to_ecef(from).transpose() * d
    }

    /// The position reached from `pos` by the NED displacement `d_ned` (m,
    /// in the frame at `pos`); the inverse of [`ned_offset`](Self::ned_offset).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Geodetic, nalgebra::Vector3};
    /// let e = Ellipsoid::wgs84();
    /// let a = Geodetic::from_degrees(34.0, 110.0, 200.0);
    /// let d = Vector3::new(1500.0, -800.0, 3.0);
    /// let b = e.displace(&a, &d);
    /// assert!((e.ned_offset(&a, &b) - d).norm() < 1e-6);
    /// ```
    pub fn displace(&self, pos: &Geodetic, d_ned: &Vector3<f64>) -> Geodetic {
        self.from_ecef(&(self.to_ecef(pos) + self.ned_to_ecef(pos) * d_ned))
    }
}

/// Precomputed constants of an ellipsoid's normal gravity field
/// (Somigliana with the WGS-84 height series; see the module documentation).
///
/// ```
/// use kestrel_nav::Ellipsoid;
/// let n = Ellipsoid::wgs84().normal_gravity();
/// let s2 = 0.7_f64.sin().powi(2);
/// assert!((n.at(s2, 50.0) - Ellipsoid::wgs84().gravity(0.7, 50.0)).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalGravity {
    /// Normal gravity at the equator, m/s².
    pub gamma_e: f64,
    /// Normal gravity at the poles, m/s².
    pub gamma_p: f64,
    /// Somigliana's constant `k = b γ_p / (a γ_e) − 1`.
    pub k: f64,
    /// `m = ω² a² b / GM`.
    pub m: f64,
    a: f64,
    f: f64,
    e2: f64,
}

impl NormalGravity {
    /// The constants of `e` (closed formulas of the level ellipsoid).
    ///
    /// ```
    /// let n = kestrel_nav::NormalGravity::new(&kestrel_nav::Ellipsoid::wgs84());
    /// assert!((n.gamma_e - 9.7803253359).abs() < 1e-9);
    /// ```
    pub fn new(e: &Ellipsoid) -> Self {
        let (a, b) = (e.a, e.b());
        let ep = (a * a - b * b).sqrt() / b;
        let at = ep.atan();
        let q0 = 0.5 * ((1.0 + 3.0 / (ep * ep)) * at - 3.0 / ep);
        let q0p = 3.0 * (1.0 + 1.0 / (ep * ep)) * (1.0 - at / ep) - 1.0;
        let m = e.omega_ie * e.omega_ie * a * a * b / e.gm;
        let gamma_e = e.gm / (a * b) * (1.0 - m - m / 6.0 * ep * q0p / q0);
        let gamma_p = e.gm / (a * a) * (1.0 + m / 3.0 * ep * q0p / q0);
        Self {
            gamma_e,
            gamma_p,
            k: b * gamma_p / (a * gamma_e) - 1.0,
            m,
            a,
            f: e.f,
            e2: e.e2(),
        }
    }

    /// Normal gravity, m/s², from `sin²L` and the height `h` (m).
    ///
    /// ```
    /// let n = kestrel_nav::Ellipsoid::wgs84().normal_gravity();
    /// assert!((n.at(1.0, 0.0) - n.gamma_p).abs() < 1e-12);
    /// ```
    #[inline]
    pub fn at(&self, sin2_lat: f64, h: f64) -> f64 {
        self.surface(sin2_lat) * self.height_factor(sin2_lat, h)
    }

    /// The derivatives of [`at`](Self::at) with respect to latitude (m/s² per
    /// rad) and height (m/s² per m), given `sin L` and `cos L`.
    ///
    /// ```
    /// let n = kestrel_nav::Ellipsoid::wgs84().normal_gravity();
    /// let (_, dh) = n.derivatives(0.5, 0.75_f64.sqrt(), 0.0);
    /// assert!((dh + 3.086e-6).abs() < 1e-8); // the free-air gradient
    /// ```
    pub fn derivatives(&self, sin_lat: f64, cos_lat: f64, h: f64) -> (f64, f64) {
        let s2 = sin_lat * sin_lat;
        let w2 = 1.0 - self.e2 * s2;
        let g0 = self.surface(s2);
        // d γ₀ / d(sin²L) and d(height factor) / d(sin²L).
        let dg0 = self.gamma_e * (self.k + 0.5 * self.e2 * (1.0 + self.k * s2) / w2) / w2.sqrt();
        let dfac = 4.0 * self.f * h / self.a;
        let ds2 = 2.0 * sin_lat * cos_lat;
        let fac = self.height_factor(s2, h);
        let dlat = (dg0 * fac + g0 * dfac) * ds2;
        let dh = g0
            * (-2.0 / self.a * (1.0 + self.f + self.m - 2.0 * self.f * s2)
                + 6.0 * h / (self.a * self.a));
        (dlat, dh)
    }

    #[inline]
    fn surface(&self, s2: f64) -> f64 {
        self.gamma_e * (1.0 + self.k * s2) / (1.0 - self.e2 * s2).sqrt()
    }

    #[inline]
    fn height_factor(&self, s2: f64, h: f64) -> f64 {
        1.0 - 2.0 / self.a * (1.0 + self.f + self.m - 2.0 * self.f * s2) * h
            + 3.0 / (self.a * self.a) * h * h
    }
}
