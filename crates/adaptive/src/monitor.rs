//! A filter-health monitor: does a χ²-distributed consistency statistic
//! (the NIS of one measurement kind, or with a truth the NEES) stay inside
//! its bound, window after window?

use kestrel_core::real::lit;
use kestrel_core::{FilterError, Real};

use crate::chi_square_quantile;

/// What a [`ConsistencyMonitor`] concluded from a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MonitorEvent<T> {
    /// [`windows`](ConsistencyMonitor::windows) windows in a row exceeded
    /// the bound: the filter's covariance no longer describes the
    /// statistic (it is diverging, or its data are worse than its model).
    /// `level` is the last window's mean statistic per degree of freedom
    /// (1 for a consistent filter).
    Alarm {
        /// Mean of the last window per degree of freedom.
        level: T,
    },
    /// `windows × window` updates in a row were refused by the filter's
    /// adapters: it no longer takes its measurements (a gate locked out).
    Refusing,
    /// After an alarm (or refusal), `windows` windows in a row inside the
    /// bound: consistent again.
    Recovered,
}

/// How the window bound of a [`ConsistencyMonitor`] treats its samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleDependence {
    /// Independent samples (the innovations of a consistent Kalman filter
    /// are white): a window of `w` samples of `χ²(m)` sums to `χ²(w·m)`,
    /// and the bound is its `1 − α` quantile.
    Independent,
    /// Samples correlated from one to the next (the estimation errors of
    /// consecutive epochs): the bound is `w` times the `1 − α` quantile of
    /// one sample, `χ²_{1−α}(m)`. The window mean of positively correlated
    /// samples is never more spread than one sample (fully correlated
    /// samples have the mean equal to each), so a consistent filter fails
    /// a window with probability at most `α` whatever the correlation.
    Correlated,
}

/// Tests a consistency statistic of `m` degrees of freedom window by
/// window and raises an alarm after `k` failing windows in a row.
///
/// The samples fill non-overlapping windows of `w` samples; a window
/// fails when the sum of its samples exceeds the bound
/// ([`SampleDependence`]: `χ²_{1−α}(w·m)` for independent samples,
/// `w · χ²_{1−α}(m)` for correlated ones). [`push`](Self::push) returns
/// [`MonitorEvent::Alarm`] at the end of the `k`-th failing window in a
/// row and [`MonitorEvent::Recovered`] at the end of the `k`-th passing
/// window in a row after it. A non-finite sample fails its window.
/// Updates the filter refused are not samples ([`refuse`](Self::refuse)):
/// an adapter that rejects an outlier has not been misled by it; `k·w`
/// refusals in a row raise [`MonitorEvent::Refusing`].
///
/// Defaults ([`innovations`](Self::innovations),
/// [`errors`](Self::errors)): `w = 20`, `k = 3`, `α = 10⁻³` for
/// independent samples (`10⁻⁴` for correlated ones). A consistent filter
/// fails a window of independent samples with probability `α`, so three
/// in a row with `α³ = 10⁻⁹`: no false alarm is expected in any realistic
/// run (a 1 h run at 10 Hz has 1800 windows). A filter running
/// away fails every window: the alarm comes `k·w` updates after the
/// start, 60 s at 1 Hz and 6 s at 10 Hz (plus the part of the first
/// window before it).
///
/// Nothing allocates; `push` costs an addition and a comparison.
///
/// ```
/// use kestrel_adaptive::{ConsistencyMonitor, MonitorEvent};
/// // NIS of a 6-row measurement: windows of 20, bound χ²₀.₉₉₉(120) ≈ 173.6.
/// let mut m = ConsistencyMonitor::<f64>::innovations(6).unwrap();
/// assert!((m.bound() - 173.617).abs() < 1e-2);
/// // 60 consistent updates (NIS = 6, the mean): nothing happens.
/// assert!((0..60).all(|_| m.push(6.0).is_none()));
/// // A runaway: every NIS 50. The alarm comes at the end of the 3rd window.
/// let events: Vec<_> = (0..60).filter_map(|_| m.push(50.0)).collect();
/// assert_eq!(events, [MonitorEvent::Alarm { level: 50.0 / 6.0 }]);
/// assert!(m.alarm());
/// // Back to normal: recovered after 3 windows.
/// let events: Vec<_> = (0..60).filter_map(|_| m.push(6.0)).collect();
/// assert_eq!(events, [MonitorEvent::Recovered]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConsistencyMonitor<T> {
    dof: usize,
    window: usize,
    windows: usize,
    bound: T,
    sum: T,
    broken: bool,
    count: usize,
    failing: usize,
    passing: usize,
    refused: usize,
    alarm: bool,
}

impl<T: Real> ConsistencyMonitor<T> {
    /// Samples per window of the default monitors.
    pub const WINDOW: usize = 20;
    /// Failing windows in a row that raise the alarm (and passing ones
    /// that clear it) in the default monitors.
    pub const WINDOWS: usize = 3;
    /// The probability that a consistent filter fails one window of
    /// independent samples, in the default innovation monitor.
    pub const SIGNIFICANCE: f64 = 1e-3;
    /// The bound on the probability that a consistent filter fails one
    /// window of correlated samples, in the default error (NEES) monitor:
    /// smaller than [`SIGNIFICANCE`](Self::SIGNIFICANCE) because
    /// correlated windows are not independent chances. Three windows in a
    /// row are then about as likely as one (errors that last), so a run
    /// with `n` independent error episodes raises a false alarm with
    /// probability up to `n · 10⁻⁴`: 1 % for a hundred.
    pub const ERRORS_SIGNIFICANCE: f64 = 1e-4;

    /// The default monitor of the NIS of an `m`-row measurement:
    /// independent samples, windows of [`WINDOW`](Self::WINDOW), alarm
    /// after [`WINDOWS`](Self::WINDOWS), significance
    /// [`SIGNIFICANCE`](Self::SIGNIFICANCE).
    ///
    /// # Errors
    /// `InvalidParameter` for `m = 0`.
    pub fn innovations(m: usize) -> Result<Self, FilterError> {
        Self::new(
            m,
            Self::WINDOW,
            Self::WINDOWS,
            Self::SIGNIFICANCE,
            SampleDependence::Independent,
        )
    }

    /// The default monitor of the NEES of `n` error states at consecutive
    /// epochs: correlated samples, significance
    /// [`ERRORS_SIGNIFICANCE`](Self::ERRORS_SIGNIFICANCE), otherwise as
    /// [`innovations`](Self::innovations).
    ///
    /// ```
    /// use kestrel_adaptive::ConsistencyMonitor;
    /// // Position NEES: a window fails when its mean exceeds χ²₀.₉₉₉₉(3) ≈ 21.11.
    /// let m = ConsistencyMonitor::<f64>::errors(3).unwrap();
    /// assert!((m.bound() / 20.0 - 21.108).abs() < 1e-3);
    /// ```
    ///
    /// # Errors
    /// `InvalidParameter` for `n = 0`.
    pub fn errors(n: usize) -> Result<Self, FilterError> {
        Self::new(
            n,
            Self::WINDOW,
            Self::WINDOWS,
            Self::ERRORS_SIGNIFICANCE,
            SampleDependence::Correlated,
        )
    }

    /// A monitor of a statistic of `dof` degrees of freedom with windows
    /// of `window` samples, an alarm after `windows` failing windows in a
    /// row, and the bound at `significance` for samples of `dependence`.
    ///
    /// # Errors
    /// `InvalidParameter` for `dof`, `window` or `windows` of 0, or a
    /// `significance` outside `(0, 1)`.
    ///
    /// ```
    /// use kestrel_adaptive::{ConsistencyMonitor, SampleDependence};
    /// let m = ConsistencyMonitor::<f64>::new(1, 2, 1, 0.05, SampleDependence::Independent).unwrap();
    /// // χ²₀.₉₅(2) = −2 ln 0.05.
    /// assert!((m.bound() + 2.0 * 0.05f64.ln()).abs() < 1e-9);
    /// assert!(ConsistencyMonitor::<f64>::new(1, 0, 1, 0.05, SampleDependence::Independent).is_err());
    /// ```
    pub fn new(
        dof: usize,
        window: usize,
        windows: usize,
        significance: f64,
        dependence: SampleDependence,
    ) -> Result<Self, FilterError> {
        if window == 0 || windows == 0 {
            return Err(FilterError::InvalidParameter {
                name: "window",
                valid: "at least one sample per window and one window",
            });
        }
        let p = 1.0 - significance;
        let bound = match dependence {
            SampleDependence::Independent => chi_square_quantile(p, window * dof)?,
            SampleDependence::Correlated => window as f64 * chi_square_quantile(p, dof)?,
        };
        Ok(Self {
            dof,
            window,
            windows,
            bound: lit(bound),
            sum: T::zero(),
            broken: false,
            count: 0,
            failing: 0,
            passing: 0,
            refused: 0,
            alarm: false,
        })
    }

    /// The bound on a window's sum.
    pub fn bound(&self) -> T {
        self.bound
    }

    /// Samples per window.
    pub fn window(&self) -> usize {
        self.window
    }

    /// Failing windows in a row that raise the alarm.
    pub fn windows(&self) -> usize {
        self.windows
    }

    /// The statistic's degrees of freedom.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Whether the alarm (or a refusal) is raised and not yet recovered.
    pub fn alarm(&self) -> bool {
        self.alarm
    }

    /// Adds one sample of the statistic (an update the filter accepted).
    pub fn push(&mut self, statistic: T) -> Option<MonitorEvent<T>> {
        self.refused = 0;
        // A NaN or infinite sample makes the window fail.
        if statistic.is_finite() {
            self.sum += statistic;
        } else {
            self.broken = true;
        }
        self.count += 1;
        if self.count < self.window {
            return None;
        }
        let (sum, broken) = (self.sum, self.broken);
        self.sum = T::zero();
        self.broken = false;
        self.count = 0;
        if broken || sum > self.bound || !sum.is_finite() {
            self.failing += 1;
            self.passing = 0;
            if !self.alarm && self.failing >= self.windows {
                self.alarm = true;
                let level = sum / lit::<T>((self.window * self.dof) as f64);
                return Some(MonitorEvent::Alarm { level });
            }
        } else {
            self.passing += 1;
            self.failing = 0;
            if self.alarm && self.passing >= self.windows {
                self.alarm = false;
                return Some(MonitorEvent::Recovered);
            }
        }
        None
    }

    /// Notes an update the filter's adapters refused (not a sample).
    ///
    /// ```
    /// use kestrel_adaptive::{ConsistencyMonitor, MonitorEvent};
    /// let mut m = ConsistencyMonitor::<f64>::innovations(3).unwrap();
    /// let events: Vec<_> = (0..60).filter_map(|_| m.refuse()).collect();
    /// assert_eq!(events, [MonitorEvent::Refusing]);
    /// ```
    pub fn refuse(&mut self) -> Option<MonitorEvent<T>> {
        self.refused += 1;
        if !self.alarm && self.refused >= self.window * self.windows {
            self.alarm = true;
            // A window of accepted samples must pass before it recovers.
            self.failing = self.windows;
            self.passing = 0;
            return Some(MonitorEvent::Refusing);
        }
        None
    }
}
