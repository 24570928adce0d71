//! From the runtime [`FilterKind`] to the concrete filter types: a `match`
//! whose every arm calls a generic loop once ([`build_filter`] for the
//! engine filters, shared with loops over other data sources; the
//! federated filters run their own loop).

use kestrel::adapter::{NoiseAdapter, PriorAdapter};
use kestrel::adaptive::{
    ChiSquareGate, HuberInflation, ImprovedAdaptive, SageHusaFading, StrongTracking, WindowedNoise,
};
use kestrel::form::{FadeStates, SquareRootForm, UnscentedForm};
use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::sigma::MerweParams;
use kestrel::{Ekf, FilterError, SrUkf, Ukf};

use super::aiding::{
    AttitudeVelocityPosition, GnssAiding, GnssNoise, GnssPositionVelocity, OdometerAiding,
    OdometerProcessing,
};
use super::error::RunError;
use super::federated::federated;
use super::record::Describe;
use super::run::{Feed, Job};
use crate::scenario::{
    ErrorModelKind, FadeBlock, FilterKind, FilterSetup, InitialUncertainty, MeasurementKind,
    Scenario,
};
use kestrel::nav::engine::{Ins15, Ins18, Ins21};
use kestrel::nav::measurement::{GnssAntenna, Odometer};
use kestrel::nav::odometer::{FuzzyOdometer, InsOdometer16, MaxThreshold, ScaleFactorProcess};

/// A filter loop over some data source whose GNSS updates have `M` rows:
/// [`build_filter`] hands it the concrete parts of a [`FilterKind`].
pub trait FilterLoop<const M: usize> {
    /// What running the loop returns.
    type Output;
    /// Whether the loop runs the 16-state odometer model
    /// ([`FilterKind::Standard`] then runs [`odometer`](Self::odometer)
    /// with `()`, every reading as it is).
    fn odometer_model(&self) -> bool;
    /// Runs the GNSS-aided closed-loop EKF with `adapter`, the fade
    /// restricted to the `fade` states.
    fn gnss<A>(self, adapter: A, fade: FadeBlock) -> Self::Output
    where
        A: PriorAdapter<f64> + NoiseAdapter<f64, M, Report: Describe> + 'static;
    /// Runs the odometer EKF with `processing`.
    fn odometer<P: OdometerProcessing + 'static>(self, processing: P) -> Self::Output;
}

/// Why [`build_filter`] built no filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BuildError {
    /// A parameter of the kind is invalid.
    Invalid(FilterError),
    /// The kind does not run in an engine loop, or not with these
    /// parameters.
    Unsupported(&'static str),
}

/// Builds the adapter or odometer processing of `kind` and runs `run` with
/// it: one monomorphised loop per kind.
///
/// # Errors
/// [`BuildError::Invalid`] for an invalid parameter,
/// [`BuildError::Unsupported`] for the federated kinds (they run their own
/// loop) and fuzzy windows other than 10, 20 or 50.
///
/// ```
/// use kestrel_app::experiment::{build_filter, BuildError, FilterLoop, Describe, OdometerProcessing};
/// use kestrel_app::scenario::{FadeBlock, FilterKind};
/// use kestrel::adapter::{NoiseAdapter, PriorAdapter};
/// struct Name;
/// impl FilterLoop<6> for Name {
///     type Output = &'static str;
///     fn odometer_model(&self) -> bool { false }
///     fn gnss<A>(self, _: A, _: FadeBlock) -> &'static str
///     where A: PriorAdapter<f64> + NoiseAdapter<f64, 6, Report: Describe> {
///         core::any::type_name::<A>()
///     }
///     fn odometer<P: OdometerProcessing>(self, _: P) -> &'static str { "odometer" }
/// }
/// assert_eq!(build_filter(&FilterKind::Standard, Name), Ok("()"));
/// let bad = FilterKind::IctErekf { significance: 2.0 };
/// assert!(matches!(build_filter(&bad, Name), Err(BuildError::Invalid(_))));
/// ```
pub fn build_filter<const M: usize, L: FilterLoop<M>>(
    kind: &FilterKind,
    run: L,
) -> Result<L::Output, BuildError> {
    use BuildError::{Invalid, Unsupported};
    Ok(match *kind {
        FilterKind::Standard if run.odometer_model() => run.odometer(()),
        FilterKind::Standard => run.gnss((), FadeBlock::All),
        FilterKind::SageHusaFading {
            forgetting,
            reserve,
            lambda_max,
            fade_states,
        } => run.gnss(
            SageHusaFading::<f64, M>::with_params(forgetting, reserve, lambda_max)
                .map_err(Invalid)?,
            fade_states,
        ),
        FilterKind::ImprovedAdaptive {
            forgetting,
            reserve,
            lambda_max,
            significance,
            fade_states,
        } => run.gnss(
            ImprovedAdaptive::<f64, M>::with_params(forgetting, significance, reserve, lambda_max)
                .map_err(Invalid)?,
            fade_states,
        ),
        FilterKind::IctErekf { significance } => run.gnss(
            HuberInflation::<f64, M>::new(significance).map_err(Invalid)?,
            FadeBlock::All,
        ),
        FilterKind::ChiSquareGate { significance } => run.gnss(
            ChiSquareGate::<f64, M>::new(significance).map_err(Invalid)?,
            FadeBlock::All,
        ),
        FilterKind::StrongTrackingFading {
            rho,
            softening,
            lambda_max,
            fade_states,
        } => run.gnss(
            StrongTracking::new(rho, softening)
                .and_then(|s| s.with_max_fade(lambda_max))
                .map_err(Invalid)?,
            fade_states,
        ),
        FilterKind::MaxThreshold {
            threshold,
            r_window,
        } => {
            let gate = MaxThreshold::<f64>::new(threshold);
            // The isolation test first, so an isolated reading never
            // enters the R window (as the fuzzy filter's veto).
            match r_window {
                None => run.odometer(gate),
                Some(10) => run.odometer((gate, windowed_r::<10>().map_err(Invalid)?)),
                Some(20) => run.odometer((gate, windowed_r::<20>().map_err(Invalid)?)),
                Some(50) => run.odometer((gate, windowed_r::<50>().map_err(Invalid)?)),
                Some(_) => return Err(Unsupported("R windows of 10, 20 or 50 innovations only")),
            }
        }
        // The window is a compile-time length (no allocation in the update).
        FilterKind::FuzzyAdaptive { window } => match window {
            10 => run.odometer(FuzzyOdometer::<f64, 10>::as_published().map_err(Invalid)?),
            20 => run.odometer(FuzzyOdometer::<f64, 20>::as_published().map_err(Invalid)?),
            50 => run.odometer(FuzzyOdometer::<f64, 50>::as_published().map_err(Invalid)?),
            _ => {
                return Err(Unsupported(
                    "fuzzy R windows of 10, 20 or 50 innovations only",
                ))
            }
        },
        FilterKind::FederatedUkf { .. } | FilterKind::FederatedSrUkf { .. } => {
            return Err(Unsupported("the federated filters run their own loop"))
        }
    })
}

/// The windowed R estimate of the max-threshold baseline: the fuzzy
/// filter's (same variance floor, 10⁻⁴ (m/s)²).
fn windowed_r<const W: usize>() -> Result<WindowedNoise<f64, 3, W>, FilterError> {
    WindowedNoise::new(1e-4)
}

/// The closed-loop error-state EKF of `N` states: zero error state, P0 the
/// squares of `p0`'s σ for `model`, `adapter`, the fade restricted to the
/// `fade` states.
///
/// # Errors
/// [`FilterError::InvalidParameter`] if `model` does not have `N` states;
/// the filter's error for an invalid P0.
///
/// ```
/// use kestrel_app::experiment::closed_loop_ekf;
/// use kestrel_app::scenario::{ErrorModelKind, FadeBlock, InitialUncertainty};
/// let p0 = InitialUncertainty::default();
/// let f = closed_loop_ekf::<15, ()>(&p0, ErrorModelKind::Ins15, (), FadeBlock::All).unwrap();
/// assert_eq!(f.covariance().nrows(), 15);
/// assert!(closed_loop_ekf::<18, ()>(&p0, ErrorModelKind::Ins15, (), FadeBlock::All).is_err());
/// ```
pub fn closed_loop_ekf<const N: usize, A>(
    p0: &InitialUncertainty,
    model: ErrorModelKind,
    adapter: A,
    fade: FadeBlock,
) -> Result<Ekf<f64, N, A>, FilterError> {
    let std = p0.std_vector(model);
    if std.len() != N {
        return Err(FilterError::InvalidParameter {
            name: "P0",
            valid: "one standard deviation for each state of the error model",
        });
    }
    let p0 =
        SMatrix::<f64, N, N>::from_diagonal(&SVector::from_iterator(std.iter().map(|s| s * s)));
    let mut filter = Ekf::new(SVector::zeros(), p0)?.with_adapter(adapter);
    filter
        .form_mut()
        .set_fade_states(FadeStates::range(fade.states(N)));
    Ok(filter)
}

/// Builds and runs the filter of `kind`.
pub(crate) fn dispatch<'a>(
    job: Job<'a>,
    kind: &FilterKind,
) -> Result<Box<dyn Feed + 'a>, RunError> {
    let label = job.label;
    let built = match *kind {
        FilterKind::FederatedUkf { alpha, beta, kappa } => {
            let p0 = p0_15(&job.scenario.filter);
            let local = UnscentedForm::new(&p0)
                .and_then(|f| f.with_params(MerweParams::new(alpha, beta, kappa)))
                .and_then(|f| Ukf::with_form(SVector::zeros(), f));
            return federated(job, local);
        }
        FilterKind::FederatedSrUkf { alpha, beta, kappa } => {
            let p0 = p0_15(&job.scenario.filter);
            let local = SquareRootForm::new(&p0)
                .and_then(|f| f.with_params(MerweParams::new(alpha, beta, kappa)))
                .and_then(|f| SrUkf::with_form(SVector::zeros(), f));
            return federated(job, local);
        }
        _ if job.scenario.filter.measurement == MeasurementKind::AttitudeVelocityPosition => {
            build_filter::<9, _>(kind, Scenario9(job))
        }
        _ => build_filter::<6, _>(kind, Scenario6(job)),
    };
    built.unwrap_or_else(|e| {
        Err(match e {
            BuildError::Invalid(error) => RunError::InvalidParameter {
                filter: label,
                error,
            },
            BuildError::Unsupported(reason) => RunError::Unsupported {
                filter: label,
                reason,
            },
        })
    })
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

/// A scenario run whose GNSS updates are position and velocity (m = 6).
struct Scenario6<'a>(Job<'a>);

/// A scenario run whose GNSS updates add the attitude (m = 9).
struct Scenario9<'a>(Job<'a>);

impl<'a> FilterLoop<6> for Scenario6<'a> {
    type Output = Result<Box<dyn Feed + 'a>, RunError>;

    fn odometer_model(&self) -> bool {
        self.0.scenario.filter.measurement == MeasurementKind::OdometerVelocity
    }

    fn gnss<A>(self, adapter: A, fade: FadeBlock) -> Self::Output
    where
        A: PriorAdapter<f64> + NoiseAdapter<f64, 6, Report: Describe> + 'static,
    {
        let job = self.0;
        let s = &job.scenario.filter;
        if s.measurement != MeasurementKind::GnssPositionVelocity {
            return Err(gnss_incompatible(&job));
        }
        match s.error_model {
            ErrorModelKind::Ins15 => {
                let f = ekf::<15, _>(&job, adapter, fade)?;
                let g = GnssPositionVelocity(gnss_aiding(&job)?);
                job.run(Ins15::new(s.imu_model), f, g)
            }
            ErrorModelKind::Ins18 => {
                let f = ekf::<18, _>(&job, adapter, fade)?;
                let g = GnssPositionVelocity(gnss_aiding(&job)?);
                job.run(Ins18::new(s.imu_model), f, g)
            }
            ErrorModelKind::Ins21 { scale_tau } => {
                let f = ekf::<21, _>(&job, adapter, fade)?;
                let g = GnssPositionVelocity(gnss_aiding(&job)?);
                job.run(Ins21::new(s.imu_model, scale_tau), f, g)
            }
            ErrorModelKind::Odometer16 { .. } => Err(gnss_incompatible(&job)),
        }
    }

    fn odometer<P: OdometerProcessing + 'static>(self, processing: P) -> Self::Output {
        odometer(self.0, processing)
    }
}

impl<'a> FilterLoop<9> for Scenario9<'a> {
    type Output = Result<Box<dyn Feed + 'a>, RunError>;

    fn odometer_model(&self) -> bool {
        false
    }

    fn gnss<A>(self, adapter: A, fade: FadeBlock) -> Self::Output
    where
        A: PriorAdapter<f64> + NoiseAdapter<f64, 9, Report: Describe> + 'static,
    {
        let job = self.0;
        let s = &job.scenario.filter;
        match s.error_model {
            ErrorModelKind::Ins15 => {
                let f = ekf::<15, _>(&job, adapter, fade)?;
                let g = attitude_aiding(&job)?;
                job.run(Ins15::new(s.imu_model), f, g)
            }
            ErrorModelKind::Ins18 => {
                let f = ekf::<18, _>(&job, adapter, fade)?;
                let g = attitude_aiding(&job)?;
                job.run(Ins18::new(s.imu_model), f, g)
            }
            ErrorModelKind::Ins21 { scale_tau } => {
                let f = ekf::<21, _>(&job, adapter, fade)?;
                let g = attitude_aiding(&job)?;
                job.run(Ins21::new(s.imu_model, scale_tau), f, g)
            }
            ErrorModelKind::Odometer16 { .. } => Err(gnss_incompatible(&job)),
        }
    }

    fn odometer<P: OdometerProcessing + 'static>(self, _: P) -> Self::Output {
        Err(odometer_incompatible(&self.0))
    }
}

fn gnss_incompatible(job: &Job<'_>) -> RunError {
    job.incompatible("GNSS filters need the 15-, 18- or 21-state model and a GNSS measurement")
}

fn odometer_incompatible(job: &Job<'_>) -> RunError {
    job.incompatible("odometer filters need the 16-state odometer model")
}

/// The closed-loop EKF of `N` states with P0 from the scenario.
fn ekf<const N: usize, A>(
    job: &Job<'_>,
    adapter: A,
    fade: FadeBlock,
) -> Result<Ekf<f64, N, A>, RunError> {
    let s = &job.scenario.filter;
    if s.p0.std_vector(s.error_model).len() != N {
        return Err(job.incompatible("P0 does not match the error model"));
    }
    closed_loop_ekf(&s.p0, s.error_model, adapter, fade).map_err(|error| {
        RunError::InvalidParameter {
            filter: job.label,
            error,
        }
    })
}

/// The GNSS aiding: the setup's lever arm and GNSS `R`, if the scenario
/// has a receiver and the setup an R.
fn gnss_aiding(job: &Job<'_>) -> Result<GnssAiding, RunError> {
    let s = &job.scenario.filter;
    match (&job.scenario.gnss, s.r.position, s.r.velocity) {
        (Some(_), Some(position), Some(velocity)) => Ok(GnssAiding {
            antenna: GnssAntenna::new(s.lever_arm),
            noise: GnssNoise::Fixed { position, velocity },
        }),
        _ => Err(job.incompatible("no GNSS receiver or no GNSS position and velocity R")),
    }
}

/// The GNSS aiding with the attitude reference and its `R`.
fn attitude_aiding(job: &Job<'_>) -> Result<AttitudeVelocityPosition, RunError> {
    let (Some(_), Some(attitude_std)) = (&job.scenario.attitude, job.scenario.filter.r.attitude)
    else {
        return Err(job.incompatible("no attitude reference or no attitude R"));
    };
    Ok(AttitudeVelocityPosition {
        gnss: gnss_aiding(job)?,
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
fn odometer<P: OdometerProcessing + 'static>(
    job: Job<'_>,
    processing: P,
) -> Result<Box<dyn Feed + '_>, RunError> {
    let sc: &Scenario = job.scenario;
    let s = &sc.filter;
    let (ErrorModelKind::Odometer16 { scale_tau }, MeasurementKind::OdometerVelocity) =
        (s.error_model, s.measurement)
    else {
        return Err(odometer_incompatible(&job));
    };
    let (Some(config), Some(r)) = (&sc.odometer, s.r.odometer) else {
        return Err(job.incompatible("no odometer or no odometer R"));
    };
    let [pitch, yaw] = s.odometer_mounting;
    let aiding = OdometerAiding {
        odometer: Odometer::new(r.x, r.y).with_mounting(pitch, yaw),
        processing,
    };
    let scale = ScaleFactorProcess::new(scale_tau, config.scale_markov_sigma, s.p0.odometer_scale);
    let filter = ekf::<16, _>(&job, (), FadeBlock::All)?;
    job.run(InsOdometer16::new(s.imu_model, scale), filter, aiding)
}
