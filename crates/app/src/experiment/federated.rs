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

use kestrel::adaptive::federated::{FederatedFilter, FusionError, PredictSet, Sharing};
use kestrel::form::UpdateForm;
use kestrel::models::LinearProcess;
use kestrel::nalgebra::{SMatrix, SVector, Vector3};
use kestrel::real::lit;
use kestrel::{Ekf, Filter, FilterError, Quantity, Real};

use super::data::SensorSample;
use super::error::RunError;
use super::record::Adaptation;
use super::run::{Feed, Job, Solved};
use crate::scenario::{ErrorModelKind, MeasurementKind, Scenario};
use kestrel::nav::engine::{feed_back, ErrorSystem, Ins15, SensorCorrections};
use kestrel::nav::error_model::ForcingMean;
use kestrel::nav::measurement::{ErrorMeasurement, GnssAntenna, GnssFix, InsContext};
use kestrel::nav::mechanisation::Strapdown;
use kestrel::nav::Ellipsoid;
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
    let gnss_std = gnss_std(&job)?;
    let label = job.label;
    let invalid = |error| RunError::InvalidParameter {
        filter: label,
        error,
    };
    let x0 = SVector::<T, 15>::zeros();
    let p0t = p0.map(lit::<T>);
    let locals = (Ekf::new(x0, p0t).map_err(invalid)?, local.map_err(invalid)?);
    let fed = match FederatedFilter::new(locals, Sharing::edop(), x0, p0t) {
        Ok(f) => f,
        Err(error) => {
            let e = RunError::Fusion {
                filter: label,
                time: job.start.time,
                error,
            };
            return Ok(job.stillborn(e));
        }
    };
    let mut federation = Federation::new(&job, fed, d, gnss_std);
    Ok(job.driver(move |sample| federation.step(sample)))
}

/// The σ of the GNSS position and velocity (the filter's `R`), or why the
/// scenario does not suit the federated filter.
fn gnss_std(job: &Job<'_>) -> Result<(Vector3<f64>, Vector3<f64>), RunError> {
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
    Ok((pos_std, vel_std))
}

/// The local filters of the federation: an EKF on the position, the
/// velocity local `F` (UKF or SR-UKF) on the velocity.
type Locals<T, F> = (Ekf<T, 15>, Filter<T, 15, F>);

/// The federated loop's state from one sample to the next: the
/// federation (in `T`, on the scaled error states), the INS it corrects
/// (in `f64`) and what the propagation collects between covariance epochs.
struct Federation<T: Real, F> {
    label: &'static str,
    fed: FederatedFilter<T, 15, 2, Locals<T, F>>,
    /// The diagonal of `D⁻¹` (scaled error state to natural units).
    inv: SVector<f64, 15>,
    /// `D` and `D⁻¹` as matrices, to scale `Φ`, `Q` and `H`.
    dd: SMatrix<f64, 15, 15>,
    di: SMatrix<f64, 15, 15>,
    earth: Ellipsoid,
    system: Ins15,
    antenna: GnssAntenna,
    ins: Strapdown,
    corrections: SensorCorrections,
    /// The specific force and rate over the current propagation interval.
    forcing: ForcingMean,
    /// The last sample's angular rate (for the lever-arm velocity).
    omega_ib: Vector3<f64>,
    /// The covariance propagation interval, s.
    interval: f64,
    /// The GNSS position and velocity σ.
    gnss_std: (Vector3<f64>, Vector3<f64>),
}

impl<T, F> Federation<T, F>
where
    T: Real,
    F: UpdateForm<T, 15, ErrorMeasurement<T, 15, 3>, 3>,
    Locals<T, F>: for<'m> PredictSet<'m, T, 15, 2, LinearProcess<T, 15>>,
{
    /// The loop of `job` on the federation `fed` and the scaling `d`.
    fn new(
        job: &Job<'_>,
        fed: FederatedFilter<T, 15, 2, Locals<T, F>>,
        d: &SVector<f64, 15>,
        gnss_std: (Vector3<f64>, Vector3<f64>),
    ) -> Self {
        let sc = job.scenario;
        let s = &sc.filter;
        let inv = d.map(|v| 1.0 / v);
        Self {
            label: job.label,
            fed,
            dd: SMatrix::<f64, 15, 15>::from_diagonal(d),
            di: SMatrix::<f64, 15, 15>::from_diagonal(&inv),
            inv,
            earth: sc.earth,
            system: Ins15::new(s.imu_model),
            antenna: GnssAntenna::new(s.lever_arm),
            ins: Strapdown::new(sc.earth, sc.initial_state(&job.start)),
            corrections: SensorCorrections::default(),
            forcing: ForcingMean::default(),
            omega_ib: Vector3::zeros(),
            interval: job.options.covariance_interval,
            gnss_std,
        }
    }

    /// One sample: the mechanisation, the propagation when due and, at a
    /// fix with velocity, the local updates, the fusion and the feedback.
    fn step(&mut self, sample: &SensorSample) -> Result<Option<Solved>, RunError> {
        let at = At {
            filter: self.label,
            time: sample.truth.time,
        };
        let inc = self.corrections.imu.compensate(&sample.imu);
        self.ins.step(&inc);
        if inc.dt > 0.0 {
            self.omega_ib = inc.dtheta / inc.dt;
        }
        self.forcing.add(&self.ins, inc.dt);
        let (pos_std, vel_std) = self.gnss_std;
        let fix = sample
            .gnss
            .map(|g| g.value.with_std(pos_std, vel_std))
            .filter(|f| f.vel.is_some());
        // Propagate per interval, and up to the sample before an update.
        let dt = self.forcing.dt();
        if dt > 0.0 && (dt >= self.interval - 1e-9 || fix.is_some()) {
            self.propagate(at)?;
        }
        let Some(fix) = fix else {
            return Ok(None);
        };
        let adaptation = self.update(at, &fix)?;
        // The fused covariance is not a single filter's: no NEES.
        Ok(Some((*self.ins.state(), adaptation, None, None)))
    }

    /// Propagates every local over the interval collected, with the model
    /// scaled to `x' = D x` and rounded to `T`.
    fn propagate(&mut self, at: At) -> Result<(), RunError> {
        let model = self
            .system
            .process(&self.earth, self.ins.state(), &self.forcing);
        let phi = self.dd * model.phi() * self.di;
        let q = self.dd * model.qd() * self.dd;
        let scaled = LinearProcess::new(phi.map(lit::<T>), q.map(lit::<T>));
        self.fed
            .predict(&scaled, lit(self.forcing.dt()))
            .map_err(|e| at.fusion(e))?;
        self.forcing.clear();
        Ok(())
    }

    /// The position local's and the velocity local's updates with `fix`,
    /// their fusion and the closed-loop feedback.
    fn update(&mut self, at: At, fix: &GnssFix) -> Result<Adaptation, RunError> {
        let (pos, vel) = self.measurements(fix);
        let d0 = self
            .fed
            .locals_mut()
            .0
            .update_detailed(&pos, &pos.z())
            .map_err(|e| at.failed(e))?;
        self.fed.record(0, &d0.report).map_err(|e| at.fusion(e))?;
        let d1 = self
            .fed
            .locals_mut()
            .1
            .update_detailed(&vel, &vel.z())
            .map_err(|e| at.failed(e))?;
        self.fed.record(1, &d1.report).map_err(|e| at.fusion(e))?;
        self.fed.fuse().map_err(|e| at.fusion(e))?;
        self.feed_back(at)?;
        Ok(Adaptation {
            nis: to_f64(d0.report.nis + d1.report.nis),
            adapted_nis: to_f64(d0.report.adapted_nis + d1.report.adapted_nis),
            rows: 6,
            rejected: d0.report.rejected && d1.report.rejected,
            noise_trace: to_f64(d0.noise.trace() + d1.noise.trace()),
            ..Adaptation::default()
        })
    }

    /// The GNSS position-velocity measurement of `fix` split into the
    /// position local's rows and the velocity local's, on the scaled
    /// states and rounded to `T`.
    fn measurements(
        &self,
        fix: &GnssFix,
    ) -> (ErrorMeasurement<T, 15, 3>, ErrorMeasurement<T, 15, 3>) {
        let ctx = InsContext::new(self.earth, *self.ins.state(), self.omega_ib);
        let pv = self
            .antenna
            .position_velocity::<f64, 15, _>(&self.system, &ctx, fix);
        let h = pv.h() * self.di;
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
        (pos, vel)
    }

    /// Closed loop: feeds the fused estimate back (in f64, natural units)
    /// and zeroes every local.
    fn feed_back(&mut self, at: At) -> Result<(), RunError> {
        let dx = self.fed.state().map(to_f64).component_mul(&self.inv);
        if let Some(index) = dx.iter().position(|v| !v.is_finite()) {
            return Err(at.failed(FilterError::NonFinite {
                what: Quantity::UpdatedState,
                row: index,
                col: 0,
            }));
        }
        feed_back::<f64, 15, Ins15>(
            &dx,
            &self.earth,
            self.ins.state_mut(),
            &mut self.corrections,
        );
        let x0 = SVector::<T, 15>::zeros();
        let locals = self.fed.locals_mut();
        locals.0.set_state(x0).map_err(|e| at.failed(e))?;
        locals.1.set_state(x0).map_err(|e| at.failed(e))?;
        Ok(())
    }
}

/// The filter and the sample's time, naming a failure.
#[derive(Clone, Copy)]
struct At {
    filter: &'static str,
    time: f64,
}

impl At {
    /// A failure of the federation.
    fn fusion(self, error: FusionError) -> RunError {
        RunError::Fusion {
            filter: self.filter,
            time: self.time,
            error,
        }
    }

    /// A failure of a local filter.
    fn failed(self, error: FilterError) -> RunError {
        RunError::Filter {
            filter: self.filter,
            time: self.time,
            error,
        }
    }
}
