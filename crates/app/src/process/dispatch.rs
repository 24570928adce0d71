//! From the configured filter to the concrete engine type: the experiment
//! runner's [`build_filter`] picks the adapter or odometer processing, and
//! this file's loop runs it over the files (one monomorphised loop per
//! filter type).

use crate::experiment::{
    build_filter, closed_loop_ekf, Adaptation, AidedEngine, BuildError, Describe, FilterLoop,
    GnssAiding, OdometerAiding, OdometerProcessing,
};
use crate::scenario::{ErrorModelKind, FadeBlock};
use kestrel::adapter::{NoiseAdapter, PriorAdapter};
use kestrel::form::{CovarianceForm, PredictForm};
use kestrel::nav::engine::{ErrorSystem, Ins15, Ins18, Ins21, LooselyCoupled, SensorCorrections};
use kestrel::nav::measurement::{GnssAntenna, GnssFix, Odometer, OdometerReading};
use kestrel::nav::odometer::{InsOdometer16, ScaleFactorProcess};
use kestrel::nav::Strapdown;
use kestrel::{Ekf, FilterError, LinearizedProcess};

use super::pipeline::{drive, FileAiding, Job};
use crate::config::process::{OdometerSettings, Settings};
use crate::Error;

/// What the GNSS file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum GnssLayout {
    /// No GNSS file (or an empty one).
    None,
    /// Position only (7 columns).
    Position,
    /// Position and velocity (13 columns).
    PositionVelocity,
}

/// Builds the filter of the settings and runs it over the job.
pub(crate) fn dispatch(s: &Settings, layout: GnssLayout, job: &mut Job<'_>) -> Result<(), Error> {
    let files = Files { s, layout, job };
    let built = match layout {
        GnssLayout::Position => build_filter::<3, _>(&s.kind, files),
        _ => build_filter::<6, _>(&s.kind, files),
    };
    built.unwrap_or_else(|e| {
        Err(Error::Failed(match e {
            BuildError::Invalid(e) => format!("invalid filter set-up: {e}"),
            BuildError::Unsupported(reason) => {
                format!(
                    "{} is not available in `process` ({reason})",
                    s.kind.label()
                )
            }
        }))
    })
}

/// The GNSS update of `M`-row fixes.
trait FixUpdate<const M: usize> {
    fn fix<const N: usize>(
        &self,
        engine: &mut impl AidedEngine<N, M>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError>;
}

impl FixUpdate<6> for GnssAiding {
    fn fix<const N: usize>(
        &self,
        engine: &mut impl AidedEngine<N, 6>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError> {
        self.update(engine, fix, |a, s, ins, f| a.position_velocity(s, ins, f))
    }
}

impl FixUpdate<3> for GnssAiding {
    fn fix<const N: usize>(
        &self,
        engine: &mut impl AidedEngine<N, 3>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError> {
        self.update(engine, fix, |a, s, ins, f| a.position(s, ins, f))
    }
}

/// The aiding of a GNSS-only filter: `M`-row fixes. An odometer reading
/// is refused: the filter has no odometer error model.
struct GnssOnly<const M: usize>(GnssAiding);

impl<const N: usize, const M: usize, S, F, A> FileAiding<LooselyCoupled<f64, N, S, F, A>>
    for GnssOnly<M>
where
    LooselyCoupled<f64, N, S, F, A>: AidedEngine<N, M>,
    GnssAiding: FixUpdate<M>,
{
    fn gnss(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError> {
        self.0.fix(engine, fix)
    }

    fn odometer(
        &mut self,
        _: &mut LooselyCoupled<f64, N, S, F, A>,
        _: &OdometerReading,
    ) -> Result<Adaptation, FilterError> {
        Err(FilterError::InvalidParameter {
            name: "odometer",
            valid: "absent: this filter has no odometer error model",
        })
    }
}

/// The aiding of the odometer filter: `M`-row fixes and the odometer
/// readings through its processing `P`.
struct WithOdometer<P, const M: usize> {
    gnss: GnssAiding,
    odometer: OdometerAiding<P>,
}

impl<const N: usize, const M: usize, S, F, A, P> FileAiding<LooselyCoupled<f64, N, S, F, A>>
    for WithOdometer<P, M>
where
    LooselyCoupled<f64, N, S, F, A>: AidedEngine<N, M> + AidedEngine<N, 3>,
    GnssAiding: FixUpdate<M>,
    P: OdometerProcessing,
{
    fn gnss(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError> {
        FixUpdate::<M>::fix(&self.gnss, engine, fix)
    }

    fn odometer(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        reading: &OdometerReading,
    ) -> Result<Adaptation, FilterError> {
        self.odometer.update(engine, reading)
    }
}

/// The recorded files as the data source of a filter loop.
struct Files<'a, 'p> {
    s: &'a Settings,
    layout: GnssLayout,
    job: &'a mut Job<'p>,
}

impl<const M: usize> FilterLoop<M> for Files<'_, '_>
where
    GnssAiding: FixUpdate<M>,
{
    type Output = Result<(), Error>;

    fn odometer_model(&self) -> bool {
        matches!(self.s.error_model, ErrorModelKind::Odometer16 { .. })
    }

    fn gnss<A>(self, adapter: A, fade: FadeBlock) -> Self::Output
    where
        A: PriorAdapter<f64> + NoiseAdapter<f64, M, Report: Describe>,
    {
        let imu = self.s.imu;
        match self.s.error_model {
            ErrorModelKind::Ins15 => self.run(Ins15::new(imu), adapter, fade),
            ErrorModelKind::Ins18 => self.run(Ins18::new(imu), adapter, fade),
            ErrorModelKind::Ins21 { scale_tau } => {
                self.run(Ins21::new(imu, scale_tau), adapter, fade)
            }
            ErrorModelKind::Odometer16 { .. } => Err(Error::Failed(
                "the odometer model runs `ekf`, `max-threshold` or `fuzzy-adaptive`".into(),
            )),
        }
    }

    fn odometer<P: OdometerProcessing>(self, processing: P) -> Self::Output {
        odometer(self.s, self.layout, self.job, processing)
    }
}

impl Files<'_, '_> {
    /// Runs the GNSS-aided EKF of `N` states on `system`.
    fn run<const N: usize, const M: usize, S, A>(
        self,
        system: S,
        adapter: A,
        fade: FadeBlock,
    ) -> Result<(), Error>
    where
        S: ErrorSystem<N>,
        S::Process: LinearizedProcess<f64, N>,
        A: PriorAdapter<f64>,
        CovarianceForm<f64, N>: PredictForm<f64, N, S::Process>,
        Engine<N, S, A>: AidedEngine<N, M>,
        GnssAiding: FixUpdate<M>,
    {
        let mut engine = engine(self.s, system, ekf(self.s, adapter, fade)?);
        if self.job.smoother.is_some() {
            engine.record_epochs();
        }
        drive(self.job, &mut engine, GnssOnly::<M>(gnss_aiding(self.s)))?;
        smooth(self.job, &mut engine)
    }
}

/// The engine of `N` states on `S` with adapter `A`.
type Engine<const N: usize, S, A> = LooselyCoupled<f64, N, S, CovarianceForm<f64, N>, A>;

/// The closed-loop EKF of `N` states with P0 from the settings.
fn ekf<const N: usize, A>(
    s: &Settings,
    adapter: A,
    fade: FadeBlock,
) -> Result<Ekf<f64, N, A>, Error> {
    closed_loop_ekf(&s.p0, s.error_model, adapter, fade)
        .map_err(|e| Error::Failed(format!("invalid filter set-up: {e}")))
}

fn gnss_aiding(s: &Settings) -> GnssAiding {
    GnssAiding {
        antenna: GnssAntenna::new(s.lever_arm),
        noise: s.gnss_noise,
    }
}

fn engine<const N: usize, S, A>(s: &Settings, system: S, filter: Ekf<f64, N, A>) -> Engine<N, S, A>
where
    S: ErrorSystem<N>,
    A: PriorAdapter<f64>,
    CovarianceForm<f64, N>: PredictForm<f64, N, S::Process>,
{
    LooselyCoupled::new(
        Strapdown::new(s.earth, s.start),
        filter,
        system,
        GnssAntenna::new(s.lever_arm),
        s.covariance_interval,
    )
    .with_corrections(SensorCorrections {
        imu: s.initial_imu,
        ..SensorCorrections::default()
    })
}

/// The 16-state SINS / odometer EKF with odometer processing `processing`
/// (and GNSS position and velocity updates if the GNSS file has them).
fn odometer<P: OdometerProcessing>(
    s: &Settings,
    layout: GnssLayout,
    job: &mut Job<'_>,
    processing: P,
) -> Result<(), Error> {
    let ErrorModelKind::Odometer16 { scale_tau } = s.error_model else {
        return Err(Error::Failed(
            "odometer filters need error_model = `odometer16`".into(),
        ));
    };
    let o = s.odometer.unwrap_or(OdometerSettings {
        rate: 0.0,
        speed_std: 1.0,
        nhc_std: 1.0,
        mounting: [0.0, 0.0],
        lever_arm: kestrel::nav::nalgebra::Vector3::zeros(),
        scale_sigma: 0.0,
    });
    let [pitch, yaw] = o.mounting;
    let odometer = OdometerAiding {
        odometer: Odometer::new(o.speed_std, o.nhc_std)
            .with_mounting(pitch, yaw)
            .with_lever_arm(o.lever_arm),
        processing,
    };
    let scale = ScaleFactorProcess::new(scale_tau, o.scale_sigma, s.p0.odometer_scale);
    let system = InsOdometer16::new(s.imu, scale);
    let mut engine = engine(s, system, ekf::<16, _>(s, (), FadeBlock::All)?);
    if job.smoother.is_some() {
        engine.record_epochs();
    }
    let gnss = gnss_aiding(s);
    // Position-only fixes update the position, fixes with velocity both.
    let driven = if layout == GnssLayout::Position {
        drive(job, &mut engine, WithOdometer::<P, 3> { gnss, odometer })
    } else {
        drive(job, &mut engine, WithOdometer::<P, 6> { gnss, odometer })
    };
    driven?;
    smooth(job, &mut engine)
}

/// With `--smooth`: the backward pass and the smoothed output, after a
/// successful forward run (the report goes into the job).
fn smooth<const N: usize, S, A>(
    job: &mut Job<'_>,
    engine: &mut Engine<N, S, A>,
) -> Result<(), Error>
where
    S: ErrorSystem<N>,
    A: PriorAdapter<f64>,
    CovarianceForm<f64, N>: PredictForm<f64, N, S::Process>,
{
    let Some(record) = job.smoother.take() else {
        return Ok(());
    };
    if let Some(e) = job.sink.evaluation.as_mut() {
        e.flush_truth_copy()?;
    }
    if engine.recording_overrun() > 0 {
        return Err(Error::Failed(format!(
            "internal error: {} covariance epochs were not recorded for the smoother",
            engine.recording_overrun()
        )));
    }
    let last = engine
        .finish_epochs()
        .ok_or_else(|| Error::Failed("internal error: the smoother recorded nothing".into()))?;
    let (report, traces) = record.finish::<N, S>(last)?;
    job.smoothed = Some(report);
    job.smoothed_traces = traces;
    Ok(())
}
