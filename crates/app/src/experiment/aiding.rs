//! How each measurement kind updates the engine: the steps the in-memory
//! runner applies to simulated samples and a file-driven loop applies to
//! recorded fixes and readings, so both compute the same update.

use kestrel::adapter::{NoiseAdapter, PriorAdapter};
use kestrel::adaptive::WindowedNoise;
use kestrel::form::{Form, PredictForm, UpdateForm};
use kestrel::nalgebra::Vector3;
use kestrel::FilterError;

use super::data::SensorSample;
use super::record::{Adaptation, Describe};
use kestrel::nav::engine::{ErrorSystem, LooselyCoupled};
use kestrel::nav::measurement::{
    AttitudeFix, ErrorMeasurement, GnssAntenna, GnssFix, InsContext, Odometer, OdometerReading,
};
use kestrel::nav::odometer::{FuzzyAdapter, FuzzyOdometer, MaxThreshold};

/// The aiding of one measurement kind: updates the engine with the
/// readings of a sample (after its IMU increment), `None` if it holds none.
pub(crate) trait Aiding<const N: usize, S, F, A> {
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError>;
}

/// A loosely coupled engine of `N` error states that updates with `M`-row
/// error measurements: what an aiding step needs of it. Implemented by
/// every [`LooselyCoupled`] engine whose filter and adapter take `M` rows.
pub trait AidedEngine<const N: usize, const M: usize> {
    /// The error system (its layout builds the measurements).
    type System: ErrorSystem<N>;
    /// The error system and the INS solution at `time`.
    fn context(&self, time: f64) -> (&Self::System, InsContext);
    /// The odometer scale-factor correction the engine applies.
    fn odometer_scale(&self) -> f64;
    /// Updates through the filter's adapter and feeds the estimate back.
    ///
    /// # Errors
    /// The filter's update error.
    fn update(&mut self, m: &ErrorMeasurement<f64, N, M>) -> Result<Adaptation, FilterError>;
    /// As [`update`](Self::update) through `adapter` instead.
    ///
    /// # Errors
    /// The filter's update error.
    fn update_with<B: NoiseAdapter<f64, M, Report: Describe>>(
        &mut self,
        m: &ErrorMeasurement<f64, N, M>,
        adapter: &mut B,
    ) -> Result<Adaptation, FilterError>;
}

impl<const N: usize, const M: usize, S, F, A> AidedEngine<N, M> for LooselyCoupled<f64, N, S, F, A>
where
    S: ErrorSystem<N>,
    F: Form<f64, N> + PredictForm<f64, N, S::Process>,
    F: UpdateForm<f64, N, ErrorMeasurement<f64, N, M>, M>,
    A: PriorAdapter<f64> + NoiseAdapter<f64, M>,
    A::Report: Describe,
{
    type System = S;

    fn context(&self, time: f64) -> (&S, InsContext) {
        (self.system(), self.ins_context(time))
    }

    fn odometer_scale(&self) -> f64 {
        self.corrections().odometer_scale
    }

    fn update(&mut self, m: &ErrorMeasurement<f64, N, M>) -> Result<Adaptation, FilterError> {
        Ok(Adaptation::from_update(&self.apply_detailed(m)?))
    }

    fn update_with<B: NoiseAdapter<f64, M, Report: Describe>>(
        &mut self,
        m: &ErrorMeasurement<f64, N, M>,
        adapter: &mut B,
    ) -> Result<Adaptation, FilterError> {
        Ok(Adaptation::from_update(
            &self.apply_detailed_with(m, adapter)?,
        ))
    }
}

/// The filter's GNSS `R`.
///
/// ```
/// use kestrel_app::experiment::GnssNoise;
/// use kestrel::nav::measurement::GnssFix;
/// use kestrel::nav::{nalgebra::Vector3, Geodetic};
/// let fix = GnssFix::position_only(1.0, Geodetic::from_degrees(30.0, 114.0, 0.0))
///     .with_std(Vector3::repeat(5.0), Vector3::repeat(0.5));
/// let fixed = GnssNoise::Fixed { position: Vector3::repeat(2.0), velocity: Vector3::repeat(0.1) };
/// assert_eq!(fixed.apply(&fix).pos_std, Vector3::repeat(2.0));
/// assert_eq!(GnssNoise::Reported.apply(&fix).pos_std, Vector3::repeat(5.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GnssNoise {
    /// The σ each fix reports.
    Reported,
    /// Fixed σ, NED.
    Fixed {
        /// Position σ, m.
        position: Vector3<f64>,
        /// Velocity σ, m/s.
        velocity: Vector3<f64>,
    },
}

impl GnssNoise {
    /// The fix with the σ the filter uses.
    pub fn apply(&self, fix: &GnssFix) -> GnssFix {
        match *self {
            Self::Reported => *fix,
            Self::Fixed { position, velocity } => fix.with_std(position, velocity),
        }
    }
}

/// GNSS updates: the antenna and the filter's `R`. One method per
/// measurement (position and velocity, position only, or with an attitude
/// reference), each generic over the engine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GnssAiding {
    /// The antenna the fixes refer to.
    pub antenna: GnssAntenna,
    /// The `R` of the fixes.
    pub noise: GnssNoise,
}

impl GnssAiding {
    /// Updates `engine` with the rows `measure` forms from the antenna,
    /// the error system, the INS solution at the fix time and the fix with
    /// the filter's σ: [`GnssAntenna::position_velocity`] (m = 6),
    /// [`GnssAntenna::position`] (m = 3) or, with an attitude reference,
    /// [`GnssAntenna::attitude_velocity_position`] (m = 9).
    ///
    /// # Errors
    /// The filter's update error.
    ///
    /// ```
    /// # use kestrel::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel::nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel::nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel::nav::measurement::{GnssAntenna, GnssFix};
    /// use kestrel_app::experiment::{GnssAiding, GnssNoise};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// engine.imu(&ImuIncrement::from_rates(0.01, 0.01, earth.earth_rate_ned(start.pos.lat),
    ///     Vector3::new(0.0, 0.0, -g))).unwrap();
    /// let gnss = GnssAiding { antenna: GnssAntenna::new(Vector3::zeros()), noise: GnssNoise::Reported };
    /// let fix = GnssFix::new(0.01, start.pos, Vector3::new(0.1, 0.0, 0.0));
    /// let a = gnss.update(&mut engine, &fix, |a, s, ins, f| a.position_velocity(s, ins, f)).unwrap();
    /// assert!(!a.rejected && a.nis > 0.0);
    /// assert!(engine.solution().vel.x > 0.0); // fed back
    /// ```
    pub fn update<const N: usize, const M: usize, E: AidedEngine<N, M>>(
        &self,
        engine: &mut E,
        fix: &GnssFix,
        measure: impl FnOnce(
            &GnssAntenna,
            &E::System,
            &InsContext,
            &GnssFix,
        ) -> ErrorMeasurement<f64, N, M>,
    ) -> Result<Adaptation, FilterError> {
        let fix = self.noise.apply(fix);
        let (system, ins) = engine.context(fix.time);
        let m = measure(&self.antenna, system, &ins, &fix);
        engine.update(&m)
    }
}

/// GNSS position and velocity (m = 6) from the samples.
pub(crate) struct GnssPositionVelocity(pub GnssAiding);

impl<const N: usize, S, F, A> Aiding<N, S, F, A> for GnssPositionVelocity
where
    LooselyCoupled<f64, N, S, F, A>: AidedEngine<N, 6>,
{
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError> {
        match &sample.gnss {
            Some(g) if g.value.vel.is_some() => self
                .0
                .update(engine, &g.value, |a, system, ins, fix| {
                    a.position_velocity(system, ins, fix)
                })
                .map(Some),
            _ => Ok(None),
        }
    }
}

/// Attitude, velocity and position (m = 9, paper 004), when the attitude
/// reference and a GNSS fix with velocity arrive at the same sample.
pub(crate) struct AttitudeVelocityPosition {
    pub gnss: GnssAiding,
    pub attitude_std: Vector3<f64>,
}

impl<const N: usize, S, F, A> Aiding<N, S, F, A> for AttitudeVelocityPosition
where
    LooselyCoupled<f64, N, S, F, A>: AidedEngine<N, 9>,
{
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError> {
        let (Some(g), Some(att)) = (&sample.gnss, &sample.attitude) else {
            return Ok(None);
        };
        if g.value.vel.is_none() {
            return Ok(None);
        }
        let att = AttitudeFix::new(att.time, att.att, self.attitude_std);
        self.gnss
            .update(engine, &g.value, |a, system, ins, fix| {
                a.attitude_velocity_position(system, ins, &att, fix)
            })
            .map(Some)
    }
}

/// How odometer updates are processed (paper 003): a type per method, so
/// the loop is monomorphised for it. `()` uses every reading as it is.
pub trait OdometerProcessing {
    /// The adapter of the odometer updates.
    type Adapter: NoiseAdapter<f64, 3, Report: Describe>;
    /// The adapter, readied for `reading` (`ins`: the INS solution at its
    /// time, `scale`: the engine's odometer scale correction).
    fn adapter(
        &mut self,
        ins: &InsContext,
        reading: &OdometerReading,
        scale: f64,
    ) -> &mut Self::Adapter;
}

impl OdometerProcessing for () {
    type Adapter = ();
    fn adapter(&mut self, _: &InsContext, _: &OdometerReading, _: f64) -> &mut () {
        self
    }
}

impl OdometerProcessing for MaxThreshold<f64> {
    type Adapter = Self;
    fn adapter(&mut self, _: &InsContext, _: &OdometerReading, _: f64) -> &mut Self {
        self
    }
}

// The max-threshold baseline with windowed R: both are plain adapters.
impl<const W: usize> OdometerProcessing for (MaxThreshold<f64>, WindowedNoise<f64, 3, W>) {
    type Adapter = Self;
    fn adapter(&mut self, _: &InsContext, _: &OdometerReading, _: f64) -> &mut Self {
        self
    }
}

impl<const W: usize> OdometerProcessing for FuzzyOdometer<f64, W> {
    type Adapter = FuzzyAdapter<f64, W>;
    fn adapter(
        &mut self,
        ins: &InsContext,
        reading: &OdometerReading,
        scale: f64,
    ) -> &mut Self::Adapter {
        self.prepare(ins, reading, scale)
    }
}

/// Odometer speed plus non-holonomic constraints (m = 3), processed by `P`.
pub struct OdometerAiding<P> {
    /// The odometer model (σ and mounting).
    pub odometer: Odometer,
    /// The processing of each update.
    pub processing: P,
}

impl<P: OdometerProcessing> OdometerAiding<P> {
    /// Updates `engine` with `reading`.
    ///
    /// # Errors
    /// The filter's update error.
    pub fn update<const N: usize>(
        &mut self,
        engine: &mut impl AidedEngine<N, 3>,
        reading: &OdometerReading,
    ) -> Result<Adaptation, FilterError> {
        let scale = engine.odometer_scale();
        let (system, ins) = engine.context(reading.time);
        let m = self.odometer.forward_nhc(system, &ins, reading, scale);
        let adapter = self.processing.adapter(&ins, reading, scale);
        engine.update_with(&m, adapter)
    }
}

impl<const N: usize, P, S, F, A> Aiding<N, S, F, A> for OdometerAiding<P>
where
    P: OdometerProcessing,
    LooselyCoupled<f64, N, S, F, A>: AidedEngine<N, 3>,
{
    fn update(
        &mut self,
        engine: &mut LooselyCoupled<f64, N, S, F, A>,
        sample: &SensorSample,
    ) -> Result<Option<Adaptation>, FilterError> {
        match sample.odometer {
            Some(r) => OdometerAiding::update(self, engine, &r.value).map(Some),
            None => Ok(None),
        }
    }
}
