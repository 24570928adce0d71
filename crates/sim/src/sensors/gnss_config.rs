//! What a simulated GNSS receiver outputs and how it goes wrong.

use nalgebra::Vector3;

use super::multipath::MultipathBursts;
use super::window::TimeWindow;

/// A change of the white measurement noise over a window (the base values
/// of [`GnssConfig`] apply outside every window; the first matching window
/// wins).
///
/// ```
/// use kestrel_nav::{nalgebra::Vector3};
/// use kestrel_sim::{NoiseWindow, TimeWindow};
/// let w = NoiseWindow::velocity(TimeWindow::new(50.0, 100.0), Vector3::repeat(1.5));
/// assert!(w.position_std.is_none());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseWindow {
    /// When the change applies.
    pub window: TimeWindow,
    /// Position noise σ north, east, down (m); `None` keeps the base.
    pub position_std: Option<Vector3<f64>>,
    /// Velocity noise σ north, east, down (m/s); `None` keeps the base.
    pub velocity_std: Option<Vector3<f64>>,
}

impl NoiseWindow {
    /// A window changing only the velocity noise σ (NED, m/s).
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{NoiseWindow, TimeWindow};
    /// let w = NoiseWindow::velocity(TimeWindow::new(0.0, 1.0), Vector3::repeat(3.0));
    /// assert_eq!(w.velocity_std, Some(Vector3::repeat(3.0)));
    /// ```
    pub fn velocity(window: TimeWindow, std: Vector3<f64>) -> Self {
        Self {
            window,
            position_std: None,
            velocity_std: Some(std),
        }
    }

    /// A window changing only the position noise σ (NED, m).
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{NoiseWindow, TimeWindow};
    /// let w = NoiseWindow::position(TimeWindow::new(0.0, 1.0), Vector3::repeat(30.0));
    /// assert!(w.velocity_std.is_none());
    /// ```
    pub fn position(window: TimeWindow, std: Vector3<f64>) -> Self {
        Self {
            window,
            position_std: Some(std),
            velocity_std: None,
        }
    }
}

/// How fixes inside an outlier window are corrupted (on top of the white
/// noise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OutlierKind {
    /// Every fix in the window is wrong: a constant offset plus an error
    /// drawn uniformly in `±amplitude`, per NED axis (multipath in an urban
    /// canyon; a patch of gross velocity errors).
    Patch {
        /// Position offset north, east, down, m.
        position_offset: Vector3<f64>,
        /// Half-width of the uniform position error per axis, m.
        position_amplitude: Vector3<f64>,
        /// Velocity offset north, east, down, m/s.
        velocity_offset: Vector3<f64>,
        /// Half-width of the uniform velocity error per axis, m/s.
        velocity_amplitude: Vector3<f64>,
    },
    /// Isolated gross errors: each fix in the window is hit with
    /// probability `probability`; a hit adds an error of uniformly random
    /// direction whose size is uniform in `[min, max]`.
    Spikes {
        /// Probability per fix, in [0, 1].
        probability: f64,
        /// Size range of the position error, m.
        position: (f64, f64),
        /// Size range of the velocity error, m/s.
        velocity: (f64, f64),
    },
    /// Randomly timed multipath / NLOS bursts inside the window (see
    /// [`MultipathBursts`]); a burst running at the end of the window
    /// stops there.
    Multipath(MultipathBursts),
}

/// An outlier episode.
///
/// ```
/// use kestrel_nav::{nalgebra::Vector3};
/// use kestrel_sim::{Outlier, TimeWindow};
/// let o = Outlier::velocity_patch(TimeWindow::new(350.0, 360.0), Vector3::new(15.0, 15.0, 0.0));
/// assert_eq!(o.window.duration(), 10.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outlier {
    /// When it happens.
    pub window: TimeWindow,
    /// What happens.
    pub kind: OutlierKind,
}

impl Outlier {
    /// A patch of velocity errors uniform in `±amplitude` (NED, m/s).
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{Outlier, OutlierKind, TimeWindow};
    /// let o = Outlier::velocity_patch(TimeWindow::new(0.0, 1.0), Vector3::repeat(1.0));
    /// assert!(matches!(o.kind, OutlierKind::Patch { .. }));
    /// ```
    pub fn velocity_patch(window: TimeWindow, amplitude: Vector3<f64>) -> Self {
        Self {
            window,
            kind: OutlierKind::Patch {
                position_offset: Vector3::zeros(),
                position_amplitude: Vector3::zeros(),
                velocity_offset: Vector3::zeros(),
                velocity_amplitude: amplitude,
            },
        }
    }

    /// A patch of position errors: a constant `offset` plus uniform
    /// `±amplitude` (NED, m).
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{Outlier, TimeWindow};
    /// let o = Outlier::position_patch(TimeWindow::new(0.0, 30.0), Vector3::new(12.0, -8.0, 20.0), Vector3::repeat(3.0));
    /// assert_eq!(o.window.end, 30.0);
    /// ```
    pub fn position_patch(
        window: TimeWindow,
        offset: Vector3<f64>,
        amplitude: Vector3<f64>,
    ) -> Self {
        Self {
            window,
            kind: OutlierKind::Patch {
                position_offset: offset,
                position_amplitude: amplitude,
                velocity_offset: Vector3::zeros(),
                velocity_amplitude: Vector3::zeros(),
            },
        }
    }
}

/// What the receiver reports as its standard deviations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportedStd {
    /// The base σ of the configuration, always (the receiver does not
    /// know when it is degraded).
    Nominal,
    /// The σ of the white noise in effect (noise windows included);
    /// outliers are never reported.
    Actual,
}

/// A GNSS receiver: fixes at `rate` Hz of the antenna's position and
/// (optionally) velocity with white noise, noise windows, outliers and
/// outages.
///
/// ```
/// use kestrel_nav::{nalgebra::Vector3};
/// use kestrel_sim::GnssConfig;
/// let c = GnssConfig::new(1.0, Vector3::new(5.0, 5.0, 5.0), Some(Vector3::repeat(0.3)));
/// assert!(c.outages.is_empty() && c.lever_arm == Vector3::zeros());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct GnssConfig {
    /// Fix rate, Hz; fixes fall at multiples of `1/rate` s (not at 0).
    pub rate: f64,
    /// Position white noise σ north, east, down, m.
    pub position_std: Vector3<f64>,
    /// Velocity white noise σ north, east, down (m/s); `None`: the receiver
    /// outputs no velocity.
    pub velocity_std: Option<Vector3<f64>>,
    /// Antenna position relative to the IMU in body axes (forward, right,
    /// down), m.
    pub lever_arm: Vector3<f64>,
    /// Noise changes.
    pub noise_windows: Vec<NoiseWindow>,
    /// Outlier episodes (they add up where they overlap).
    pub outliers: Vec<Outlier>,
    /// No fixes inside these windows.
    pub outages: Vec<TimeWindow>,
    /// What the fixes report as σ.
    pub reported_std: ReportedStd,
}

impl GnssConfig {
    /// A clean receiver: rate (Hz), position σ (NED, m), velocity σ (NED,
    /// m/s, `None` for no velocity), no lever arm, windows or outliers;
    /// reports the actual σ.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::GnssConfig;
    /// assert_eq!(GnssConfig::new(10.0, Vector3::repeat(1.0), None).rate, 10.0);
    /// ```
    pub fn new(rate: f64, position_std: Vector3<f64>, velocity_std: Option<Vector3<f64>>) -> Self {
        Self {
            rate,
            position_std,
            velocity_std,
            lever_arm: Vector3::zeros(),
            noise_windows: Vec::new(),
            outliers: Vec::new(),
            outages: Vec::new(),
            reported_std: ReportedStd::Actual,
        }
    }

    /// The white-noise σ (position m, velocity m/s; NED) in effect at `t`.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{GnssConfig, NoiseWindow, TimeWindow};
    /// let mut c = GnssConfig::new(1.0, Vector3::repeat(5.0), Some(Vector3::repeat(0.3)));
    /// c.noise_windows.push(NoiseWindow::velocity(TimeWindow::new(50.0, 100.0), Vector3::repeat(1.5)));
    /// assert_eq!(c.noise_at(60.0).1, Vector3::repeat(1.5));
    /// assert_eq!(c.noise_at(100.0).1, Vector3::repeat(0.3));
    /// ```
    pub fn noise_at(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let base_v = self.velocity_std.unwrap_or_else(Vector3::zeros);
        match self.noise_windows.iter().find(|w| w.window.contains(t)) {
            Some(w) => (
                w.position_std.unwrap_or(self.position_std),
                w.velocity_std.unwrap_or(base_v),
            ),
            None => (self.position_std, base_v),
        }
    }

    /// Whether `t` falls in an outage.
    ///
    /// ```
    /// use kestrel_nav::{nalgebra::Vector3};
    /// use kestrel_sim::{GnssConfig, TimeWindow};
    /// let mut c = GnssConfig::new(1.0, Vector3::repeat(5.0), None);
    /// c.outages.push(TimeWindow::new(10.0, 20.0));
    /// assert!(c.in_outage(10.0) && !c.in_outage(20.0));
    /// ```
    pub fn in_outage(&self, t: f64) -> bool {
        self.outages.iter().any(|w| w.contains(t))
    }
}
