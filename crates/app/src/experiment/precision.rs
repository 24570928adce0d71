//! Paper 001's numerical claim put to the test: the federated UKF and
//! SR-UKF error filters run in `f64` and in `f32`, in the natural units of
//! the error state or in badly scaled ones, over the same sensor data.
//!
//! The navigation solution (mechanisation, feedback) stays `f64`; only the
//! two local error-state filters and the fusion change precision. Their
//! models are built in `f64` (`Φ`, `Q_d`, `H`, `R`) and rounded to the
//! filter's type, and the fused correction is fed back in `f64`.
//!
//! A scaled set-up works on `x' = D x` with `D` diagonal: `Φ' = D Φ D⁻¹`,
//! `Q' = D Q D`, `H' = H D⁻¹`, `P₀' = D P₀ D`; in exact arithmetic every
//! filter gives the same corrections as in natural units.
//!
//! What it shows on scenario 001 (600 s): in `f64` the two filters differ
//! by rounding only (about 10⁻⁹ m); with the paper's tuning both complete
//! in `f32` and in [`StateScaling::mixed`] units within a millimetre of
//! `f64`; with the filters' process noise densities ×1/100
//! ([`PrecisionOptions::small_process_noise`]) the `f32` UKF in mixed units
//! loses positive definiteness after 80–120 s while the SR-UKF completes
//! (seeds 1–6). In natural units with that noise rounding decides whether
//! a form fails in `f32` (neither on seeds 1–6 in the current build;
//! builds equal to it to rounding have lost the UKF on seeds 2 and 4, or 1
//! and 4, and the SR-UKF on seed 1).

use core::fmt;

use kestrel::form::{SquareRootForm, UnscentedForm};
use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::real::lit;
use kestrel::sigma::MerweParams;
use kestrel::{FilterError, Real, SrUkf, Ukf};

use super::data::Simulation;
use super::error::RunError;
use super::federated::{federated_scaled, scaled_p0};
use super::options::RunOptions;
use super::record::EpochRecord;
use super::run::{feed_all, Feed, Job};
use super::summary::RunSummary;
use crate::scenario::{FilterKind, Scenario};

/// The floating-point type of the error-state filters.
///
/// ```
/// assert_eq!(kestrel_app::experiment::Precision::F32.to_string(), "f32");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// Double precision (`f64`).
    F64,
    /// Single precision (`f32`).
    F32,
}

impl fmt::Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        })
    }
}

/// The units of the 15 error states the filters work in: state `i` is
/// multiplied by `factors[i]` (attitude, velocity, position, gyro bias,
/// accelerometer bias, 3 each).
///
/// ```
/// use kestrel_app::experiment::StateScaling;
/// assert_eq!(StateScaling::natural().factors, [1.0; 15]);
/// assert_eq!(StateScaling::mixed().label(), "mixed units");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateScaling {
    /// The factor of each state.
    pub factors: [f64; 15],
    label: &'static str,
}

impl StateScaling {
    /// The model's own units: rad, m/s, m, rad/s, m/s².
    ///
    /// ```
    /// assert_eq!(kestrel_app::experiment::StateScaling::natural().label(), "natural units");
    /// ```
    pub fn natural() -> Self {
        Self {
            factors: [1.0; 15],
            label: "natural units",
        }
    }

    /// Mixed units as a careless implementation might pick them: attitude
    /// in degrees, velocity in mm/s, position in radians of arc on the
    /// Earth (÷ 6 378 137 m), gyro bias in rad/s, accelerometer bias in
    /// µg. With paper 001's P₀ the variances span about 10⁻¹² (position)
    /// to 10¹¹ (accelerometer bias): 23 orders of magnitude instead of 10.
    ///
    /// ```
    /// let s = kestrel_app::experiment::StateScaling::mixed();
    /// assert_eq!(s.factors[3], 1000.0);
    /// ```
    pub fn mixed() -> Self {
        let deg = 180.0 / core::f64::consts::PI;
        let arc = 1.0 / 6_378_137.0;
        let micro_g = 1e6 / 9.80665;
        let mut factors = [1.0; 15];
        for i in 0..3 {
            factors[i] = deg;
            factors[3 + i] = 1000.0;
            factors[6 + i] = arc;
            factors[12 + i] = micro_g;
        }
        Self {
            factors,
            label: "mixed units",
        }
    }

    /// A one-line description.
    ///
    /// ```
    /// assert_eq!(kestrel_app::experiment::StateScaling::mixed().label(), "mixed units");
    /// ```
    pub fn label(&self) -> &'static str {
        self.label
    }

    fn vector(&self) -> SVector<f64, 15> {
        SVector::from(self.factors)
    }
}

/// One configuration of the comparison.
///
/// ```
/// use kestrel_app::experiment::{Precision, PrecisionSetup, StateScaling};
/// let s = PrecisionSetup { precision: Precision::F32, scaling: StateScaling::natural() };
/// assert_eq!(s.to_string(), "f32, natural units");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrecisionSetup {
    /// The filters' floating-point type.
    pub precision: Precision,
    /// The units of the error state.
    pub scaling: StateScaling,
}

impl fmt::Display for PrecisionSetup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}, {}", self.precision, self.scaling.label())
    }
}

/// What [`compare_federated_precision`] runs.
///
/// ```
/// let o = kestrel_app::experiment::PrecisionOptions::default();
/// assert_eq!((o.setups.len(), o.process_noise_scale), (4, 1.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionOptions {
    /// Duration, IMU rate, covariance interval… (records are never kept).
    pub run: RunOptions,
    /// The configurations, each run with both filters. The `f64` natural
    /// one is always run (it is the reference of the difference).
    pub setups: Vec<PrecisionSetup>,
    /// Factor on the white-noise densities (gyro ARW, accelerometer VRW)
    /// of the filters' IMU model, hence on `Q`; the simulated sensors are
    /// unchanged. `1` is the scenario's tuning.
    pub process_noise_scale: f64,
}

impl PrecisionOptions {
    /// The default set-ups with the filters' process noise densities at
    /// 1/100 of the scenario's (`Q` at 10⁻⁴): an over-confident tuning,
    /// the classic way to make a covariance lose definiteness to rounding.
    ///
    /// ```
    /// let o = kestrel_app::experiment::PrecisionOptions::small_process_noise();
    /// assert_eq!(o.process_noise_scale, 0.01);
    /// ```
    pub fn small_process_noise() -> Self {
        Self {
            process_noise_scale: 0.01,
            ..Self::default()
        }
    }
}

impl Default for PrecisionOptions {
    /// `f64` and `f32`, each in natural and in mixed units, the scenario's
    /// process noise.
    fn default() -> Self {
        let setups = [Precision::F64, Precision::F32]
            .into_iter()
            .flat_map(|precision| {
                [StateScaling::natural(), StateScaling::mixed()]
                    .map(|scaling| PrecisionSetup { precision, scaling })
            })
            .collect();
        Self {
            run: RunOptions::default(),
            setups,
            process_noise_scale: 1.0,
        }
    }
}

/// How one filter run ended.
///
/// ```
/// use kestrel_app::experiment::{Outcome, RunError};
/// let e = RunError::Incompatible { filter: "federated UKF", reason: "no GNSS" };
/// assert!(!Outcome::Failed(e).completed());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Every epoch was processed.
    Completed,
    /// The run stopped: the error names the time and what failed.
    Failed(RunError),
}

impl Outcome {
    /// Whether the run completed.
    ///
    /// ```
    /// assert!(kestrel_app::experiment::Outcome::Completed.completed());
    /// ```
    pub fn completed(&self) -> bool {
        matches!(self, Outcome::Completed)
    }

    /// The time of the failure, s (`None` when completed; NaN for a
    /// failure before the first sample, such as an invalid parameter).
    ///
    /// ```
    /// assert_eq!(kestrel_app::experiment::Outcome::Completed.failure_time(), None);
    /// ```
    pub fn failure_time(&self) -> Option<f64> {
        match self {
            Outcome::Completed => None,
            Outcome::Failed(
                RunError::Filter { time, .. }
                | RunError::Fusion { time, .. }
                | RunError::NonFinite { time, .. },
            ) => Some(*time),
            Outcome::Failed(_) => Some(f64::NAN),
        }
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Outcome::Completed => f.write_str("completed"),
            Outcome::Failed(e) => write!(f, "failed: {e}"),
        }
    }
}

/// One filter in one set-up.
///
/// ```
/// use kestrel_app::experiment::*;
/// let s = kestrel_app::scenario::by_name("001").unwrap();
/// let o = PrecisionOptions { run: RunOptions::default().with_duration(2.0), setups: vec![], ..Default::default() };
/// let row = &compare_federated_precision(&s, 1, &o).unwrap().runs[1];
/// assert_eq!((row.filter, row.from_f64.position), ("federated SR-UKF", 0.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionRun {
    /// The set-up.
    pub setup: PrecisionSetup,
    /// The filter's label ([`FilterKind::label`]).
    pub filter: &'static str,
    /// How it ended.
    pub outcome: Outcome,
    /// RMS over the epochs processed (up to the failure, if any).
    pub summary: RunSummary,
    /// Largest difference of the navigation errors from the same filter's
    /// `f64` natural-unit run, over the epochs both processed.
    pub from_f64: MaxDifference,
}

/// The largest differences between two runs' navigation errors over their
/// common epochs.
///
/// ```
/// assert_eq!(kestrel_app::experiment::MaxDifference::default().epochs, 0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaxDifference {
    /// Position, m (3-D).
    pub position: f64,
    /// Velocity, m/s (3-D).
    pub velocity: f64,
    /// Attitude, rad (3-D).
    pub attitude: f64,
    /// Epochs compared.
    pub epochs: usize,
}

/// The comparison of [`compare_federated_precision`]: every run, and the
/// `f64` (natural units) UKF against SR-UKF difference. `Display` prints
/// it as a table, one row per run.
///
/// ```
/// use kestrel_app::experiment::*;
/// let s = kestrel_app::scenario::by_name("001").unwrap();
/// let o = PrecisionOptions { run: RunOptions::default().with_duration(2.0), setups: vec![], ..Default::default() };
/// let r = compare_federated_precision(&s, 1, &o).unwrap();
/// assert!(r.to_string().contains("f64 max |UKF − SR-UKF| over 2 epochs"));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionReport {
    /// The scenario's name.
    pub scenario: String,
    /// The seed of the sensor data.
    pub seed: u64,
    /// The factor on the filters' process noise densities.
    pub process_noise_scale: f64,
    /// One row per set-up and filter (UKF first).
    pub runs: Vec<PrecisionRun>,
    /// Largest |UKF − SR-UKF| of the navigation errors, `f64`, natural
    /// units.
    pub f64_difference: MaxDifference,
}

impl PrecisionReport {
    /// The row of `filter` in `setup`.
    ///
    /// ```
    /// use kestrel_app::experiment::*;
    /// let s = kestrel_app::scenario::by_name("001").unwrap();
    /// let o = PrecisionOptions { run: RunOptions::default().with_duration(3.0), ..Default::default() };
    /// let r = compare_federated_precision(&s, 1, &o).unwrap();
    /// let f32_ukf = r.run("federated UKF", Precision::F32, "natural units").unwrap();
    /// assert!(f32_ukf.outcome.completed() && f32_ukf.summary.epochs == 3);
    /// ```
    pub fn run(&self, filter: &str, precision: Precision, scaling: &str) -> Option<&PrecisionRun> {
        self.runs.iter().find(|r| {
            r.filter == filter
                && r.setup.precision == precision
                && r.setup.scaling.label() == scaling
        })
    }
}

impl fmt::Display for PrecisionReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} seed {}: federated UKF vs SR-UKF by precision (filter process noise densities ×{})",
            self.scenario, self.seed, self.process_noise_scale
        )?;
        writeln!(
            f,
            "{:<22} {:<18} {:>6} {:>23} {:>23} {:>17}  outcome",
            "set-up",
            "filter",
            "epochs",
            "position RMS (m)",
            "velocity RMS (m/s)",
            "Δ from f64 (m)"
        )?;
        for r in &self.runs {
            let m = &r.summary;
            writeln!(
                f,
                "{:<22} {:<18} {:>6} {:>7.3} {:>7.3} {:>7.3} {:>7.4} {:>7.4} {:>7.4} {:>17.1e}  {}",
                r.setup.to_string(),
                r.filter,
                m.epochs,
                m.rms_position.x,
                m.rms_position.y,
                m.rms_position.z,
                m.rms_velocity.x,
                m.rms_velocity.y,
                m.rms_velocity.z,
                r.from_f64.position,
                r.outcome
            )?;
        }
        let d = &self.f64_difference;
        write!(
            f,
            "f64 max |UKF − SR-UKF| over {} epochs: position {:.1e} m, velocity {:.1e} m/s, attitude {:.1e} rad",
            d.epochs, d.position, d.velocity, d.attitude
        )
    }
}

/// Runs paper 001's federated UKF and SR-UKF (the scenario's
/// [`FilterKind::FederatedUkf`] and [`FilterKind::FederatedSrUkf`]) in
/// every set-up of `options` on the sensor data of `seed`, and compares
/// the `f64` natural-unit runs epoch by epoch. A filter that fails is
/// reported with the time and the error, and the others go on.
///
/// # Errors
/// [`RunError::Incompatible`] when the scenario lacks the federated
/// filters, the 15-state model or GNSS position and velocity;
/// [`RunError::InvalidParameter`] for a process noise scale that is not
/// positive and finite or sigma-point parameters out of range;
/// [`RunError::Trajectory`] when its trajectory does not compile.
///
/// ```
/// use kestrel_app::experiment::{compare_federated_precision, PrecisionOptions, RunOptions};
/// let s = kestrel_app::scenario::by_name("001").unwrap();
/// let opts = PrecisionOptions {
///     run: RunOptions::default().with_duration(5.0),
///     setups: vec![],
///     process_noise_scale: 1.0,
/// };
/// let r = compare_federated_precision(&s, 1, &opts).unwrap();
/// assert_eq!(r.runs.len(), 2); // f64 natural: UKF, SR-UKF
/// assert!(r.f64_difference.position < 1e-6);
/// ```
pub fn compare_federated_precision(
    scenario: &Scenario,
    seed: u64,
    options: &PrecisionOptions,
) -> Result<PrecisionReport, RunError> {
    let (ukf, srukf) = federated_kinds(scenario)?;
    let mut scenario = scenario.clone();
    let k = options.process_noise_scale;
    if !(k.is_finite() && k > 0.0) {
        return Err(RunError::InvalidParameter {
            filter: ukf.label(),
            error: FilterError::InvalidParameter {
                name: "process_noise_scale",
                valid: "finite and greater than 0",
            },
        });
    }
    scenario.filter.imu_model.gyro_arw *= k;
    scenario.filter.imu_model.accel_vrw *= k;
    let scenario = &scenario;
    let reference = PrecisionSetup {
        precision: Precision::F64,
        scaling: StateScaling::natural(),
    };
    let mut setups = vec![reference];
    setups.extend(options.setups.iter().filter(|s| **s != reference).copied());
    let mut runs = Vec::new();
    let mut references: Vec<Vec<EpochRecord>> = Vec::new();
    for setup in &setups {
        for (i, kind) in [ukf, srukf].iter().enumerate() {
            let mut trace = Vec::new();
            let (summary, outcome) = run_setup(scenario, kind, seed, &options.run, setup, |r| {
                trace.push(*r)
            })?;
            if *setup == reference {
                references.push(trace.clone());
            }
            runs.push(PrecisionRun {
                setup: *setup,
                filter: kind.label(),
                outcome,
                summary,
                from_f64: max_difference(&references[i], &trace),
            });
        }
    }
    Ok(PrecisionReport {
        scenario: scenario.name.clone(),
        seed,
        process_noise_scale: k,
        runs,
        f64_difference: max_difference(&references[0], &references[1]),
    })
}

/// The scenario's federated UKF and SR-UKF kinds.
fn federated_kinds(scenario: &Scenario) -> Result<(FilterKind, FilterKind), RunError> {
    let find = |ukf: bool| {
        scenario.filters.iter().copied().find(|k| {
            matches!(
                (k, ukf),
                (FilterKind::FederatedUkf { .. }, true)
                    | (FilterKind::FederatedSrUkf { .. }, false)
            )
        })
    };
    match (find(true), find(false)) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err(RunError::Incompatible {
            filter: "federated UKF",
            reason: "the scenario has no federated UKF and SR-UKF",
        }),
    }
}

/// The largest differences over the common epochs of two traces.
fn max_difference(a: &[EpochRecord], b: &[EpochRecord]) -> MaxDifference {
    a.iter()
        .zip(b)
        .fold(MaxDifference::default(), |d, (x, y)| MaxDifference {
            position: d.position.max((x.position - y.position).norm()),
            velocity: d.velocity.max((x.velocity - y.velocity).norm()),
            attitude: d.attitude.max((x.attitude - y.attitude).norm()),
            epochs: d.epochs + 1,
        })
}

/// One filter in one set-up: the summary up to the end or the failure.
fn run_setup<C: FnMut(&EpochRecord)>(
    scenario: &Scenario,
    kind: &FilterKind,
    seed: u64,
    options: &RunOptions,
    setup: &PrecisionSetup,
    mut on_epoch: C,
) -> Result<(RunSummary, Outcome), RunError> {
    let sim = Simulation::new(scenario, seed, options)?;
    let d = setup.scaling.vector();
    let p0 = scaled_p0(scenario, &d);
    let job = Job::new(kind.label(), scenario, &sim, options);
    let mut feed = match setup.precision {
        Precision::F64 => feed_in::<f64>(job, kind, &p0, &d),
        Precision::F32 => feed_in::<f32>(job, kind, &p0, &d),
    }?;
    let outcome = match feed_all(sim, feed.as_mut(), &mut on_epoch) {
        Ok(()) => Outcome::Completed,
        Err(e) => Outcome::Failed(e),
    };
    Ok((feed.summary(), outcome))
}

/// The federated run with the UKF or SR-UKF local of `kind` in type `T`.
fn feed_in<'a, T: Real>(
    job: Job<'a>,
    kind: &FilterKind,
    p0: &SMatrix<f64, 15, 15>,
    d: &SVector<f64, 15>,
) -> Result<Box<dyn Feed + 'a>, RunError> {
    let label = job.label;
    let invalid = |error| RunError::InvalidParameter {
        filter: label,
        error,
    };
    let p0t = p0.map(lit::<T>);
    let params = |a: f64, b: f64, k: f64| MerweParams::new(lit(a), lit(b), lit(k));
    match *kind {
        FilterKind::FederatedUkf { alpha, beta, kappa } => {
            let local = UnscentedForm::new(&p0t)
                .and_then(|f| f.with_params(params(alpha, beta, kappa)))
                .and_then(|f| Ukf::with_form(SVector::zeros(), f));
            federated_scaled(job, Ok(local.map_err(invalid)?), p0, d)
        }
        FilterKind::FederatedSrUkf { alpha, beta, kappa } => {
            let local = SquareRootForm::new(&p0t)
                .and_then(|f| f.with_params(params(alpha, beta, kappa)))
                .and_then(|f| SrUkf::with_form(SVector::zeros(), f));
            federated_scaled(job, Ok(local.map_err(invalid)?), p0, d)
        }
        _ => Err(job.incompatible("not a federated UKF or SR-UKF")),
    }
}
