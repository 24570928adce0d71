//! Fault isolation: consecutive failed innovation tests isolate a local,
//! consecutive passes re-admit it.

use kestrel_core::real::{lit, to_f64};
use kestrel_core::{FilterError, Real};

use crate::chi_square_quantile;

/// Thresholds precomputed at construction for these measurement dimensions;
/// larger ones are computed when met.
const CACHED_DOF: usize = 12;

/// The outcome of a local's innovation tests over one epoch (between two
/// fusions).
///
/// ```
/// use kestrel_adaptive::federated::Verdict;
/// assert_eq!(Verdict::Passed.and(Verdict::Failed), Verdict::Failed);
/// assert_eq!(Verdict::Untested.and(Verdict::Passed), Verdict::Passed);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Verdict {
    /// No test recorded this epoch (no measurement): the counters stay.
    #[default]
    Untested,
    /// Every recorded test passed.
    Passed,
    /// At least one recorded test failed.
    Failed,
}

impl Verdict {
    /// This epoch's verdict after one more test outcome: a failure wins.
    pub fn and(self, other: Verdict) -> Verdict {
        match (self, other) {
            (Verdict::Failed, _) | (_, Verdict::Failed) => Verdict::Failed,
            (Verdict::Passed, _) | (_, Verdict::Passed) => Verdict::Passed,
            _ => Verdict::Untested,
        }
    }
}

/// Whether a local takes part in fusion, and its run of test outcomes.
///
/// ```
/// use kestrel_adaptive::federated::LocalStatus;
/// let s = LocalStatus::default();
/// assert!(s.admitted && s.failures == 0 && s.passes == 0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LocalStatus {
    /// Admitted to fusion (`false`: isolated).
    pub admitted: bool,
    /// Consecutive failed epochs while admitted.
    pub failures: u32,
    /// Consecutive passed epochs while isolated.
    pub passes: u32,
}

impl Default for LocalStatus {
    fn default() -> Self {
        Self {
            admitted: true,
            failures: 0,
            passes: 0,
        }
    }
}

/// The fault-isolation rule of a federated filter: a local whose innovation
/// test `NIS > χ²_{1−α}(m)` fails in `fail_after` consecutive epochs is
/// isolated from fusion, and re-admitted after `readmit_after` consecutive
/// passing epochs (paper 001: the fault tolerance of the federated
/// structure). Epochs without a recorded test leave the counts as they are.
///
/// ```
/// use kestrel_adaptive::federated::{Isolation, LocalStatus, Verdict};
/// let iso = Isolation::<f64>::new(0.01, 2, 3).unwrap();
/// assert!((iso.threshold(2).unwrap() + 2.0 * 0.01f64.ln()).abs() < 1e-9);
/// let mut s = LocalStatus::default();
/// s = iso.advance(s, Verdict::Failed);
/// assert!(s.admitted);
/// s = iso.advance(s, Verdict::Failed);
/// assert!(!s.admitted);
/// for _ in 0..3 { s = iso.advance(s, Verdict::Passed); }
/// assert!(s.admitted);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Isolation<T: Real> {
    significance: f64,
    fail_after: u32,
    readmit_after: u32,
    thresholds: [T; CACHED_DOF],
}

impl<T: Real> Isolation<T> {
    /// Isolate after `fail_after` consecutive failed epochs of the test at
    /// significance `alpha`, re-admit after `readmit_after` passing ones.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`]: `"alpha"` unless `0 < α < 1`,
    /// `"fail_after"` / `"readmit_after"` if zero.
    pub fn new(alpha: T, fail_after: u32, readmit_after: u32) -> Result<Self, FilterError> {
        let alpha = to_f64(alpha);
        if !(alpha > 0.0 && alpha < 1.0) {
            return Err(FilterError::InvalidParameter {
                name: "alpha",
                valid: "0 < alpha < 1",
            });
        }
        if fail_after == 0 {
            return Err(FilterError::InvalidParameter {
                name: "fail_after",
                valid: "at least 1",
            });
        }
        if readmit_after == 0 {
            return Err(FilterError::InvalidParameter {
                name: "readmit_after",
                valid: "at least 1",
            });
        }
        let mut thresholds = [T::zero(); CACHED_DOF];
        for (i, t) in thresholds.iter_mut().enumerate() {
            *t = lit(chi_square_quantile(1.0 - alpha, i + 1)?);
        }
        Ok(Self {
            significance: alpha,
            fail_after,
            readmit_after,
            thresholds,
        })
    }

    /// The significance `α` of the innovation test.
    pub fn significance(&self) -> f64 {
        self.significance
    }

    /// Consecutive failed epochs that isolate a local.
    pub fn fail_after(&self) -> u32 {
        self.fail_after
    }

    /// Consecutive passed epochs that re-admit an isolated local.
    pub fn readmit_after(&self) -> u32 {
        self.readmit_after
    }

    /// The test threshold `χ²_{1−α}(dof)`.
    ///
    /// # Errors
    /// [`FilterError::InvalidParameter`] (`"dof"`) if `dof == 0`.
    pub fn threshold(&self, dof: usize) -> Result<T, FilterError> {
        match dof {
            0 => Err(FilterError::InvalidParameter {
                name: "dof",
                valid: "at least 1 (the measurement dimension M)",
            }),
            d if d <= CACHED_DOF => Ok(self.thresholds[d - 1]),
            d => Ok(lit(chi_square_quantile(1.0 - self.significance, d)?)),
        }
    }

    /// The verdict of one test: passed iff `nis ≤ χ²_{1−α}(dof)` (a NaN
    /// statistic fails).
    ///
    /// # Errors
    /// As [`threshold`](Self::threshold).
    pub fn test(&self, nis: T, dof: usize) -> Result<Verdict, FilterError> {
        let threshold = self.threshold(dof)?;
        Ok(if nis <= threshold {
            Verdict::Passed
        } else {
            Verdict::Failed
        })
    }

    /// The status after an epoch with verdict `verdict`.
    pub fn advance(&self, status: LocalStatus, verdict: Verdict) -> LocalStatus {
        let mut s = status;
        match (s.admitted, verdict) {
            (_, Verdict::Untested) => {}
            (true, Verdict::Passed) => s.failures = 0,
            (true, Verdict::Failed) => {
                s.failures = s.failures.saturating_add(1);
                if s.failures >= self.fail_after {
                    s.admitted = false;
                    s.passes = 0;
                }
            }
            (false, Verdict::Failed) => s.passes = 0,
            (false, Verdict::Passed) => {
                s.passes = s.passes.saturating_add(1);
                if s.passes >= self.readmit_after {
                    s.admitted = true;
                    s.failures = 0;
                }
            }
        }
        s
    }
}
