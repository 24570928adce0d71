//! From the configured filter to the concrete engine type: a `match` whose
//! every arm runs the generic loop once.

use kestrel::adaptive::{HuberInflation, ImprovedAdaptive, SageHusaFading, StrongTracking};
use kestrel::form::FadeStates;
use kestrel::nav::engine::{Ins15, Ins18, LooselyCoupled};
use kestrel::nav::measurement::{GnssAntenna, Odometer};
use kestrel::nav::nalgebra::{SMatrix, SVector};
use kestrel::nav::odometer::{FuzzyOdometer, InsOdometer16, MaxThreshold, ScaleFactorProcess};
use kestrel::nav::scenario::{ErrorModelKind, FadeBlock, FilterKind};
use kestrel::nav::Strapdown;
use kestrel::{Ekf, FilterError};

use super::aiding::{OdometerAid, PositionOnly, PositionVelocity, Processing, Unprocessed};
use super::config::Settings;
use super::pipeline::{drive, Job};
use crate::CliError;

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

/// The closed-loop EKF of `N` states with P0 from the settings and `adapter`.
fn ekf<const N: usize, A>(
    s: &Settings,
    adapter: Result<A, FilterError>,
    fade: FadeBlock,
) -> Result<Ekf<f64, N, A>, CliError> {
    let invalid = |e: FilterError| CliError::Failed(format!("invalid filter set-up: {e}"));
    let adapter = adapter.map_err(invalid)?;
    let std = s.p0.std_vector(s.error_model);
    let p0 =
        SMatrix::<f64, N, N>::from_diagonal(&SVector::from_iterator(std.iter().map(|x| x * x)));
    let mut filter = Ekf::new(SVector::zeros(), p0)
        .map_err(invalid)?
        .with_adapter(adapter);
    filter
        .form_mut()
        .set_fade_states(FadeStates::range(fade.states(N)));
    Ok(filter)
}

/// Runs a GNSS-aided filter: `$a6` / `$a3` build its adapter for
/// position-and-velocity (m = 6) or position-only (m = 3) fixes.
macro_rules! gnss_filter {
    ($s:ident, $job:ident, $layout:ident, $a6:expr, $a3:expr) => {
        gnss_filter!($s, $job, $layout, FadeBlock::All, $a6, $a3)
    };
    ($s:ident, $job:ident, $layout:ident, $fade:expr, $a6:expr, $a3:expr) => {{
        let antenna = GnssAntenna::new($s.lever_arm);
        let noise = $s.gnss_noise;
        macro_rules! go {
            ($n:literal, $system:expr) => {{
                if $layout == GnssLayout::Position {
                    let aid = PositionOnly { antenna, noise };
                    let mut engine = engine($s, $system, ekf::<$n, _>($s, $a3, $fade)?);
                    drive(
                        $job,
                        &mut engine,
                        |e, f| aid.update(e, f),
                        |_, _| unreachable_odometer(),
                    )
                } else {
                    let aid = PositionVelocity { antenna, noise };
                    let mut engine = engine($s, $system, ekf::<$n, _>($s, $a6, $fade)?);
                    drive(
                        $job,
                        &mut engine,
                        |e, f| aid.update(e, f),
                        |_, _| unreachable_odometer(),
                    )
                }
            }};
        }
        match $s.error_model {
            ErrorModelKind::Ins15 => go!(15, Ins15::new($s.imu)),
            ErrorModelKind::Ins18 => go!(18, Ins18::new($s.imu)),
            ErrorModelKind::Odometer16 { .. } => Err(CliError::Failed(
                "the odometer model runs `ekf`, `max-threshold` or `fuzzy-adaptive`".into(),
            )),
        }
    }};
}

/// GNSS-only filters never see an odometer reading (no rate is set).
fn unreachable_odometer() -> Result<kestrel::nav::experiment::Adaptation, FilterError> {
    Err(FilterError::InvalidParameter {
        name: "odometer aiding without an odometer model",
    })
}

fn engine<const N: usize, S, A>(
    s: &Settings,
    system: S,
    filter: Ekf<f64, N, A>,
) -> LooselyCoupled<f64, N, S, kestrel::form::CovarianceForm<f64, N>, A>
where
    S: kestrel::nav::engine::ErrorSystem<N>,
    A: kestrel::adapter::PriorAdapter<f64>,
    kestrel::form::CovarianceForm<f64, N>: kestrel::form::PredictForm<f64, N, S::Process>,
{
    LooselyCoupled::new(
        Strapdown::new(s.earth, s.start),
        filter,
        system,
        GnssAntenna::new(s.lever_arm),
        s.covariance_interval,
    )
}

/// Builds the filter of the settings and runs it over the job.
pub(crate) fn dispatch(s: &Settings, layout: GnssLayout, job: &mut Job) -> Result<(), CliError> {
    match s.kind {
        FilterKind::Standard => match s.error_model {
            ErrorModelKind::Odometer16 { .. } => odometer(s, layout, job, Ok(Unprocessed)),
            _ => gnss_filter!(s, job, layout, Ok(()), Ok(())),
        },
        FilterKind::IctErekf { significance } => gnss_filter!(
            s,
            job,
            layout,
            HuberInflation::<f64, 6>::new(significance),
            HuberInflation::<f64, 3>::new(significance)
        ),
        FilterKind::ImprovedAdaptive {
            forgetting,
            reserve,
            lambda_max,
            significance,
            fade_states,
        } => gnss_filter!(
            s,
            job,
            layout,
            fade_states,
            ImprovedAdaptive::<f64, 6>::with_params(forgetting, significance, reserve, lambda_max),
            ImprovedAdaptive::<f64, 3>::with_params(forgetting, significance, reserve, lambda_max)
        ),
        FilterKind::SageHusaFading {
            forgetting,
            reserve,
            lambda_max,
            fade_states,
        } => gnss_filter!(
            s,
            job,
            layout,
            fade_states,
            SageHusaFading::<f64, 6>::with_params(forgetting, reserve, lambda_max),
            SageHusaFading::<f64, 3>::with_params(forgetting, reserve, lambda_max)
        ),
        FilterKind::StrongTrackingFading {
            rho,
            softening,
            lambda_max,
            fade_states,
        } => gnss_filter!(
            s,
            job,
            layout,
            fade_states,
            StrongTracking::new(rho, softening).and_then(|a| a.with_max_fade(lambda_max)),
            StrongTracking::new(rho, softening).and_then(|a| a.with_max_fade(lambda_max))
        ),
        FilterKind::MaxThreshold { threshold } => {
            odometer(s, layout, job, Ok(MaxThreshold::<f64>::new(threshold)))
        }
        FilterKind::FuzzyAdaptive { window } => match window {
            10 => odometer(s, layout, job, FuzzyOdometer::<f64, 10>::paper003()),
            20 => odometer(s, layout, job, FuzzyOdometer::<f64, 20>::paper003()),
            50 => odometer(s, layout, job, FuzzyOdometer::<f64, 50>::paper003()),
            _ => Err(CliError::Failed(
                "fuzzy R windows of 10, 20 or 50 only".into(),
            )),
        },
        FilterKind::FederatedUkf { .. } | FilterKind::FederatedSrUkf { .. } => Err(
            CliError::Failed("the federated filters are not available in `process`".into()),
        ),
    }
}

/// The 16-state SINS / odometer EKF with odometer processing `processing`
/// (and GNSS position and velocity updates if the GNSS file has them).
fn odometer<P: Processing>(
    s: &Settings,
    layout: GnssLayout,
    job: &mut Job,
    processing: Result<P, FilterError>,
) -> Result<(), CliError> {
    let ErrorModelKind::Odometer16 { scale_tau } = s.error_model else {
        return Err(CliError::Failed(
            "odometer filters need error_model = `odometer16`".into(),
        ));
    };
    if layout == GnssLayout::Position {
        return Err(CliError::Failed(
            "the odometer model takes GNSS fixes with velocity (13 columns) only".into(),
        ));
    }
    let processing =
        processing.map_err(|e| CliError::Failed(format!("invalid odometer processing: {e}")))?;
    let o = s.odometer.unwrap_or(super::config::OdometerSettings {
        rate: 0.0,
        speed_std: 1.0,
        nhc_std: 1.0,
        mounting: [0.0, 0.0],
        scale_sigma: 0.0,
    });
    let [pitch, yaw] = o.mounting;
    let mut aid = OdometerAid {
        odometer: Odometer::new(o.speed_std, o.nhc_std).with_mounting(pitch, yaw),
        processing,
    };
    let scale = ScaleFactorProcess::new(scale_tau, o.scale_sigma, s.p0.odometer_scale);
    let system = InsOdometer16::new(s.imu, scale);
    let mut engine = engine(s, system, ekf::<16, _>(s, Ok(()), FadeBlock::All)?);
    let gnss = PositionVelocity {
        antenna: GnssAntenna::new(s.lever_arm),
        noise: s.gnss_noise,
    };
    drive(
        job,
        &mut engine,
        |e, f| gnss.update(e, f),
        |e, r| aid.update(e, r),
    )
}
