//! A GNSS receiver model producing position / velocity fixes.

use nalgebra::Vector3;
use rand::RngExt;
use rand_distr::UnitSphere;

use super::gnss_config::{GnssConfig, OutlierKind, ReportedStd};
use super::multipath::{maybe_start, Burst};
use super::rng::{normal3, sensor_rng, uniform, SensorStream, SimRng};
use super::schedule::Schedule;
use super::simulated::Simulated;
use kestrel_nav::earth::Ellipsoid;
use kestrel_nav::geodetic::Geodetic;
use kestrel_nav::measurement::GnssFix;
use kestrel_nav::state::NavState;

/// Samples [`GnssConfig`] along a trajectory. Call
/// [`sample`](Self::sample) at every truth epoch; it returns a fix when a
/// fix time (a multiple of `1/rate`) is reached and no outage is active,
/// flagged faulty when an outlier was injected into it. The fix carries a
/// velocity when the configuration has a velocity σ, and the σ the
/// configuration says to report. White noise comes from its own seeded
/// stream ([`SensorStream::Gnss`]), drawn for every fix whatever the
/// windows and outages, and outliers from another
/// ([`SensorStream::GnssOutliers`]), so editing a window leaves the noise
/// of every fix unchanged; multipath bursts draw from a third
/// ([`SensorStream::GnssMultipath`]).
///
/// ```
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
/// use kestrel_sim::{GnssConfig, GnssSensor};
/// let mut gnss = GnssSensor::new(GnssConfig::new(1.0, Vector3::repeat(5.0), None), Ellipsoid::wgs84(), 9);
/// let truth = |t| NavState::new(t, Geodetic::from_degrees(40.1, 118.6, 100.0), Vector3::zeros(), Euler::default());
/// assert!(gnss.sample(&truth(0.5), &Vector3::zeros()).is_none());
/// let fix = gnss.sample(&truth(1.0), &Vector3::zeros()).unwrap();
/// assert_eq!((fix.value.time, fix.value.vel, fix.faulty), (1.0, None, false));
/// assert!(gnss.sample(&truth(1.5), &Vector3::zeros()).is_none());
/// ```
#[derive(Clone, Debug)]
pub struct GnssSensor {
    config: GnssConfig,
    earth: Ellipsoid,
    rng: SimRng,
    outlier_rng: SimRng,
    multipath_rng: SimRng,
    /// The burst in progress per outlier episode (used by
    /// [`OutlierKind::Multipath`] only).
    bursts: Vec<Option<Burst>>,
    schedule: Schedule,
}

impl GnssSensor {
    /// A receiver on `earth` with noise from `seed`.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, nalgebra::Vector3};
    /// use kestrel_sim::{GnssConfig, GnssSensor};
    /// let g = GnssSensor::new(GnssConfig::new(1.0, Vector3::repeat(1.0), None), Ellipsoid::wgs84(), 0);
    /// assert_eq!(g.config().rate, 1.0);
    /// ```
    pub fn new(config: GnssConfig, earth: Ellipsoid, seed: u64) -> Self {
        Self {
            earth,
            rng: sensor_rng(seed, SensorStream::Gnss),
            outlier_rng: sensor_rng(seed, SensorStream::GnssOutliers),
            multipath_rng: sensor_rng(seed, SensorStream::GnssMultipath),
            bursts: vec![None; config.outliers.len()],
            config,
            schedule: Schedule::new(),
        }
    }

    /// The configuration.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, nalgebra::Vector3};
    /// use kestrel_sim::{GnssConfig, GnssSensor};
    /// let g = GnssSensor::new(GnssConfig::new(2.0, Vector3::repeat(1.0), None), Ellipsoid::wgs84(), 0);
    /// assert!(g.config().velocity_std.is_none());
    /// ```
    pub fn config(&self) -> &GnssConfig {
        &self.config
    }

    /// The true antenna position and NED velocity for the truth `truth`
    /// and the body rate over NED `omega_nb` (rad/s, body axes):
    /// `r + C_b^n l` and `v + C_b^n (ω_eb^b × l)`, the velocity expressed in
    /// the NED frame at the antenna.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_sim::{GnssConfig, GnssSensor};
    /// let mut c = GnssConfig::new(1.0, Vector3::repeat(1.0), None);
    /// c.lever_arm = Vector3::new(1.0, 0.0, 0.0);
    /// let g = GnssSensor::new(c, Ellipsoid::wgs84(), 0);
    /// // Heading east, yawing right at 0.1 rad/s: the antenna 1 m ahead moves south at 0.1 m/s.
    /// let s = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(), Euler::from_degrees(0.0, 0.0, 90.0));
    /// let (_, v) = g.antenna(&s, &Vector3::new(0.0, 0.0, 0.1));
    /// assert!((v.x + 0.1).abs() < 1e-6 && v.y.abs() < 1e-6);
    /// ```
    pub fn antenna(&self, truth: &NavState, omega_nb: &Vector3<f64>) -> (Geodetic, Vector3<f64>) {
        let l = self.config.lever_arm;
        if l == Vector3::zeros() {
            return (truth.pos, truth.vel);
        }
        let c_bn = truth.att.to_rotation_matrix().into_inner();
        let w_en = self.earth.transport_rate_ned(&truth.pos, &truth.vel);
        let w_eb = omega_nb + c_bn.transpose() * w_en;
        let pos = self.earth.displace(&truth.pos, &(c_bn * l));
        let vel = truth.vel + c_bn * w_eb.cross(&l);
        // A receiver reports the velocity in the antenna's own NED frame,
        // turned by about |l|/R from the IMU's (≈ 2e-5 m/s at 80 m/s, 1.5 m).
        let to_antenna =
            self.earth.ned_to_ecef(&pos).transpose() * self.earth.ned_to_ecef(&truth.pos);
        (pos, to_antenna * vel)
    }

    /// The fix due at `truth.time`, if any (see the type's documentation).
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_sim::{GnssConfig, GnssSensor, TimeWindow};
    /// let mut c = GnssConfig::new(1.0, Vector3::repeat(5.0), Some(Vector3::repeat(0.1)));
    /// c.outages.push(TimeWindow::new(2.0, 3.0));
    /// let mut g = GnssSensor::new(c, Ellipsoid::wgs84(), 1);
    /// let s = |t| NavState::new(t, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(), Euler::default());
    /// let fixes: Vec<f64> = (1..=4).filter_map(|t| g.sample(&s(t as f64), &Vector3::zeros()))
    ///     .map(|f| f.value.time).collect();
    /// assert_eq!(fixes, vec![1.0, 3.0, 4.0]);
    /// ```
    pub fn sample(
        &mut self,
        truth: &NavState,
        omega_nb: &Vector3<f64>,
    ) -> Option<Simulated<GnssFix>> {
        let t = truth.time;
        if !self.schedule.due(t, self.config.rate) {
            return None;
        }

        let (std_p, std_v) = self.config.noise_at(t);
        let mut err_p = std_p.component_mul(&normal3(&mut self.rng));
        let mut err_v = std_v.component_mul(&normal3(&mut self.rng));
        let mut outlier = false;
        for (o, burst) in self.config.outliers.iter().zip(self.bursts.iter_mut()) {
            if !o.window.contains(t) {
                *burst = None;
                continue;
            }
            match o.kind {
                OutlierKind::Patch {
                    position_offset,
                    position_amplitude,
                    velocity_offset,
                    velocity_amplitude,
                } => {
                    err_p += position_offset
                        + signed_uniform(&mut self.outlier_rng, &position_amplitude);
                    err_v += velocity_offset
                        + signed_uniform(&mut self.outlier_rng, &velocity_amplitude);
                    outlier = true;
                }
                OutlierKind::Spikes {
                    probability,
                    position,
                    velocity,
                } => {
                    if self.outlier_rng.random::<f64>() < probability {
                        err_p += random_vector(&mut self.outlier_rng, position);
                        err_v += random_vector(&mut self.outlier_rng, velocity);
                        outlier = true;
                    }
                }
                OutlierKind::Multipath(m) => {
                    let rng = &mut self.multipath_rng;
                    let mut error = burst.and_then(|b| b.error(&m, t, rng));
                    if error.is_none() {
                        *burst = maybe_start(&m, t, rng);
                        error = burst.and_then(|b| b.error(&m, t, rng));
                    }
                    if let Some((p, v)) = error {
                        err_p += p;
                        err_v += v;
                        outlier = true;
                    } else {
                        *burst = None;
                    }
                }
            }
        }
        if self.config.in_outage(t) {
            return None;
        }
        let (pos, vel) = self.antenna(truth, omega_nb);
        let (rep_p, rep_v) = match self.config.reported_std {
            ReportedStd::Actual => (std_p, std_v),
            ReportedStd::Nominal => (
                self.config.position_std,
                self.config.velocity_std.unwrap_or_else(Vector3::zeros),
            ),
        };
        let has_vel = self.config.velocity_std.is_some();
        Some(Simulated {
            value: GnssFix {
                time: t,
                pos: self.earth.displace(&pos, &err_p),
                vel: has_vel.then(|| vel + err_v),
                pos_std: rep_p,
                vel_std: rep_v,
            },
            faulty: outlier,
        })
    }
}

/// Per-axis uniform draws in `±amplitude`.
fn signed_uniform(rng: &mut SimRng, amplitude: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(
        uniform(rng, -amplitude.x, amplitude.x),
        uniform(rng, -amplitude.y, amplitude.y),
        uniform(rng, -amplitude.z, amplitude.z),
    )
}

/// A vector of uniformly random direction with a size uniform in `range`.
fn random_vector(rng: &mut SimRng, range: (f64, f64)) -> Vector3<f64> {
    let d: [f64; 3] = rng.sample(UnitSphere);
    Vector3::from(d) * uniform(rng, range.0, range.1)
}
