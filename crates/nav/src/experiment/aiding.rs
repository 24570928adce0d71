//! How each measurement kind updates the engine from a sensor sample.

use kestrel_core::adapter::{NoiseAdapter, PriorAdapter};
use kestrel_core::form::{Form, PredictForm, UpdateForm};
use kestrel_core::FilterError;
use nalgebra::Vector3;

use super::data::SensorSample;
use super::record::{Adaptation, Describe};
use crate::engine::{ErrorSystem, LooselyCoupled};
use crate::measurement::{
    AttitudeFix, ErrorMeasurement, GnssAntenna, GnssFix, Odometer, OdometerReading,
};
use crate::odometer::{FuzzyOdometer, MaxThreshold};

/// The aiding of one measurement kind: updates the engine with the
/// readings of a sample (after its IMU increment), `None` if it holds none.
pub(crate) trait Aiding<const N: usize, S, F, A> {
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError>;
}

/// The filter's `R` for GNSS (position and velocity σ, NED).
#[derive(Clone, Copy, Debug)]
pub(crate) struct GnssNoise {
    pub pos: Vector3<f64>,
    pub vel: Vector3<f64>,
}

impl GnssNoise {
    fn apply(&self, fix: &GnssFix) -> GnssFix {
        fix.with_std(self.pos, self.vel)
    }
}

/// GNSS position and velocity (m = 6).
pub(crate) struct GnssPositionVelocity {
    pub antenna: GnssAntenna,
    pub noise: GnssNoise,
}

impl<const N: usize, S, F, A> Aiding<N, S, F, A> for GnssPositionVelocity
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process>,
    F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 6>, 6>,
    A: PriorAdapter<f64> + NoiseAdapter<f64, 6>,
    A::Report: Describe,
{
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError> {
        let Some(fix) = sample.gnss.as_ref().map(|g| self.noise.apply(&g.value)) else {
            return Ok(None);
        };
        if fix.vel.is_none() {
            return Ok(None);
        }
        let ins = engine.ins_context(fix.time);
        let m = self.antenna.position_velocity(engine.system(), &ins, &fix);
        Ok(Some(Adaptation::from_report(&engine.apply(&m)?)))
    }
}

/// Attitude, velocity and position (m = 9, paper 004), when the attitude
/// reference and a GNSS fix with velocity arrive at the same sample.
pub(crate) struct AttitudeVelocityPosition {
    pub antenna: GnssAntenna,
    pub noise: GnssNoise,
    pub attitude_std: Vector3<f64>,
}

impl<const N: usize, S, F, A> Aiding<N, S, F, A> for AttitudeVelocityPosition
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process>,
    F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 9>, 9>,
    A: PriorAdapter<f64> + NoiseAdapter<f64, 9>,
    A::Report: Describe,
{
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError> {
        let (Some(g), Some(att)) = (&sample.gnss, &sample.attitude) else {
            return Ok(None);
        };
        let fix = self.noise.apply(&g.value);
        if fix.vel.is_none() {
            return Ok(None);
        }
        let att = AttitudeFix::new(att.time, att.att, self.attitude_std);
        let ins = engine.ins_context(fix.time);
        let m = self
            .antenna
            .attitude_velocity_position(engine.system(), &ins, &att, &fix);
        Ok(Some(Adaptation::from_report(&engine.apply(&m)?)))
    }
}

/// How odometer updates are processed (paper 003): a type per method, so
/// the loop is monomorphised for it.
pub(crate) trait OdometerProcessing {
    fn apply<const N: usize, S, F, A>(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        m: &ErrorMeasurement<f64, N, 3>,
        reading: &OdometerReading,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
        A: PriorAdapter<f64>;
}

/// Every reading used as it is.
pub(crate) struct Unprocessed;

impl OdometerProcessing for Unprocessed {
    fn apply<const N: usize, S, F, A>(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        m: &ErrorMeasurement<f64, N, 3>,
        _: &OdometerReading,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
        A: PriorAdapter<f64>,
    {
        Ok(Adaptation::from_report(&engine.apply_with(m, &mut ())?))
    }
}

impl OdometerProcessing for MaxThreshold<f64> {
    fn apply<const N: usize, S, F, A>(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        m: &ErrorMeasurement<f64, N, 3>,
        _: &OdometerReading,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
        A: PriorAdapter<f64>,
    {
        Ok(Adaptation::from_report(&engine.apply_with(m, self)?))
    }
}

impl<const W: usize> OdometerProcessing for FuzzyOdometer<f64, W> {
    fn apply<const N: usize, S, F, A>(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        m: &ErrorMeasurement<f64, N, 3>,
        reading: &OdometerReading,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
        A: PriorAdapter<f64>,
    {
        let scale = engine.corrections().odometer_scale;
        let adapter = self.prepare(&engine.ins_context(reading.time), reading, scale);
        Ok(Adaptation::from_report(&engine.apply_with(m, adapter)?))
    }
}

/// Odometer speed plus non-holonomic constraints (m = 3), processed by `P`.
pub(crate) struct OdometerAiding<P> {
    pub odometer: Odometer,
    pub processing: P,
}

impl<const N: usize, P, S, F, A> Aiding<N, S, F, A> for OdometerAiding<P>
where
    P: OdometerProcessing,
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process>,
    F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
    A: PriorAdapter<f64>,
{
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError> {
        let Some(reading) = sample.odometer.map(|r| r.value) else {
            return Ok(None);
        };
        let m = engine.odometer_measurement(&self.odometer, &reading);
        self.processing.apply(engine, &m, &reading).map(Some)
    }
}
