//! The measurement updates of a sample, in the same steps as the
//! experiment runner's (so recorded and simulated data agree exactly).

use kestrel::adapter::{NoiseAdapter, PriorAdapter};
use kestrel::form::{Form, PredictForm, UpdateForm};
use kestrel::nav::engine::{ErrorSystem, LooselyCoupled};
use kestrel::nav::experiment::Adaptation;
use kestrel::nav::measurement::{
    ErrorMeasurement, GnssAntenna, GnssFix, Odometer, OdometerReading,
};
use kestrel::nav::odometer::{FuzzyOdometer, MaxThreshold};
use kestrel::FilterError;

use super::config::GnssNoise;
use super::describe::{adaptation, Describe};

impl GnssNoise {
    /// The fix with the σ the filter uses.
    fn apply(&self, fix: &GnssFix) -> GnssFix {
        match *self {
            Self::File => *fix,
            Self::Fixed { position, velocity } => fix.with_std(position, velocity),
        }
    }
}

/// GNSS position and velocity updates (m = 6).
pub(crate) struct PositionVelocity {
    pub antenna: GnssAntenna,
    pub noise: GnssNoise,
}

impl PositionVelocity {
    pub(crate) fn update<const N: usize, S, F, A>(
        &self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 6>, 6>,
        A: PriorAdapter<f64> + NoiseAdapter<f64, 6>,
        A::Report: Describe,
    {
        let fix = self.noise.apply(fix);
        let ins = engine.ins_context(fix.time);
        let m = self.antenna.position_velocity(engine.system(), &ins, &fix);
        Ok(adaptation(&engine.apply(&m)?))
    }
}

/// GNSS position-only updates (m = 3).
pub(crate) struct PositionOnly {
    pub antenna: GnssAntenna,
    pub noise: GnssNoise,
}

impl PositionOnly {
    pub(crate) fn update<const N: usize, S, F, A>(
        &self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        fix: &GnssFix,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
        A: PriorAdapter<f64> + NoiseAdapter<f64, 3>,
        A::Report: Describe,
    {
        let fix = self.noise.apply(fix);
        let ins = engine.ins_context(fix.time);
        let m = self.antenna.position(engine.system(), &ins, &fix);
        Ok(adaptation(&engine.apply(&m)?))
    }
}

/// How odometer updates are processed.
pub(crate) trait Processing {
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

impl Processing for Unprocessed {
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
        Ok(adaptation(&engine.apply_with(m, &mut ())?))
    }
}

impl Processing for MaxThreshold<f64> {
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
        Ok(adaptation(&engine.apply_with(m, self)?))
    }
}

impl<const W: usize> Processing for FuzzyOdometer<f64, W> {
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
        Ok(adaptation(&engine.apply_with(m, adapter)?))
    }
}

/// Odometer speed plus non-holonomic constraints (m = 3), processed by `P`.
pub(crate) struct OdometerAid<P> {
    pub odometer: Odometer,
    pub processing: P,
}

impl<P: Processing> OdometerAid<P> {
    pub(crate) fn update<const N: usize, S, F, A>(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        reading: &OdometerReading,
    ) -> Result<Adaptation, FilterError>
    where
        S: ErrorSystem<N>,
        F: Form<f64, N> + PredictForm<f64, N, S::Process>,
        F: UpdateForm<f64, N, ErrorMeasurement<f64, N, 3>, 3>,
        A: PriorAdapter<f64>,
    {
        let m = engine.odometer_measurement(&self.odometer, reading);
        self.processing.apply(engine, &m, reading)
    }
}
