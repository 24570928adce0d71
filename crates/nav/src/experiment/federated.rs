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

use kestrel_adaptive::federated::{FederatedFilter, PredictSet, Sharing};
use kestrel_core::form::UpdateForm;
use kestrel_core::{Ekf, Filter, FilterError};
use nalgebra::{SMatrix, SVector, Vector3};

use super::data::Digest;
use super::error::RunError;
use super::options::PositionAxes;
use super::record::{Adaptation, EpochRecord};
use super::run::Job;
use super::summary::{Accumulator, RunSummary};
use crate::engine::{feed_back, ErrorSystem, Ins15, SensorCorrections};
use crate::error_model::{ErrorModel15, ForcingMean};
use crate::measurement::{ErrorMeasurement, GnssAntenna, InsContext};
use crate::mechanisation::Strapdown;
use crate::scenario::{ErrorModelKind, MeasurementKind};

/// Runs the federated filter whose velocity local is `local` (its state
/// and covariance are reset to the scenario's P0 by the federation).
pub(crate) fn federated<C, F>(
    job: Job<'_, C>,
    local: Result<Filter<f64, 15, F>, FilterError>,
) -> Result<RunSummary, RunError>
where
    C: FnMut(&EpochRecord),
    F: UpdateForm<f64, 15, ErrorMeasurement<f64, 15, 3>, 3>,
    (Ekf<f64, 15>, Filter<f64, 15, F>): for<'m> PredictSet<'m, f64, 15, 2, ErrorModel15>,
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
    let std = s.p0.std_vector(s.error_model);
    let p0 =
        SMatrix::<f64, 15, 15>::from_diagonal(&SVector::from_iterator(std.iter().map(|v| v * v)));
    let x0 = SVector::<f64, 15>::zeros();
    let start = job.sim.initial_truth();
    let fusion = |time, error| RunError::Fusion {
        filter: label,
        time,
        error,
    };
    let locals = (Ekf::new(x0, p0).map_err(invalid)?, local.map_err(invalid)?);
    let mut fed =
        FederatedFilter::new(locals, Sharing::edop(), x0, p0).map_err(|e| fusion(start.time, e))?;

    let earth = sc.earth;
    let system = Ins15::new(s.imu_model);
    let antenna = GnssAntenna::new(s.lever_arm);
    let mut ins = Strapdown::new(earth, sc.initial_state(&start));
    let mut corrections = SensorCorrections::default();
    let mut forcing = ForcingMean::default();
    let mut omega_ib = Vector3::zeros();
    let axes = job
        .options
        .axes
        .unwrap_or_else(|| PositionAxes::for_scenario(&sc.name));
    let mut acc = Accumulator::new(axes, job.options.rms_from);
    let mut digest = Digest::default();
    let mut end = start.time;
    let interval = job.options.covariance_interval;
    let on_epoch = job.on_epoch;
    for sample in job.sim {
        digest.add(&sample);
        let time = sample.truth.time;
        end = time;
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
            fed.predict(&model, forcing.dt())
                .map_err(|e| fusion(time, e))?;
            forcing.clear();
        }
        let Some(fix) = fix else {
            continue;
        };
        let ctx = InsContext::new(earth, *ins.state(), omega_ib);
        let pos = antenna.position::<f64, 15, _>(&system, &ctx, &fix);
        let pv = antenna.position_velocity::<f64, 15, _>(&system, &ctx, &fix);
        let vel = ErrorMeasurement::<f64, 15, 3>::new(
            pv.z().fixed_rows::<3>(3).into_owned(),
            pv.h().fixed_rows::<3>(3).into_owned(),
            pv.noise_covariance()
                .diagonal()
                .fixed_rows::<3>(3)
                .into_owned(),
        );
        let r0 = fed.locals_mut().0.update(&pos, &pos.z()).map_err(failed)?;
        fed.record(0, &r0).map_err(|e| fusion(time, e))?;
        let r1 = fed.locals_mut().1.update(&vel, &vel.z()).map_err(failed)?;
        fed.record(1, &r1).map_err(|e| fusion(time, e))?;
        fed.fuse().map_err(|e| fusion(time, e))?;
        // Closed loop: feed the fused estimate back, zero every local.
        let dx = *fed.state();
        feed_back::<f64, 15, Ins15>(&dx, &earth, ins.state_mut(), &mut corrections);
        fed.locals_mut().0.set_state(x0).map_err(failed)?;
        fed.locals_mut().1.set_state(x0).map_err(failed)?;

        let adaptation = Adaptation {
            nis: r0.nis + r1.nis,
            rejected: r0.rejected && r1.rejected,
            noise_trace: r0.noise.trace() + r1.noise.trace(),
            ..Adaptation::default()
        };
        let record = EpochRecord::measure(&earth, ins.state(), &sample.truth, adaptation, label)?;
        acc.add(&record);
        on_epoch(&record);
    }
    Ok(acc.finish(label, end, digest.value()))
}
