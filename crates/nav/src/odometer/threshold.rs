//! The max-threshold baseline of paper 003: isolate the odometer while the
//! SINS and odometer velocities disagree by more than a threshold.

use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel_core::{real::lit, Real};

/// What [`MaxThreshold`] did in one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThresholdReport<T> {
    /// `‖ν‖`, the velocity disagreement, m/s.
    pub difference: T,
    /// Whether the odometer was isolated (the update rejected).
    pub isolated: bool,
}

impl<T: Real> Default for ThresholdReport<T> {
    fn default() -> Self {
        Self {
            difference: T::zero(),
            isolated: false,
        }
    }
}

/// Rejects an odometer velocity update whose innovation norm exceeds a
/// threshold, so the SINS navigates alone until the odometer agrees again
/// (the paper's baseline, checked afresh at every epoch).
///
/// In closed loop the innovation is the measurement itself,
/// `ν = z = v_SINS − v_OD` (the vehicle-frame form has the same norm as
/// paper 003's navigation-frame `v_SINS − C_b^n C_v^b [ŝ, 0, 0]ᵀ`), so the
/// test is `‖v_SINS − v_OD‖ > threshold`.
///
/// ```
/// use kestrel_core::adapter::{GainStep, NoiseAdapter};
/// use kestrel_core::nalgebra::{Matrix3, Vector3};
/// use kestrel_nav::odometer::MaxThreshold;
/// let mut t = MaxThreshold::<f64>::new(1.0);
/// let c = Matrix3::identity() * 0.01;
/// let mut step = GainStep::new(Vector3::new(1.2, 0.0, 0.1), c, None, c).unwrap();
/// let mut report = Default::default();
/// t.before_gain(&mut step, &mut report);
/// assert!(report.isolated && step.is_rejected());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaxThreshold<T> {
    threshold: T,
}

impl<T: Real> MaxThreshold<T> {
    /// Isolates the odometer above `threshold` m/s (paper 003's scenario
    /// uses 1 m/s).
    ///
    /// ```
    /// assert_eq!(kestrel_nav::odometer::MaxThreshold::<f32>::new(1.0).threshold(), 1.0);
    /// ```
    pub fn new(threshold: f64) -> Self {
        Self {
            threshold: lit(threshold),
        }
    }

    /// The threshold, m/s.
    ///
    /// ```
    /// assert_eq!(kestrel_nav::odometer::MaxThreshold::<f64>::new(0.5).threshold(), 0.5);
    /// ```
    pub fn threshold(&self) -> T {
        self.threshold
    }
}

impl<T: Real> PriorAdapter<T> for MaxThreshold<T> {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for MaxThreshold<T> {
    type Report = ThresholdReport<T>;

    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
        let d = step.innovation().norm();
        report.difference = d;
        // Non-finite differences are isolated too.
        if !d.is_finite() || d > self.threshold {
            report.isolated = true;
            step.reject();
        }
    }
}
