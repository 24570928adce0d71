//! Paper 001's federated filter on the loosely coupled INS: a local EKF
//! on the GNSS position and a local UKF or SR-UKF on the GNSS velocity,
//! both on the common 15-state error model, fused in information form with
//! adaptive information sharing by EDOP, and fed back in closed loop.
//!
//! The local "UKF on the nonlinear INS model" of the paper becomes a UKF on
//! the error-state model here (the error state is propagated linearly, the
//! nonlinearity stays in the mechanisation); the sigma-point form still
//! matters numerically (the scenario's α = 10⁻³ makes `W₀` strongly
//! negative), which is what the UKF / SR-UKF comparison is about.
//!
//! One loop serves the runner (`f64`, natural units) and the precision
//! study (`f32` or `f64`, error states scaled by a diagonal `D`): the
//! models are built in `f64`, scaled, and rounded to the filter's type.

use kestrel::adaptive::federated::{FederatedFilter, PredictSet, Sharing};
use kestrel::form::UpdateForm;
use kestrel::models::LinearProcess;
use kestrel::nalgebra::{SMatrix, SVector, Vector3};
use kestrel::real::lit;
use kestrel::{Ekf, Filter, FilterError, Quantity, Real};

use super::error::RunError;
use super::record::Adaptation;
use super::run::{Feed, Job};
use crate::scenario::{ErrorModelKind, MeasurementKind, Scenario};
use kestrel::nav::engine::{feed_back, ErrorSystem, Ins15, SensorCorrections};
use kestrel::nav::error_model::ForcingMean;
use kestrel::nav::measurement::{ErrorMeasurement, GnssAntenna, InsContext};
use kestrel::nav::mechanisation::Strapdown;
use kestrel::real::to_f64;

/// Runs the federated filter whose velocity local is `local` (its state
/// and covariance are reset to the scenario's P0 by the federation).
pub(crate) fn federated<'a, F>(
    job: Job<'a>,
    local: Result<Filter<f64, 15, F>, FilterError>,
) -> Result<Box<dyn Feed + 'a>, RunError>
where
    F: UpdateForm<f64, 15, ErrorMeasurement<f64, 15, 3>, 3> + 'a,
    (Ekf<f64, 15>, Filter<f64, 15, F>): for<'m> PredictSet<'m, f64, 15, 2, LinearProcess<f64, 15>>,
{
    let natural = SVector::repeat(1.0);
    let p0 = scaled_p0(job.scenario, &natural);
    federated_scaled(job, local, &p0, &natural)
}

/// The scenario's P0 of the 15 error states scaled by `d`:
/// `diag((σᵢ dᵢ)²)`.
pub(crate) fn scaled_p0(scenario: &Scenario, d: &SVector<f64, 15>) -> SMatrix<f64, 15, 15> {
    let s = &scenario.filter;
    let std = s.p0.std_vector(s.error_model);
    SMatrix::from_diagonal(&SVector::from_iterator(
        std.iter().zip(d.iter()).map(|(v, k)| (v * k).powi(2)),
    ))
}

/// The federated loop in type `T` on the error states `x' = D x`
/// (`d` = the diagonal of `D`, `p0` already scaled). Errors of the set-up
/// are returned as such; a federation that cannot start fails the run at
/// its start ([`Job::stillborn`]).
pub(crate) fn federated_scaled<'a, T, F>(
    job: Job<'a>,
    local: Result<Filter<T, 15, F>, FilterError>,
    p0: &SMatrix<f64, 15, 15>,
    d: &SVector<f64, 15>,
) -> Result<Box<dyn Feed + 'a>, RunError>
where
    T: Real,
    F: UpdateForm<T, 15, ErrorMeasurement<T, 15, 3>, 3> + 'a,
    (Ekf<T, 15>, Filter<T, 15, F>): for<'m> PredictSet<'m, T, 15, 2, LinearProcess<T, 15>>,
{
    let label = job.label;
    let sc = job.scenario;
    let s = &sc.filter;
    if (s.error_model, s.measurement)
        != (ErrorModelKind::Ins15, MeasurementKind::GnssPositionVelocity)
    {
        return Err(job.incompatible(
            "the federated filter needs the 15-state model and GNSS position and velocity",
        ));
    }
    let (Some(_), Some(pos_std), Some(vel_std)) = (&sc.gnss, s.r.position, s.r.velocity) else {
        return Err(job.incompatible("no GNSS receiver or no GNSS R"));
    };
    let invalid = |error| RunError::InvalidParameter {
        filter: label,
        error,
    };
    let x0 = SVector::<T, 15>::zeros();
    let p0t = p0.map(lit::<T>);
    let locals = (Ekf::new(x0, p0t).map_err(invalid)?, local.map_err(invalid)?);
    let start = job.start;
    let mut fed = match FederatedFilter::new(locals, Sharing::edop(), x0, p0t) {
        Ok(f) => f,
        Err(error) => {
            let e = RunError::Fusion {
                filter: label,
                time: start.time,
                error,
            };
            return Ok(job.stillborn(e));
        }
    };

    let inv = d.map(|v| 1.0 / v);
    let dd = SMatrix::<f64, 15, 15>::from_diagonal(d);
    let di = SMatrix::<f64, 15, 15>::from_diagonal(&inv);
    let earth = sc.earth;
    let system = Ins15::new(s.imu_model);
    let antenna = GnssAntenna::new(s.lever_arm);
    let mut ins = Strapdown::new(earth, sc.initial_state(&start));
    let mut corrections = SensorCorrections::default();
    let mut forcing = ForcingMean::default();
    let mut omega_ib = Vector3::zeros();
    let interval = job.options.covariance_interval;
    Ok(job.driver(move |sample| {
        let time = sample.truth.time;
        let fusion = |error| RunError::Fusion {
            filter: label,
            time,
            error,
        };
        let failed = |error| RunError::Filter {
            filter: label,
            time,
            error,
        };
        let inc = corrections.imu.compensate(&sample.imu);
        ins.step(&inc);
        if inc.dt > 0.0 {
            omega_ib = inc.dtheta / inc.dt;
        }
        forcing.add(&ins, inc.dt);
        let fix = sample
            .gnss
            .map(|g| g.value.with_std(pos_std, vel_std))
            .filter(|f| f.vel.is_some());
        // Propagate per interval, and up to the sample before an update.
        if forcing.dt() > 0.0 && (forcing.dt() >= interval - 1e-9 || fix.is_some()) {
            let model = system.process(&earth, ins.state(), &forcing);
            let phi = dd * model.phi() * di;
            let q = dd * model.qd() * dd;
            let scaled = LinearProcess::new(phi.map(lit::<T>), q.map(lit::<T>));
            fed.predict(&scaled, lit(forcing.dt())).map_err(fusion)?;
            forcing.clear();
        }
        let Some(fix) = fix else {
            return Ok(None);
        };
        let ctx = InsContext::new(earth, *ins.state(), omega_ib);
        let pv = antenna.position_velocity::<f64, 15, _>(&system, &ctx, &fix);
        let h = pv.h() * di;
        let z = pv.z();
        let r = pv.noise_covariance().diagonal();
        let pos = ErrorMeasurement::<T, 15, 3>::new(
            z.fixed_rows::<3>(0).into_owned(),
            h.fixed_rows::<3>(0).into_owned(),
            r.fixed_rows::<3>(0).into_owned(),
        );
        let vel = ErrorMeasurement::<T, 15, 3>::new(
            z.fixed_rows::<3>(3).into_owned(),
            h.fixed_rows::<3>(3).into_owned(),
            r.fixed_rows::<3>(3).into_owned(),
        );
        let d0 = fed
            .locals_mut()
            .0
            .update_detailed(&pos, &pos.z())
            .map_err(failed)?;
        fed.record(0, &d0.report).map_err(fusion)?;
        let d1 = fed
            .locals_mut()
            .1
            .update_detailed(&vel, &vel.z())
            .map_err(failed)?;
        fed.record(1, &d1.report).map_err(fusion)?;
        fed.fuse().map_err(fusion)?;
        // Closed loop: feed the fused estimate back (in f64, natural
        // units), zero every local.
        let dx = fed.state().map(to_f64).component_mul(&inv);
        if let Some(index) = dx.iter().position(|v| !v.is_finite()) {
            return Err(failed(FilterError::NonFinite {
                what: Quantity::UpdatedState,
                row: index,
                col: 0,
            }));
        }
        feed_back::<f64, 15, Ins15>(&dx, &earth, ins.state_mut(), &mut corrections);
        fed.locals_mut().0.set_state(x0).map_err(failed)?;
        fed.locals_mut().1.set_state(x0).map_err(failed)?;
        let adaptation = Adaptation {
            nis: to_f64(d0.report.nis + d1.report.nis),
            rejected: d0.report.rejected && d1.report.rejected,
            noise_trace: to_f64(d0.noise.trace() + d1.noise.trace()),
            ..Adaptation::default()
        };
        // The fused covariance is not a single filter's: no NEES.
        Ok(Some((*ins.state(), adaptation, None)))
    }))
}
