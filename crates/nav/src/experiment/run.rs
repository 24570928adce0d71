//! The run loop: one generic function per filter type.

use kestrel_core::adapter::PriorAdapter;
use kestrel_core::form::{Form, PredictForm};
use kestrel_core::Filter;

use super::aiding::Aiding;
use super::data::{Digest, SensorSample, Simulation};
use super::dispatch::dispatch;
use super::error::RunError;
use super::options::{PositionAxes, RunOptions};
use super::record::{Adaptation, EpochRecord};
use super::summary::{Accumulator, RunSummary};
use crate::engine::{ErrorSystem, LooselyCoupled};
use crate::measurement::GnssAntenna;
use crate::mechanisation::Strapdown;
use crate::scenario::{FilterKind, Scenario};
use crate::state::NavState;

/// The outcome of [`run`]: the summary and, if
/// [`RunOptions::keep_records`], every aiding epoch.
///
/// ```
/// use kestrel_nav::experiment::{run, RunOptions};
/// let s = kestrel_nav::scenario::by_name("004").unwrap();
/// let r = run(&s, &s.filters[0], 4, &RunOptions::default().with_duration(3.0)).unwrap();
/// assert_eq!(r.records.len(), r.summary.epochs);
/// assert_eq!(r.records[0].time, 1.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// RMS errors and counts.
    pub summary: RunSummary,
    /// The aiding epochs in time order (empty without `keep_records`).
    pub records: Vec<EpochRecord>,
}

/// Runs `kind` on `scenario` with sensor noise from `seed`.
///
/// # Errors
/// [`RunError`]: an invalid trajectory, a filter kind that is unsupported
/// or does not fit the scenario, an invalid filter parameter, or a filter
/// that diverged (with its name and the time).
///
/// ```
/// use kestrel_nav::experiment::{run, RunError, RunOptions};
/// use kestrel_nav::scenario::by_name;
/// let s = by_name("002").unwrap();
/// let opts = RunOptions::default().with_duration(10.0);
/// let ekf = run(&s, &s.filters[0], 5, &opts).unwrap();
/// let robust = run(&s, &s.filters[1], 5, &opts).unwrap();
/// assert_eq!(ekf.records.len(), 10);
/// assert_eq!(ekf.summary.data_digest, robust.summary.data_digest);
/// let odometer_only = by_name("003").unwrap().filters[1];
/// assert!(matches!(run(&s, &odometer_only, 5, &opts), Err(RunError::Incompatible { .. })));
/// ```
pub fn run(
    scenario: &Scenario,
    kind: &FilterKind,
    seed: u64,
    options: &RunOptions,
) -> Result<RunResult, RunError> {
    let mut records = Vec::new();
    let keep = options.keep_records;
    let summary = run_with(scenario, kind, seed, options, |r| {
        if keep {
            records.push(*r);
        }
    })?;
    Ok(RunResult { summary, records })
}

/// As [`run`], handing each aiding epoch to `on_epoch` instead of storing
/// it (`options.keep_records` is ignored).
///
/// # Errors
/// As [`run`].
///
/// ```
/// use kestrel_nav::experiment::{run_with, RunOptions};
/// let s = kestrel_nav::scenario::by_name("003").unwrap();
/// let mut worst = 0.0f64;
/// let summary = run_with(&s, &s.filters[2], 3, &RunOptions::default().with_duration(5.0),
///     |r| worst = worst.max(r.position.norm())).unwrap();
/// assert_eq!(summary.epochs, 50); // 10 Hz odometer
/// assert_eq!(summary.max_position, worst);
/// ```
pub fn run_with<C: FnMut(&EpochRecord)>(
    scenario: &Scenario,
    kind: &FilterKind,
    seed: u64,
    options: &RunOptions,
    mut on_epoch: C,
) -> Result<RunSummary, RunError> {
    let sim = Simulation::new(scenario, seed, options)?;
    dispatch(
        Job {
            label: kind.label(),
            scenario,
            sim,
            options,
            on_epoch: &mut on_epoch,
        },
        kind,
    )
}

/// What a runner's step returns at an aiding epoch: the navigation
/// solution, what the update did and the filter's position-error
/// covariance (NED, m², `None` if the runner has no single one).
pub(crate) type Solved = (NavState, Adaptation, Option<nalgebra::Matrix3<f64>>);

/// Everything a run needs besides the filter.
pub(crate) struct Job<'a, C> {
    pub label: &'static str,
    pub scenario: &'a Scenario,
    pub sim: Simulation,
    pub options: &'a RunOptions,
    pub on_epoch: &'a mut C,
}

impl<C: FnMut(&EpochRecord)> Job<'_, C> {
    /// The error for a kind that does not fit the scenario.
    pub(crate) fn incompatible(&self, reason: &'static str) -> RunError {
        RunError::Incompatible {
            filter: self.label,
            reason,
        }
    }

    /// Runs the engine over the simulation with this filter and aiding.
    pub(crate) fn run<const N: usize, S, F, A, G>(
        self,
        system: S,
        filter: Filter<f64, N, F, A>,
        mut aiding: G,
    ) -> Result<RunSummary, RunError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        A: PriorAdapter<f64>,
        G: Aiding<N, S, F, A>,
    {
        let sc = self.scenario;
        let start = self.sim.initial_truth();
        let mut engine = LooselyCoupled::new(
            Strapdown::new(sc.earth, sc.initial_state(&start)),
            filter,
            system,
            GnssAntenna::new(sc.filter.lever_arm),
            self.options.covariance_interval,
        );
        let label = self.label;
        let (summary, outcome) = self.drive(|sample| {
            let fail = |error| RunError::Filter {
                filter: label,
                time: sample.truth.time,
                error,
            };
            engine.imu(&sample.imu).map_err(fail)?;
            let adaptation = aiding.update(&mut engine, sample).map_err(fail)?;
            Ok(adaptation.map(|a| {
                // δr is states 6–8 of every error model here.
                let p = engine.covariance().fixed_view::<3, 3>(6, 6).into_owned();
                (*engine.solution(), a, Some(p))
            }))
        });
        outcome.map(|()| summary)
    }

    /// The RMS accumulator of this run's options.
    pub(crate) fn accumulator(&self) -> Accumulator {
        let axes = self
            .options
            .axes
            .unwrap_or_else(|| PositionAxes::for_scenario(&self.scenario.name));
        Accumulator::new(axes, self.options.rms_from)
    }

    /// The loop every runner shares: hands each sample to `step`, which
    /// returns the navigation solution and adaptation of an aiding epoch
    /// (`None` between aidings), and measures, accumulates and reports
    /// each epoch. The first failure ends the run; the summary covers the
    /// samples up to it.
    pub(crate) fn drive<P>(self, mut step: P) -> (RunSummary, Result<(), RunError>)
    where
        P: FnMut(&SensorSample) -> Result<Option<Solved>, RunError>,
    {
        let sc = self.scenario;
        let mut acc = self.accumulator();
        let mut digest = Digest::default();
        let mut end = self.sim.initial_truth().time;
        let label = self.label;
        for sample in self.sim {
            digest.add(&sample);
            end = sample.truth.time;
            let epoch = step(&sample).and_then(|solved| {
                solved
                    .map(|(nav, adaptation, position_covariance)| {
                        EpochRecord::measure(&sc.earth, &nav, &sample.truth, adaptation, label)
                            .map(|r| r.with_position_covariance(position_covariance.as_ref()))
                    })
                    .transpose()
            });
            match epoch {
                Ok(Some(record)) => {
                    acc.add(&record);
                    (self.on_epoch)(&record);
                }
                Ok(None) => {}
                Err(e) => return (acc.finish(label, end, digest.value()), Err(e)),
            }
        }
        (acc.finish(label, end, digest.value()), Ok(()))
    }
}
