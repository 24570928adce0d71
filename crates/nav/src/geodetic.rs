//! Geodetic position on an ellipsoid.

/// A geodetic position: latitude and longitude in radians, ellipsoidal
/// height in metres.
///
/// Positions are kept in `f64`: an `f32` latitude resolves only about
/// 1e-7 rad, i.e. roughly 0.5 m on the Earth's surface, too coarse for
/// navigation.
///
/// ```
/// use kestrel_nav::Geodetic;
/// let p = Geodetic::from_degrees(45.0, 120.0, 100.0);
/// assert!((p.lat - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
/// assert_eq!(p.h, 100.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geodetic {
    /// Geodetic latitude, rad, positive north.
    pub lat: f64,
    /// Longitude, rad, positive east.
    pub lon: f64,
    /// Height above the ellipsoid, m.
    pub h: f64,
}

impl Geodetic {
    /// A position from latitude and longitude in radians and height in metres.
    ///
    /// ```
    /// let p = kestrel_nav::Geodetic::new(0.5, 2.0, 10.0);
    /// assert_eq!(p.lon, 2.0);
    /// ```
    pub const fn new(lat: f64, lon: f64, h: f64) -> Self {
        Self { lat, lon, h }
    }

    /// A position from latitude and longitude in degrees and height in metres.
    ///
    /// ```
    /// let p = kestrel_nav::Geodetic::from_degrees(-90.0, 180.0, 0.0);
    /// assert_eq!(p.lat, -std::f64::consts::FRAC_PI_2);
    /// ```
    pub fn from_degrees(lat_deg: f64, lon_deg: f64, h: f64) -> Self {
        Self::new(lat_deg.to_radians(), lon_deg.to_radians(), h)
    }

    /// Latitude in degrees.
    ///
    /// ```
    /// let p = kestrel_nav::Geodetic::from_degrees(30.0, 0.0, 0.0);
    /// assert!((p.lat_deg() - 30.0).abs() < 1e-12);
    /// ```
    pub fn lat_deg(&self) -> f64 {
        self.lat.to_degrees()
    }

    /// Longitude in degrees.
    ///
    /// ```
    /// let p = kestrel_nav::Geodetic::from_degrees(0.0, 118.5, 0.0);
    /// assert!((p.lon_deg() - 118.5).abs() < 1e-12);
    /// ```
    pub fn lon_deg(&self) -> f64 {
        self.lon.to_degrees()
    }
}
