//! The IMU time line as real logs have it: a nominal interval estimated
//! robustly, dropouts bridged up to a limit and counted, longer gaps an
//! error or coasted, as configured.

use std::path::{Path, PathBuf};

use kestrel::nav::ImuIncrement;

use crate::InputError;
use kestrel_io::gins::ImuRecord;

/// How many intervals at the start of the file estimate the nominal one.
pub(crate) const NOMINAL_SAMPLES: usize = 21;

/// An interval longer than this many nominal intervals is a dropout (lost
/// samples); shorter ones are jitter, integrated as they are.
pub const DROPOUT_FACTOR: f64 = 1.5;

/// What `process` does with a gap in the IMU data longer than
/// [`TimingRule::max_gap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LongGap {
    /// Stop with an error naming the file, the line and the gap.
    Error,
    /// Bridge it like a short dropout and report it.
    Coast,
}

/// The configured treatment of the IMU time line (`[imu] max_gap`,
/// `[imu] long_gap`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimingRule {
    /// The longest gap bridged, s.
    pub max_gap: f64,
    /// What happens to a longer one.
    pub long_gap: LongGap,
}

impl Default for TimingRule {
    fn default() -> Self {
        Self {
            max_gap: 1.0,
            long_gap: LongGap::Error,
        }
    }
}

/// One bridged gap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gap {
    /// Its length, s.
    pub seconds: f64,
    /// The IMU line after it.
    pub line: usize,
    /// Whether it was longer than `max_gap` (coasted).
    pub long: bool,
}

/// What the time line held, for the summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimingReport {
    /// The nominal interval (median of the first intervals), s.
    pub nominal: f64,
    /// Gaps bridged (dropouts, and long gaps when coasting).
    pub gaps: usize,
    /// Their total length, s.
    pub bridged: f64,
    /// The first few of them, in file order.
    pub first_gaps: Vec<Gap>,
    /// The longest one.
    pub longest: Option<Gap>,
}

impl TimingReport {
    /// Gaps listed individually in the summary.
    pub const LISTED: usize = 5;
}

/// Turns IMU records into increments over their actual intervals.
#[derive(Debug)]
pub(crate) struct ImuTiming {
    rule: TimingRule,
    /// The records' increments already cover their actual intervals
    /// (integrated rates): a dropout needs no rescaling.
    integrated: bool,
    path: PathBuf,
    report: TimingReport,
}

/// `x` s to the microsecond, without trailing zeros.
pub(crate) fn seconds(x: f64) -> String {
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The median of the intervals between `times` (at least two).
fn median_interval(times: &[f64]) -> f64 {
    let mut d: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let n = d.len();
    if n % 2 == 1 {
        d[n / 2]
    } else {
        0.5 * (d[n / 2 - 1] + d[n / 2])
    }
}

impl ImuTiming {
    /// The timing of a file whose first samples are `first` (at least two,
    /// in time order).
    pub(crate) fn new(
        rule: TimingRule,
        path: &Path,
        first: &[ImuRecord],
    ) -> Result<Self, InputError> {
        if first.len() < 2 {
            return Err(InputError::file(
                path,
                "expected at least two IMU samples after the initial time",
            ));
        }
        let times: Vec<f64> = first.iter().map(|r| r.time).collect();
        Ok(Self {
            rule,
            integrated: false,
            path: path.to_path_buf(),
            report: TimingReport {
                nominal: median_interval(&times),
                ..TimingReport::default()
            },
        })
    }

    /// The increment of `sample`, the previous sample (or the initial time,
    /// `previous_line` `None`) being at `previous` s: the sample's
    /// increments over its actual interval; across a dropout its rates
    /// held over the whole gap (increments × gap / nominal).
    pub(crate) fn increment(
        &mut self,
        sample: &ImuRecord,
        previous: f64,
        previous_line: Option<usize>,
    ) -> Result<ImuIncrement, InputError> {
        let dt = sample.time - previous;
        let nominal = self.report.nominal;
        if dt <= DROPOUT_FACTOR * nominal {
            return Ok(sample.increment(previous));
        }
        let long = dt > self.rule.max_gap;
        if long && self.rule.long_gap == LongGap::Error {
            let since = match previous_line {
                Some(l) => format!("since line {l}"),
                None => "since initial.time".to_string(),
            };
            return Err(InputError::at(
                &self.path,
                sample.line,
                1,
                format!(
                    "gap in the IMU data: {} s {since}, longer than max_gap = {} s \
                     (the nominal interval is {} s); raise [imu] max_gap or set \
                     [imu] long_gap = \"coast\" to bridge it",
                    seconds(dt),
                    seconds(self.rule.max_gap),
                    seconds(nominal)
                ),
            ));
        }
        let gap = Gap {
            seconds: dt,
            line: sample.line,
            long,
        };
        let r = &mut self.report;
        r.gaps += 1;
        r.bridged += dt;
        if r.first_gaps.len() < TimingReport::LISTED {
            r.first_gaps.push(gap);
        }
        if r.longest.is_none_or(|g| dt > g.seconds) {
            r.longest = Some(gap);
        }
        let scale = if self.integrated { 1.0 } else { dt / nominal };
        Ok(ImuIncrement {
            time: sample.time,
            dt,
            dtheta: sample.dtheta * scale,
            dvel: sample.dvel * scale,
        })
    }

    /// The same timing for records whose increments already cover their
    /// actual intervals (integrated rates).
    pub(crate) fn integrated(mut self, yes: bool) -> Self {
        self.integrated = yes;
        self
    }

    /// What was seen.
    pub(crate) fn report(&self) -> TimingReport {
        self.report.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kestrel::nav::nalgebra::Vector3;

    fn rec(time: f64, line: usize) -> ImuRecord {
        ImuRecord {
            time,
            dtheta: Vector3::new(1e-4, 0.0, 0.0),
            dvel: Vector3::new(0.0, 0.0, -0.098),
            odometer: None,
            line,
        }
    }

    #[test]
    fn the_median_ignores_an_early_dropout() {
        let times = [0.01, 0.02, 0.05, 0.06, 0.07, 0.08];
        assert!((median_interval(&times) - 0.01).abs() < 1e-15);
    }

    #[test]
    fn dropouts_are_bridged_at_the_held_rate_and_counted() {
        let first: Vec<_> = (1..=5).map(|k| rec(0.01 * k as f64, k)).collect();
        let mut t = ImuTiming::new(TimingRule::default(), "imu.txt".as_ref(), &first).unwrap();
        // Jitter: as it is.
        let inc = t.increment(&rec(0.064, 6), 0.05, Some(5)).unwrap();
        assert!((inc.dt - 0.014).abs() < 1e-15 && inc.dtheta == first[0].dtheta);
        // A dropout of two samples: the increment ×3.
        let inc = t.increment(&rec(0.094, 7), 0.064, Some(6)).unwrap();
        assert!((inc.dtheta.x - 3e-4).abs() < 1e-15, "{}", inc.dtheta);
        let r = t.report();
        assert_eq!((r.gaps, r.first_gaps[0].line), (1, 7));
    }

    #[test]
    fn a_long_gap_is_an_error_naming_the_line_or_is_coasted() {
        let first: Vec<_> = (1..=5).map(|k| rec(0.01 * k as f64, k)).collect();
        let mut t = ImuTiming::new(TimingRule::default(), "imu.txt".as_ref(), &first).unwrap();
        let e = t.increment(&rec(2.05, 6), 0.05, Some(5)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "imu.txt:6:1: gap in the IMU data: 2 s since line 5, longer than max_gap = 1 s \
             (the nominal interval is 0.01 s); raise [imu] max_gap or set [imu] long_gap = \
             \"coast\" to bridge it"
        );
        let coast = TimingRule {
            long_gap: LongGap::Coast,
            ..TimingRule::default()
        };
        let mut t = ImuTiming::new(coast, "imu.txt".as_ref(), &first).unwrap();
        let inc = t.increment(&rec(2.05, 6), 0.05, Some(5)).unwrap();
        assert!((inc.dt - 2.0).abs() < 1e-12);
        assert!(t.report().longest.unwrap().long);
        // A late start after initial.time is judged the same way.
        let mut t = ImuTiming::new(TimingRule::default(), "imu.txt".as_ref(), &first).unwrap();
        let e = t.increment(&rec(10.01, 1), 0.0, None).unwrap_err();
        assert!(e.to_string().contains("10.01 s since initial.time"), "{e}");
    }
}
