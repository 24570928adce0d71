//! Seeded random numbers for the sensor models.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// The generator every sensor model uses: ChaCha with 8 rounds (fast,
/// statistically strong, identical on every platform).
pub type SimRng = ChaCha8Rng;

/// The independent random stream of each sensor kind: one scenario seed
/// drives all sensors without their draws interfering, so adding a sensor
/// does not change the noise of the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum SensorStream {
    /// IMU noise, Markov drifts.
    Imu = 1,
    /// GNSS noise and outliers.
    Gnss = 2,
    /// Odometer noise and faults.
    Odometer = 3,
    /// Attitude measurement noise.
    Attitude = 4,
    /// Draws of random constants (biases, scale factors, initial errors).
    Constants = 5,
    /// GNSS outlier draws (apart from the white noise, so adding an outlier
    /// window leaves the noise of every fix unchanged).
    GnssOutliers = 6,
    /// Odometer fault draws (apart from its white noise).
    OdometerFaults = 7,
    /// GNSS multipath burst draws ([`MultipathBursts`](super::MultipathBursts)),
    /// apart from the other outliers so adding bursts leaves them unchanged.
    GnssMultipath = 8,
}

/// The generator for `stream` under the scenario seed `seed`.
///
/// ```
/// use kestrel_sim::{sensor_rng, SensorStream};
/// use rand::RngExt;
/// let a: u64 = sensor_rng(7, SensorStream::Gnss).random();
/// let b: u64 = sensor_rng(7, SensorStream::Gnss).random();
/// let c: u64 = sensor_rng(7, SensorStream::Imu).random();
/// assert!(a == b && a != c);
/// ```
pub fn sensor_rng(seed: u64, stream: SensorStream) -> SimRng {
    let mut rng = SimRng::seed_from_u64(seed);
    rng.set_stream(stream as u64);
    rng
}

/// A standard normal draw.
#[inline]
pub(crate) fn normal(rng: &mut SimRng) -> f64 {
    rng.sample(StandardNormal)
}

/// Three independent standard normal draws.
#[inline]
pub(crate) fn normal3(rng: &mut SimRng) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::new(normal(rng), normal(rng), normal(rng))
}

/// A uniform draw in `[lo, hi)`.
#[inline]
pub(crate) fn uniform(rng: &mut SimRng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}
