//! The consistency check of a reproduction's filters: the average position
//! NEES over the Monte Carlo runs (ANEES) of the fault-free form of the
//! scenario, epoch by epoch, against its χ² band.
//!
//! **The rule.** With `R` runs, the ANEES at an epoch of a consistent
//! filter is `χ²(3R)/R` (the runs are independent, so their NEES add):
//! mean 3, two-sided 95 % band `[χ²_{0.025}(3R)/R, χ²_{0.975}(3R)/R]`
//! ([`anees_band`]). A filter is **consistent** when the ANEES lies inside
//! that band at ≥ 90 % of the epochs after the first 10 % of the run
//! ([`CONSISTENT_SHARE`], [`SETTLING_SHARE`]); otherwise **over-confident**
//! when at least as many of the other epochs lie above the band as below
//! it, else **conservative** ([`Reading::of`]).
//!
//! Why 90 % and not a test: the band holds 95 % of the epochs of a
//! consistent filter on average, but one run's epochs are correlated in
//! time (an error lasts longer than the time between updates), so the
//! share inside varies from one Monte Carlo to the next far more than a
//! binomial count of independent epochs would, and no per-epoch binomial
//! test applies. The 5-point margin is what that variation needs on a
//! filter known to be consistent (an exact Kalman filter of a linear
//! model, 20 runs per Monte Carlo, `crates/app/tests/suite/anees.rs`):
//! with errors correlated over 2 epochs, 400 Monte Carlos of 300 epochs
//! gave shares of 0.900–0.990, never below 90 %; with errors correlated
//! over 32 epochs, none of 200 Monte Carlos of 3000 epochs fell below 90 %
//! but 21 of 200 of 300 epochs did. The rule therefore needs runs of
//! about 100 error correlation times or more. A filter whose variances
//! are three quarters of the truth's (σ 13 % too small) reads
//! over-confident in every Monte Carlo tried; its mean NEES, about 4, is
//! what the earlier rule ("a mean between 1 and 6") read as consistent.

use std::fmt::Write as _;

use crate::experiment::{run_together, RunOptions, ScaleEstimate};
use crate::scenario::{fault_free, Scenario};
use rayon::prelude::*;

use super::monte_carlo::worker_pool;
use super::table::TextTable;
use crate::transaction::Cancel;
use crate::Error;

/// The share of a run skipped before NEES is counted (the initial
/// convergence).
pub const SETTLING_SHARE: f64 = 0.1;

/// The share of the counted epochs whose ANEES must lie inside its 95 %
/// band for the filter to read as consistent.
pub const CONSISTENT_SHARE: f64 = 0.9;

/// The two-sided 95 % band of the ANEES of `runs` independent runs of a
/// consistent filter of `dof` error states: `χ²_{0.025}(dof·runs)/runs`
/// and `χ²_{0.975}(dof·runs)/runs` (NaN for no runs).
///
/// ```
/// use kestrel_app::reproduce::anees_band;
/// // One run: the band of one NEES.
/// let (lo, hi) = anees_band(3, 1);
/// assert!((lo - 0.2158).abs() < 1e-4 && (hi - 9.3484).abs() < 1e-4);
/// // 20 runs: χ²(60)/20.
/// let (lo, hi) = anees_band(3, 20);
/// assert!((lo - 2.0241).abs() < 1e-3 && (hi - 4.1649).abs() < 1e-3);
/// ```
pub fn anees_band(dof: usize, runs: usize) -> (f64, f64) {
    let (lo, hi) = crate::process::chi_square_band(dof * runs);
    (lo / runs as f64, hi / runs as f64)
}

/// What the ANEES says about a filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reading {
    /// Inside the band at ≥ [`CONSISTENT_SHARE`] of the epochs.
    Consistent,
    /// Not consistent, at least as many epochs above the band as below.
    OverConfident,
    /// Not consistent, more epochs below the band than above.
    Conservative,
    /// No NEES (no single covariance, or no epoch counted).
    Unknown,
}

impl Reading {
    /// The reading of shares `inside`, `above` and `below` the band (of
    /// the counted epochs; `None` when there are none).
    ///
    /// ```
    /// use kestrel_app::reproduce::Reading;
    /// assert_eq!(Reading::of(Some((0.93, 0.05, 0.02))), Reading::Consistent);
    /// assert_eq!(Reading::of(Some((0.83, 0.17, 0.0))), Reading::OverConfident);
    /// assert_eq!(Reading::of(Some((0.5, 0.0, 0.5))), Reading::Conservative);
    /// assert_eq!(Reading::of(None), Reading::Unknown);
    /// ```
    pub fn of(shares: Option<(f64, f64, f64)>) -> Self {
        match shares {
            None => Self::Unknown,
            Some((inside, _, _)) if inside >= CONSISTENT_SHARE => Self::Consistent,
            Some((_, above, below)) if above >= below => Self::OverConfident,
            Some(_) => Self::Conservative,
        }
    }

    /// The word the report prints.
    pub fn word(&self) -> &'static str {
        match self {
            Self::Consistent => "consistent",
            Self::OverConfident => "over-confident",
            Self::Conservative => "conservative",
            Self::Unknown => "no NEES (no single covariance)",
        }
    }
}

/// The ANEES of a set of runs, epoch by epoch: how many epochs lie inside,
/// above and below the band.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Anees {
    /// Epochs counted (every run had a NEES at them).
    pub epochs: usize,
    /// Of them, inside the band.
    pub inside: usize,
    /// Above it.
    pub above: usize,
    /// Below it.
    pub below: usize,
    /// Runs averaged.
    pub runs: usize,
    /// The mean of the ANEES over the counted epochs.
    pub mean: f64,
}

impl Anees {
    /// The ANEES of `runs` (each one run's NEES at the same epochs, in
    /// order; `dof` error states): epoch `k` is counted when every run has
    /// a NEES at it; the band is [`anees_band`]`(dof, runs.len())`.
    ///
    /// ```
    /// use kestrel_app::reproduce::{Anees, Reading};
    /// // Two runs, three epochs: means 3, 10, 0.1; χ²(6)/2 band [0.62, 7.22].
    /// let a = Anees::of(&[vec![2.0, 12.0, 0.1], vec![4.0, 8.0, 0.1]], 3);
    /// assert_eq!((a.epochs, a.inside, a.above, a.below), (3, 1, 1, 1));
    /// // 1 of 3 inside; as many above as below reads over-confident.
    /// assert_eq!(a.reading(), Reading::OverConfident);
    /// ```
    pub fn of(runs: &[Vec<f64>], dof: usize) -> Self {
        let epochs = runs.iter().map(Vec::len).min().unwrap_or(0);
        if runs.is_empty() || epochs == 0 {
            return Self::default();
        }
        let (lo, hi) = anees_band(dof, runs.len());
        let mut a = Self {
            runs: runs.len(),
            ..Self::default()
        };
        let mut total = 0.0;
        for k in 0..epochs {
            let v = runs.iter().map(|r| r[k]).sum::<f64>() / runs.len() as f64;
            if !v.is_finite() {
                continue;
            }
            a.epochs += 1;
            total += v;
            if v > hi {
                a.above += 1;
            } else if v < lo {
                a.below += 1;
            } else {
                a.inside += 1;
            }
        }
        a.mean = if a.epochs > 0 {
            total / a.epochs as f64
        } else {
            f64::NAN
        };
        a
    }

    /// Shares of the counted epochs inside, above and below the band
    /// (`None` for no epoch).
    pub fn shares(&self) -> Option<(f64, f64, f64)> {
        (self.epochs > 0).then(|| {
            let n = self.epochs as f64;
            (
                self.inside as f64 / n,
                self.above as f64 / n,
                self.below as f64 / n,
            )
        })
    }

    /// The reading ([`Reading::of`] of the shares).
    pub fn reading(&self) -> Reading {
        Reading::of(self.shares())
    }
}

/// One filter's consistency over the fault-free runs.
#[derive(Clone, Debug, PartialEq)]
pub struct NeesRow {
    /// The filter's label (with its configuration).
    pub label: String,
    /// The ANEES over the completed runs.
    pub anees: Anees,
    /// Runs that failed (not averaged).
    pub failed: usize,
    /// Runs in which the health monitor raised an alarm (a false alarm:
    /// the data are fault-free).
    pub alarms: usize,
    /// Runs the health monitor found diverged at their end.
    pub diverged: usize,
    /// Runs completed.
    pub completed: usize,
    /// The odometer scale-factor estimate at the end of each completed run
    /// (16-state filters).
    pub scales: Vec<ScaleEstimate>,
}

impl NeesRow {
    /// The reading of its ANEES.
    pub fn reading(&self) -> Reading {
        self.anees.reading()
    }
}

/// What one fault-free run of one filter gave: its NEES after the
/// settling share, the times they were taken at, and the monitor's
/// verdicts.
#[derive(Clone, Debug, Default)]
struct RunNees {
    nees: Vec<f64>,
    times: Vec<f64>,
    alarm: bool,
    diverged: bool,
    scale: Option<ScaleEstimate>,
}

/// Runs every filter of each `(label suffix, scenario)` configuration on
/// the scenario's [`fault_free`] form for `seeds` and reads each filter's
/// ANEES after the first [`SETTLING_SHARE`] of the run, and the health
/// monitor's alarms (false alarms, the data being fault-free).
///
/// # Errors
/// [`Error::Failed`] if the worker threads cannot start;
/// [`Error::Cancelled`] once `cancel` is set (no run starts after that).
pub fn nees_rows(
    configs: &[(&str, &Scenario)],
    seeds: core::ops::Range<u64>,
    threads: usize,
    duration: Option<f64>,
    cancel: &Cancel,
) -> Result<Vec<NeesRow>, Error> {
    let pool = worker_pool(threads)?;
    let clean: Vec<Scenario> = configs.iter().map(|(_, s)| fault_free(s)).collect();
    let seeds: Vec<u64> = seeds.collect();
    let options = RunOptions {
        duration,
        ..RunOptions::default()
    }
    .without_records();
    // One job per (configuration, seed): its filters share one simulation.
    let work: Vec<(usize, u64)> = (0..clean.len())
        .flat_map(|c| seeds.iter().map(move |&seed| (c, seed)))
        .collect();
    let runs: Vec<Vec<Option<RunNees>>> = pool.install(|| {
        work.par_iter()
            .map(|&(c, seed)| {
                let s = &clean[c];
                if cancel.is_cancelled() {
                    return vec![None; s.filters.len()];
                }
                let start = duration
                    .or_else(|| s.trajectory().ok().map(|t| t.duration()))
                    .unwrap_or(0.0)
                    * SETTLING_SHARE;
                let mut per = vec![RunNees::default(); s.filters.len()];
                let done = run_together(s, &s.filters, seed, &options, |i, r| {
                    if r.time >= start {
                        per[i].nees.push(r.position_nees.unwrap_or(f64::NAN));
                        per[i].times.push(r.time);
                    }
                });
                match done {
                    Ok(done) => done
                        .iter()
                        .zip(per)
                        .map(|(d, mut x)| {
                            let summary = d.as_ref().ok()?;
                            x.alarm = summary.health.alarms > 0;
                            x.diverged = summary.health.diverged();
                            x.scale = summary.odometer_scale;
                            Some(x)
                        })
                        .collect(),
                    Err(_) => vec![None; s.filters.len()],
                }
            })
            .collect()
    });
    cancel.check()?;
    let mut rows = Vec::new();
    for (c, ((suffix, _), s)) in configs.iter().zip(&clean).enumerate() {
        let of_config = &runs[c * seeds.len()..(c + 1) * seeds.len()];
        for (i, k) in s.filters.iter().enumerate() {
            let done: Vec<&RunNees> = of_config.iter().filter_map(|r| r[i].as_ref()).collect();
            // The runs' epochs are the same instants (the sensors sample
            // on the seed-independent schedule); compared index by index.
            let aligned = done
                .windows(2)
                .all(|w| w[0].times.len() == w[1].times.len() && w[0].times == w[1].times);
            let nees: Vec<Vec<f64>> = if aligned {
                done.iter().map(|r| r.nees.clone()).collect()
            } else {
                Vec::new()
            };
            rows.push(NeesRow {
                label: format!("{}{suffix}", k.label()),
                anees: Anees::of(&nees, 3),
                failed: of_config.len() - done.len(),
                alarms: done.iter().filter(|r| r.alarm).count(),
                diverged: done.iter().filter(|r| r.diverged).count(),
                completed: done.len(),
                scales: done.iter().filter_map(|r| r.scale).collect(),
            });
        }
    }
    Ok(rows)
}

/// The consistency rows as a text table with each filter's reading and the
/// rule.
pub fn nees_table(rows: &[NeesRow], seeds: core::ops::Range<u64>) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let n = rows.iter().map(|r| r.anees.runs).max().unwrap_or(0);
    let (lo, hi) = anees_band(3, n.max(1));
    let mut out = String::new();
    let _ = writeln!(
        out,
        "consistency on the fault-free scenario (no outliers, noise changes or odometer faults), seeds {}–{}, after the first {:.0} % of each run: position ANEES (the NEES averaged over the runs) epoch by epoch against its 95 % band [{lo:.2}, {hi:.2}] (χ²(3·{n})/{n}):",
        seeds.start,
        seeds.end.saturating_sub(1),
        SETTLING_SHARE * 100.0
    );
    let mut t = TextTable::new(
        [
            "filter",
            "mean ANEES (3 expected)",
            "epochs inside / above / below",
            "epochs",
            "runs (failed)",
            "health alarms / diverged",
            "reading",
        ]
        .map(String::from)
        .to_vec(),
    );
    for r in rows {
        let a = &r.anees;
        t.row(vec![
            r.label.clone(),
            if a.epochs > 0 {
                format!("{:.2}", a.mean)
            } else {
                "—".into()
            },
            a.shares().map_or("—".into(), |(i, ab, be)| {
                format!("{:.1} / {:.1} / {:.1} %", 100.0 * i, 100.0 * ab, 100.0 * be)
            }),
            a.epochs.to_string(),
            format!("{} ({})", r.completed, r.failed),
            format!("{} / {}", r.alarms, r.diverged),
            r.reading().word().to_string(),
        ]);
    }
    let _ = writeln!(out, "{t}");
    let _ = writeln!(
        out,
        "   reading: consistent when the ANEES is inside its band at ≥ {:.0} % of the epochs, else over-confident (more above) or conservative (more below); health alarms on fault-free data are false alarms\n",
        CONSISTENT_SHARE * 100.0
    );
    let scales: Vec<(String, Vec<ScaleEstimate>)> = rows
        .iter()
        .map(|r| (r.label.clone(), r.scales.clone()))
        .collect();
    out.push_str(&super::report::scale_table(
        "odometer scale factor at the end of the fault-free runs",
        &scales,
    ));
    out
}
