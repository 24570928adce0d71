//! The run loop: one generic function per filter type.

use kestrel::adapter::PriorAdapter;
use kestrel::form::{Form, PredictForm};
use kestrel::Filter;

use super::aiding::Aiding;
use super::data::{Digest, SensorSample, Simulation};
use super::dispatch::dispatch;
use super::error::RunError;
use super::health::Health;
use super::options::{PositionAxes, RunOptions};
use super::record::{Adaptation, EpochRecord};
use super::summary::ScaleEstimate;
use super::summary::{Accumulator, RunSummary};
use crate::scenario::{FilterKind, MeasurementKind, Scenario};
use kestrel::nav::engine::{ErrorSystem, LooselyCoupled};
use kestrel::nav::measurement::GnssAntenna;
use kestrel::nav::mechanisation::Strapdown;
use kestrel::nav::state::NavState;

/// The outcome of [`run`]: the summary and, if
/// [`RunOptions::keep_records`], every aiding epoch.
///
/// ```
/// use kestrel_app::experiment::{run, RunOptions};
/// let s = kestrel_app::scenario::by_name("004").unwrap();
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
/// use kestrel_app::experiment::{run, RunError, RunOptions};
/// use kestrel_app::scenario::by_name;
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
/// use kestrel_app::experiment::{run_with, RunOptions};
/// let s = kestrel_app::scenario::by_name("003").unwrap();
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
    let mut feed = dispatch(Job::new(kind.label(), scenario, &sim, options), kind)?;
    feed_all(sim, feed.as_mut(), &mut on_epoch)?;
    Ok(feed.summary())
}

/// Runs every filter of `kinds` on one simulation of `scenario` with
/// sensor noise from `seed`: the same results as [`run_with`] for each
/// kind, for the cost of simulating once.
///
/// The filters take the samples in lockstep, so only one sample is held
/// at a time, whatever the run's length. `on_epoch(i, record)` receives
/// the aiding epochs of `kinds[i]`. Entry `i` of the result is that
/// filter's summary or why it did not finish; a filter that fails leaves
/// the others running.
///
/// # Errors
/// [`RunError`] if the simulation cannot be built (an invalid trajectory
/// or rate, a run too long); each filter's own errors are in its entry.
///
/// ```
/// use kestrel_app::experiment::{run_together, run_with, RunError, RunOptions};
/// let s = kestrel_app::scenario::by_name("003").unwrap();
/// let opts = RunOptions::default().with_duration(20.0);
/// let mut epochs = vec![0; s.filters.len()];
/// let all = run_together(&s, &s.filters, 7, &opts, |i, _| epochs[i] += 1).unwrap();
/// for (kind, together) in s.filters.iter().zip(&all) {
///     let alone = run_with(&s, kind, 7, &opts, |_| {}).unwrap();
///     assert_eq!(together.as_ref().unwrap(), &alone);
/// }
/// assert_eq!(epochs[0], 200); // 10 Hz odometer for 20 s
/// // A kind that does not fit the scenario (002's GNSS χ² filter) fails alone.
/// let gnss_only = kestrel_app::scenario::by_name("002").unwrap().filters[1];
/// let mixed = run_together(&s, &[gnss_only, s.filters[0]], 7, &opts, |_, _| {}).unwrap();
/// assert!(matches!(mixed[0], Err(RunError::Incompatible { .. })));
/// assert!(mixed[1].is_ok());
/// ```
pub fn run_together<C: FnMut(usize, &EpochRecord)>(
    scenario: &Scenario,
    kinds: &[FilterKind],
    seed: u64,
    options: &RunOptions,
    mut on_epoch: C,
) -> Result<Vec<Result<RunSummary, RunError>>, RunError> {
    let sim = Simulation::new(scenario, seed, options)?;
    let mut lanes: Vec<Lane<'_>> = kinds
        .iter()
        .map(|kind| {
            let job = Job::new(kind.label(), scenario, &sim, options);
            match dispatch(job, kind).and_then(|mut feed| feed.start().map(|()| feed)) {
                Ok(feed) => Lane::Running(feed),
                Err(e) => Lane::Ended(Box::new(Err(e))),
            }
        })
        .collect();
    for sample in sim {
        let mut running = false;
        for (i, lane) in lanes.iter_mut().enumerate() {
            let Lane::Running(feed) = lane else { continue };
            match feed.feed(&sample) {
                Ok(Some(record)) => on_epoch(i, &record),
                Ok(None) => {}
                Err(e) => *lane = Lane::Ended(Box::new(Err(e))),
            }
            running |= matches!(lane, Lane::Running(_));
        }
        if !running {
            break;
        }
    }
    Ok(lanes
        .into_iter()
        .map(|lane| match lane {
            Lane::Running(feed) => Ok(feed.summary()),
            Lane::Ended(result) => *result,
        })
        .collect())
}

/// One filter of [`run_together`]: still taking samples, or ended (by a
/// failure, or before the first sample).
enum Lane<'a> {
    Running(Box<dyn Feed + 'a>),
    Ended(Box<Result<RunSummary, RunError>>),
}

/// Feeds every sample of `sim` to `feed`, handing its aiding epochs to
/// `on_epoch`, until the data ends or the filter fails.
pub(crate) fn feed_all(
    sim: Simulation,
    feed: &mut dyn Feed,
    on_epoch: &mut dyn FnMut(&EpochRecord),
) -> Result<(), RunError> {
    feed.start()?;
    for sample in sim {
        if let Some(record) = feed.feed(&sample)? {
            on_epoch(&record);
        }
    }
    Ok(())
}

/// A filter run that takes its data one sample at a time, so that several
/// filters can share one simulation ([`run_together`]).
pub(crate) trait Feed {
    /// Called once before the first sample: a failure of the filter's
    /// set-up that belongs to the run (the summary is then empty).
    fn start(&mut self) -> Result<(), RunError> {
        Ok(())
    }

    /// Processes one sample: the record of an aiding epoch, `None`
    /// between aidings. An error ends the run; feed nothing after it.
    fn feed(&mut self, sample: &SensorSample) -> Result<Option<EpochRecord>, RunError>;

    /// The summary of the samples fed so far (up to and including a
    /// failing one).
    fn summary(&self) -> RunSummary;
}

/// What a runner's step returns at an aiding epoch: the navigation
/// solution, what the update did, the filter's position-error covariance
/// (NED, m², `None` if the runner has no single one) and its odometer
/// scale-factor estimate and σ (`None` without a scale state).
pub(crate) type Solved = (
    NavState,
    Adaptation,
    Option<kestrel::nalgebra::Matrix3<f64>>,
    Option<(f64, f64)>,
);

/// Everything a run needs besides the filter and its data.
pub(crate) struct Job<'a> {
    pub label: &'static str,
    pub scenario: &'a Scenario,
    /// The true initial state of the data to come.
    pub start: NavState,
    pub options: &'a RunOptions,
}

impl<'a> Job<'a> {
    /// The job of running `label` on `sim`'s data.
    pub(crate) fn new(
        label: &'static str,
        scenario: &'a Scenario,
        sim: &Simulation,
        options: &'a RunOptions,
    ) -> Self {
        Self {
            label,
            scenario,
            start: sim.initial_truth(),
            options,
        }
    }

    /// The error for a kind that does not fit the scenario.
    pub(crate) fn incompatible(&self, reason: &'static str) -> RunError {
        RunError::Incompatible {
            filter: self.label,
            reason,
        }
    }

    /// The engine with this filter and aiding, ready for the samples.
    pub(crate) fn run<const N: usize, S, F, A, G>(
        self,
        system: S,
        filter: Filter<f64, N, F, A>,
        mut aiding: G,
    ) -> Result<Box<dyn Feed + 'a>, RunError>
    where
        S: ErrorSystem<N> + 'a,
        F: Form<f64, N> + PredictForm<f64, N, S::Process> + 'a,
        A: PriorAdapter<f64> + 'a,
        G: Aiding<N, S, F, A> + 'a,
    {
        let sc = self.scenario;
        let mut engine = LooselyCoupled::new(
            Strapdown::new(sc.earth, sc.initial_state(&self.start)),
            filter,
            system,
            GnssAntenna::new(sc.filter.lever_arm),
            self.options.covariance_interval,
        );
        let label = self.label;
        Ok(self.driver(move |sample| {
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
                let scale =
                    <S as kestrel::nav::measurement::ErrorLayout<N>>::ODOMETER_SCALE.map(|i| {
                        (
                            engine.corrections().odometer_scale,
                            engine.covariance()[(i, i)].max(0.0).sqrt(),
                        )
                    });
                (*engine.solution(), a, Some(p), scale)
            }))
        }))
    }

    /// The RMS accumulator of this run's options.
    pub(crate) fn accumulator(&self) -> Accumulator {
        let axes = self
            .options
            .axes
            .unwrap_or_else(|| PositionAxes::for_scenario(&self.scenario.name));
        Accumulator::new(axes, self.options.rms_from)
    }

    /// The run every runner shares around its `step`, which returns the
    /// navigation solution and adaptation of an aiding epoch (`None`
    /// between aidings): it measures, accumulates and fingerprints.
    pub(crate) fn driver<P>(self, step: P) -> Box<dyn Feed + 'a>
    where
        P: FnMut(&SensorSample) -> Result<Option<Solved>, RunError> + 'a,
    {
        Box::new(Driver {
            label: self.label,
            scenario: self.scenario,
            measurement: measurement_name(self.scenario.filter.measurement),
            health: Health::new(),
            scale: None,
            acc: self.accumulator(),
            digest: Digest::default(),
            end: self.start.time,
            step,
        })
    }

    /// A run that fails before its first sample with `error`, its summary
    /// empty.
    pub(crate) fn stillborn(self, error: RunError) -> Box<dyn Feed + 'a> {
        Box::new(Stillborn {
            summary: self.accumulator().finish(
                self.label,
                self.start.time,
                Digest::default().value(),
            ),
            error: Some(error),
        })
    }
}

/// The name of a measurement kind in health events.
fn measurement_name(kind: MeasurementKind) -> &'static str {
    match kind {
        MeasurementKind::GnssPositionVelocity => "GNSS",
        MeasurementKind::AttitudeVelocityPosition => "attitude + GNSS",
        MeasurementKind::OdometerVelocity => "odometer",
    }
}

/// [`Job::driver`]'s run.
struct Driver<'a, P> {
    label: &'static str,
    scenario: &'a Scenario,
    measurement: &'static str,
    health: Health,
    scale: Option<ScaleEstimate>,
    acc: Accumulator,
    digest: Digest,
    end: f64,
    step: P,
}

impl<P> Feed for Driver<'_, P>
where
    P: FnMut(&SensorSample) -> Result<Option<Solved>, RunError>,
{
    fn feed(&mut self, sample: &SensorSample) -> Result<Option<EpochRecord>, RunError> {
        self.digest.add(sample);
        self.end = sample.truth.time;
        let (label, earth) = (self.label, &self.scenario.earth);
        let record = (self.step)(sample)?
            .map(|(nav, adaptation, position_covariance, scale)| {
                if let (Some((estimate, sigma)), Some(truth)) = (scale, sample.odometer_scale) {
                    self.scale = Some(ScaleEstimate {
                        estimate,
                        sigma,
                        truth,
                    });
                }
                EpochRecord::measure(earth, &nav, &sample.truth, adaptation, label)
                    .map(|r| r.with_position_covariance(position_covariance.as_ref()))
            })
            .transpose()?;
        if let Some(record) = &record {
            self.acc.add(record);
            self.health
                .update(record.time, self.measurement, &record.adaptation);
            self.health.nees(record.time, record.position_nees);
        }
        Ok(record)
    }

    fn summary(&self) -> RunSummary {
        let mut s = self.acc.finish(self.label, self.end, self.digest.value());
        s.health = self.health.summary();
        s.odometer_scale = self.scale;
        s
    }
}

/// [`Job::stillborn`]'s run.
struct Stillborn {
    summary: RunSummary,
    error: Option<RunError>,
}

impl Feed for Stillborn {
    fn start(&mut self) -> Result<(), RunError> {
        self.error.take().map_or(Ok(()), Err)
    }

    fn feed(&mut self, _: &SensorSample) -> Result<Option<EpochRecord>, RunError> {
        // Unreachable after a failed `start`; a second start is a no-op.
        Ok(None)
    }

    fn summary(&self) -> RunSummary {
        self.summary
    }
}
