//! From the runtime [`FilterKind`] to the concrete filter types: a `match`
//! whose every arm calls the generic [`Job::run`] once.

use kestrel_adaptive::{HuberInflation, ImprovedAdaptive, SageHusaFading, StrongTracking};
use kestrel_core::form::{FadeStates, SquareRootForm, UnscentedForm};
use kestrel_core::sigma::MerweParams;
use kestrel_core::{Ekf, FilterError, SrUkf, Ukf};
use nalgebra::{SMatrix, SVector};

use super::aiding::{
    AttitudeVelocityPosition, GnssNoise, GnssPositionVelocity, OdometerAiding, OdometerProcessing,
    Unprocessed,
};
use super::error::RunError;
use super::federated::federated;
use super::record::EpochRecord;
use super::run::Job;
use super::summary::RunSummary;
use crate::engine::{Ins15, Ins18};
use crate::measurement::{GnssAntenna, Odometer};
use crate::odometer::{FuzzyOdometer, InsOdometer16, MaxThreshold, ScaleFactorProcess};
use crate::scenario::{
    ErrorModelKind, FadeBlock, FilterKind, FilterSetup, MeasurementKind, Scenario,
};

/// A GNSS-aided filter with adapter `$a6` (m = 6) or `$a9` (m = 9, the
/// attitude measurement), each a `Result<_, FilterError>`, on the 15- or
/// 18-state model.
macro_rules! gnss_filter {
    ($job:ident, $a6:expr, $a9:expr) => {
        gnss_filter!($job, FadeBlock::All, $a6, $a9)
    };
    ($job:ident, $fade:expr, $a6:expr, $a9:expr) => {{
        let sc = $job.scenario;
        let s = &sc.filter;
        match (s.error_model, s.measurement) {
            (ErrorModelKind::Ins15, MeasurementKind::GnssPositionVelocity) => {
                let f = ekf::<15, _>(&$job, s, $a6, $fade)?;
                let g = gnss_pv(&$job)?;
                $job.run(Ins15::new(s.imu_model), f, g)
            }
            (ErrorModelKind::Ins18, MeasurementKind::GnssPositionVelocity) => {
                let f = ekf::<18, _>(&$job, s, $a6, $fade)?;
                let g = gnss_pv(&$job)?;
                $job.run(Ins18::new(s.imu_model), f, g)
            }
            (ErrorModelKind::Ins15, MeasurementKind::AttitudeVelocityPosition) => {
                let f = ekf::<15, _>(&$job, s, $a9, $fade)?;
                let g = avp(&$job)?;
                $job.run(Ins15::new(s.imu_model), f, g)
            }
            (ErrorModelKind::Ins18, MeasurementKind::AttitudeVelocityPosition) => {
                let f = ekf::<18, _>(&$job, s, $a9, $fade)?;
                let g = avp(&$job)?;
                $job.run(Ins18::new(s.imu_model), f, g)
            }
            _ => Err($job.incompatible(
                "GNSS filters need the 15- or 18-state model and a GNSS measurement",
            )),
        }
    }};
}

/// Builds and runs the filter of `kind`.
pub(crate) fn dispatch<C: FnMut(&EpochRecord)>(
    job: Job<'_, C>,
    kind: &FilterKind,
) -> Result<RunSummary, RunError> {
    match *kind {
        FilterKind::FederatedUkf { alpha, beta, kappa } => {
            let p0 = p0_15(&job.scenario.filter);
            let local = UnscentedForm::new(&p0)
                .and_then(|f| f.with_params(MerweParams::new(alpha, beta, kappa)))
                .and_then(|f| Ukf::with_form(SVector::zeros(), f));
            federated(job, local)
        }
        FilterKind::FederatedSrUkf { alpha, beta, kappa } => {
            let p0 = p0_15(&job.scenario.filter);
            let local = SquareRootForm::new(&p0)
                .and_then(|f| f.with_params(MerweParams::new(alpha, beta, kappa)))
                .and_then(|f| SrUkf::with_form(SVector::zeros(), f));
            federated(job, local)
        }
        FilterKind::Standard => match job.scenario.filter.measurement {
            MeasurementKind::OdometerVelocity => odometer(job, Ok(Unprocessed)),
            _ => gnss_filter!(job, Ok(()), Ok(())),
        },
        FilterKind::SageHusaFading {
            forgetting,
            reserve,
            lambda_max,
            fade_states,
        } => gnss_filter!(
            job,
            fade_states,
            SageHusaFading::<f64, 6>::with_params(forgetting, reserve, lambda_max),
            SageHusaFading::<f64, 9>::with_params(forgetting, reserve, lambda_max)
        ),
        FilterKind::ImprovedAdaptive {
            forgetting,
            reserve,
            lambda_max,
            significance,
            fade_states,
        } => gnss_filter!(
            job,
            fade_states,
            ImprovedAdaptive::<f64, 6>::with_params(forgetting, significance, reserve, lambda_max),
            ImprovedAdaptive::<f64, 9>::with_params(forgetting, significance, reserve, lambda_max)
        ),
        FilterKind::IctErekf { significance } => gnss_filter!(
            job,
            HuberInflation::<f64, 6>::new(significance),
            HuberInflation::<f64, 9>::new(significance)
        ),
        FilterKind::StrongTrackingFading {
            rho,
            softening,
            lambda_max,
            fade_states,
        } => gnss_filter!(
            job,
            fade_states,
            StrongTracking::new(rho, softening).and_then(|s| s.with_max_fade(lambda_max)),
            StrongTracking::new(rho, softening).and_then(|s| s.with_max_fade(lambda_max))
        ),
        FilterKind::MaxThreshold { threshold } => {
            odometer(job, Ok(MaxThreshold::<f64>::new(threshold)))
        }
        // The window is a compile-time length (no allocation in the update).
        FilterKind::FuzzyAdaptive { window } => match window {
            10 => odometer(job, FuzzyOdometer::<f64, 10>::paper003()),
            20 => odometer(job, FuzzyOdometer::<f64, 20>::paper003()),
            50 => odometer(job, FuzzyOdometer::<f64, 50>::paper003()),
            _ => Err(RunError::Unsupported {
                filter: job.label,
                reason: "fuzzy R windows of 10, 20 or 50 innovations only",
            }),
        },
    }
}

/// The scenario's P0 as a 15-state covariance (zero if the model differs;
/// the federated runner then refuses the scenario).
fn p0_15(setup: &FilterSetup) -> SMatrix<f64, 15, 15> {
    let std = setup.p0.std_vector(setup.error_model);
    let mut p = SMatrix::<f64, 15, 15>::zeros();
    if std.len() == 15 {
        std.iter().enumerate().for_each(|(i, s)| p[(i, i)] = s * s);
    }
    p
}

/// The closed-loop EKF of `N` states with P0 from the setup, `adapter`,
/// and fades restricted to `fade`.
fn ekf<const N: usize, A>(
    job: &Job<'_, impl FnMut(&EpochRecord)>,
    setup: &FilterSetup,
    adapter: Result<A, FilterError>,
    fade: FadeBlock,
) -> Result<Ekf<f64, N, A>, RunError> {
    let invalid = |error| RunError::InvalidParameter {
        filter: job.label,
        error,
    };
    let adapter = adapter.map_err(invalid)?;
    let std = setup.p0.std_vector(setup.error_model);
    if std.len() != N {
        return Err(job.incompatible("P0 does not match the error model"));
    }
    let p0 =
        SMatrix::<f64, N, N>::from_diagonal(&SVector::from_iterator(std.iter().map(|s| s * s)));
    let mut filter = Ekf::new(SVector::zeros(), p0)
        .map_err(invalid)?
        .with_adapter(adapter);
    filter
        .form_mut()
        .set_fade_states(FadeStates::range(fade.states(N)));
    Ok(filter)
}

/// The filter's GNSS `R`, if the scenario has a receiver and the setup an R.
fn gnss_noise(job: &Job<'_, impl FnMut(&EpochRecord)>) -> Result<GnssNoise, RunError> {
    let r = &job.scenario.filter.r;
    match (&job.scenario.gnss, r.position, r.velocity) {
        (Some(_), Some(pos), Some(vel)) => Ok(GnssNoise { pos, vel }),
        _ => Err(job.incompatible("no GNSS receiver or no GNSS position and velocity R")),
    }
}

fn antenna(job: &Job<'_, impl FnMut(&EpochRecord)>) -> GnssAntenna {
    GnssAntenna::new(job.scenario.filter.lever_arm)
}

fn gnss_pv(job: &Job<'_, impl FnMut(&EpochRecord)>) -> Result<GnssPositionVelocity, RunError> {
    Ok(GnssPositionVelocity {
        antenna: antenna(job),
        noise: gnss_noise(job)?,
    })
}

fn avp(job: &Job<'_, impl FnMut(&EpochRecord)>) -> Result<AttitudeVelocityPosition, RunError> {
    let (Some(_), Some(attitude_std)) = (&job.scenario.attitude, job.scenario.filter.r.attitude)
    else {
        return Err(job.incompatible("no attitude reference or no attitude R"));
    };
    Ok(AttitudeVelocityPosition {
        antenna: antenna(job),
        noise: gnss_noise(job)?,
        attitude_std,
    })
}

/// The 16-state SINS / odometer filter (plain EKF) with odometer
/// processing `processing`.
///
/// The scale-factor process: the scenario's correlation time, the
/// odometer's Markov σ (the filter knows the sensor model, as it knows the
/// IMU's) and P0's scale σ. R: the setup's odometer σ, north for the
/// speed row and east for both constraint rows.
fn odometer<C: FnMut(&EpochRecord), P: OdometerProcessing>(
    job: Job<'_, C>,
    processing: Result<P, FilterError>,
) -> Result<RunSummary, RunError> {
    let sc: &Scenario = job.scenario;
    let s = &sc.filter;
    let (ErrorModelKind::Odometer16 { scale_tau }, MeasurementKind::OdometerVelocity) =
        (s.error_model, s.measurement)
    else {
        return Err(job.incompatible("odometer filters need the 16-state odometer model"));
    };
    let (Some(config), Some(r)) = (&sc.odometer, s.r.odometer) else {
        return Err(job.incompatible("no odometer or no odometer R"));
    };
    let processing = processing.map_err(|error| RunError::InvalidParameter {
        filter: job.label,
        error,
    })?;
    let [pitch, yaw] = s.odometer_mounting;
    let aiding = OdometerAiding {
        odometer: Odometer::new(r.x, r.y).with_mounting(pitch, yaw),
        processing,
    };
    let scale = ScaleFactorProcess::new(scale_tau, config.scale_markov_sigma, s.p0.odometer_scale);
    let filter = ekf::<16, _>(&job, s, Ok(()), FadeBlock::All)?;
    job.run(InsOdometer16::new(s.imu_model, scale), filter, aiding)
}
