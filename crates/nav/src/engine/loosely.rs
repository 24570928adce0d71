//! The loosely coupled engine: mechanisation at IMU rate, the error-state
//! filter at the aiding epochs, closed-loop feedback.

use kestrel_core::adapter::{NoiseAdapter, PriorAdapter};
use kestrel_core::form::{Form, PredictForm, UpdateForm};
use kestrel_core::{
    real::lit, Filter, FilterError, LinearizedProcess, Real, UpdateDetail, UpdateReport,
};
use nalgebra::{SMatrix, SVector, Vector3};

use super::feedback::{feed_back, SensorCorrections};
use super::record::{ForwardEpoch, Recording};
use super::system::ErrorSystem;
use crate::error_model::ForcingMean;
use crate::imu::ImuIncrement;
use crate::measurement::{
    ErrorMeasurement, GnssAntenna, GnssFix, InsContext, Odometer, OdometerReading,
};
use crate::mechanisation::Strapdown;
use crate::state::NavState;

/// A loosely coupled INS / aiding engine over an error-state filter.
///
/// - [`imu`](Self::imu) corrects each increment with the fed-back bias
///   estimates and runs the mechanisation; the error covariance is
///   propagated once per `covariance_interval` seconds of IMU data with a
///   model linearised at the current solution and the interval's mean
///   specific force ([`ForcingMean`]) — and always up to the last IMU sample
///   before an update.
/// - [`apply`](Self::apply) (and [`gnss`](Self::gnss), …) update the
///   filter with an [`ErrorMeasurement`] built from
///   [`ins_context`](Self::ins_context), feed the estimate back into the
///   navigation solution and the sensor corrections, and reset the error
///   state to zero.
/// - Epoch alignment: an aiding epoch at `t` is processed at the last IMU
///   sample `t_k ≤ t`; the INS solution is extrapolated over `t − t_k`
///   (less than one IMU period) to build the measurement, and the error
///   state is taken at `t_k`.
///
/// Generic over the filter: any form with the predict / update bounds of
/// the methods (covariance, UKF, SR-UKF) and any adapter tuple. Between
/// aiding epochs nothing is updated: the INS coasts and the covariance grows.
///
/// ```
/// use kestrel_core::{Ekf, nalgebra::{SMatrix, SVector, Vector3}};
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
/// use kestrel_nav::engine::{InitialUncertainty, Ins15, LooselyCoupled, ErrorSystem};
/// use kestrel_nav::measurement::{GnssAntenna, GnssFix};
///
/// let earth = Ellipsoid::wgs84();
/// let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
///     Euler::default());
/// let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
/// let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
/// let filter = Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap();
/// let mut engine = LooselyCoupled::new(Strapdown::new(earth, start), filter, system,
///     GnssAntenna::new(Vector3::zeros()), 0.1);
/// // Stationary for 1 s at 100 Hz, then a GNSS fix at the true position.
/// let g = earth.gravity(start.pos.lat, 0.0);
/// for k in 1..=100 {
///     let rate = earth.earth_rate_ned(start.pos.lat);
///     engine.imu(&ImuIncrement::from_rates(k as f64 * 0.01, 0.01, rate,
///         Vector3::new(0.0, 0.0, -g))).unwrap();
/// }
/// let report = engine.gnss(&GnssFix::new(1.0, start.pos, Vector3::zeros())).unwrap();
/// assert!(report.nis < 1.0);
/// assert_eq!(engine.filter().state(), &SVector::<f64, 15>::zeros());
/// ```
#[derive(Debug, Clone)]
pub struct LooselyCoupled<T: Real, const N: usize, S, F, A = ()> {
    ins: Strapdown,
    filter: Filter<T, N, F, A>,
    system: S,
    antenna: GnssAntenna,
    corrections: SensorCorrections,
    forcing: ForcingMean,
    interval: f64,
    omega_ib: Vector3<f64>,
    accel_ned: Vector3<f64>,
    last_dt: f64,
    recording: Option<Recording<S, T, N>>,
}

impl<T, const N: usize, S, F, A> LooselyCoupled<T, N, S, F, A>
where
    T: Real,
    S: ErrorSystem<N>,
    F: Form<T, N> + PredictForm<T, N, S::Process>,
    A: PriorAdapter<T>,
{
    /// An engine from the mechanisation (holding the initial solution), an
    /// error-state filter (its state should be zero), the error system, the
    /// GNSS antenna and the covariance propagation interval in seconds
    /// (`0` propagates at every IMU sample, `f64::INFINITY` only at
    /// aiding epochs).
    pub fn new(
        ins: Strapdown,
        filter: Filter<T, N, F, A>,
        system: S,
        antenna: GnssAntenna,
        covariance_interval: f64,
    ) -> Self {
        const {
            assert!(
                crate::measurement::layout_fits::<N, S>(),
                "error layout does not fit the state"
            )
        };
        Self {
            ins,
            filter,
            system,
            antenna,
            corrections: SensorCorrections::default(),
            forcing: ForcingMean::default(),
            interval: covariance_interval,
            omega_ib: Vector3::zeros(),
            accel_ned: Vector3::zeros(),
            last_dt: 0.0,
            recording: None,
        }
    }

    /// The same engine starting from sensor corrections `corrections`
    /// (e.g. calibrated biases or a known odometer scale).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// use kestrel_nav::engine::SensorCorrections;
    /// let c = SensorCorrections { odometer_scale: 0.01, ..Default::default() };
    /// let engine = engine.with_corrections(c);
    /// assert_eq!(engine.corrections().odometer_scale, 0.01);
    /// ```
    pub fn with_corrections(mut self, corrections: SensorCorrections) -> Self {
        self.corrections = corrections;
        self
    }

    /// Processes one raw IMU increment: bias correction, mechanisation and,
    /// when the propagation interval is complete, the covariance prediction.
    ///
    /// # Errors
    /// A failed covariance prediction (non-finite model); the navigation
    /// solution has advanced, the covariance has not (it is retried with
    /// the longer interval at the next sample).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// for k in 1..=25 {
    ///     engine.imu(&still(k)).unwrap();
    /// }
    /// // Two covariance propagations of 0.1 s done, 0.05 s pending.
    /// assert!((engine.pending_interval() - 0.05).abs() < 1e-9);
    /// assert!((engine.solution().time - 0.25).abs() < 1e-12);
    /// ```
    pub fn imu(&mut self, raw: &ImuIncrement) -> Result<(), FilterError> {
        let inc = self.corrections.imu.compensate(raw);
        let v0 = self.ins.state().vel;
        self.ins.step(&inc);
        if inc.dt > 0.0 {
            self.last_dt = inc.dt;
            self.omega_ib = inc.dtheta / inc.dt;
            self.accel_ned = (self.ins.state().vel - v0) / inc.dt;
        }
        self.forcing.add(&self.ins, inc.dt);
        // The tolerance absorbs the rounding of summed sample intervals
        // (ten 0.01 s add up to 0.09999…).
        if self.forcing.dt() >= self.interval - 1e-9 {
            self.propagate_covariance()?;
        }
        Ok(())
    }

    /// Propagates the covariance over the IMU data accumulated since the
    /// last propagation (nothing if there is none).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// let p0 = engine.covariance();
    /// for k in 1..=5 {
    ///     engine.imu(&still(k)).unwrap();
    /// }
    /// engine.propagate_covariance().unwrap();
    /// assert_eq!(engine.pending_interval(), 0.0);
    /// assert!(engine.covariance()[(0, 0)] > p0[(0, 0)]); // ARW
    /// ```
    pub fn propagate_covariance(&mut self) -> Result<(), FilterError> {
        if self.forcing.dt() > 0.0 {
            let model = self
                .system
                .process(self.ins.earth(), self.ins.state(), &self.forcing);
            let dt = lit(self.forcing.dt());
            let transition = self.recording.as_ref().map(|r| {
                (r.transition)(
                    &self.system,
                    self.ins.earth(),
                    self.ins.state(),
                    &self.forcing,
                    self.filter.state(),
                    dt,
                )
            });
            self.filter.predict(&model, dt)?;
            self.forcing.clear();
            if let (Some(r), Some(phi)) = (self.recording.as_mut(), transition) {
                let p = self.filter.covariance();
                r.open(ForwardEpoch::propagated(self.ins.state().time, phi, p));
            }
        }
        Ok(())
    }

    /// The INS side of a measurement at `time`: the current solution
    /// extrapolated from the last IMU sample to `time`, with the
    /// bias-corrected body rate of that sample.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// engine.imu(&still(1)).unwrap();
    /// let ctx = engine.ins_context(0.013);
    /// assert!((ctx.state.time - 0.013).abs() < 1e-12);
    /// ```
    pub fn ins_context(&self, time: f64) -> InsContext {
        let here = InsContext::new(*self.ins.earth(), *self.ins.state(), self.omega_ib);
        here.extrapolated(time - self.ins.state().time, &self.accel_ned)
    }

    /// Updates with `model` (`z = model.z()`) through the filter's adapter,
    /// then feeds the estimate back and resets the error state.
    ///
    /// # Errors
    /// The filter's update error; the engine is then unchanged except for
    /// the covariance propagated up to the current IMU sample.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// engine.imu(&still(1)).unwrap();
    /// let fix = GnssFix::new(0.01, start.pos, Vector3::new(0.1, 0.0, 0.0));
    /// let m = engine.antenna().position_velocity(engine.system(), &engine.ins_context(0.01), &fix);
    /// let report = engine.apply(&m).unwrap();
    /// assert!(report.innovation[3] < 0.0); // INS slower than the fix
    /// assert!(engine.solution().vel.x > 0.0); // fed back
    /// ```
    pub fn apply<const M: usize>(
        &mut self,
        model: &ErrorMeasurement<T, N, M>,
    ) -> Result<UpdateReport<T, M, A::Report>, FilterError>
    where
        F: UpdateForm<T, N, ErrorMeasurement<T, N, M>, M>,
        A: NoiseAdapter<T, M>,
    {
        self.aided(|f| f.update(model, &model.z()))
    }

    /// As [`apply`](Self::apply), with the update's innovation covariances
    /// and noise ([`UpdateDetail`]).
    pub fn apply_detailed<const M: usize>(
        &mut self,
        model: &ErrorMeasurement<T, N, M>,
    ) -> Result<UpdateDetail<T, M, A::Report>, FilterError>
    where
        F: UpdateForm<T, N, ErrorMeasurement<T, N, M>, M>,
        A: NoiseAdapter<T, M>,
    {
        self.aided(|f| f.update_detailed(model, &model.z()))
    }

    /// As [`apply`](Self::apply) with `adapter` instead of the filter's own
    /// (a second sensor with its own adaptive scheme; `&mut ()` for none).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// use kestrel_nav::odometer::MaxThreshold;
    /// engine.imu(&still(1)).unwrap();
    /// let fix = GnssFix::new(0.01, start.pos, Vector3::new(5.0, 0.0, 0.0));
    /// let m = engine.antenna().position_velocity(engine.system(), &engine.ins_context(0.01), &fix);
    /// // A 5 m/s disagreement is isolated by a 1 m/s threshold.
    /// let report = engine.apply_with(&m, &mut MaxThreshold::new(1.0)).unwrap();
    /// assert!(report.rejected && engine.solution().vel.x.abs() < 1e-9);
    /// ```
    pub fn apply_with<B, const M: usize>(
        &mut self,
        model: &ErrorMeasurement<T, N, M>,
        adapter: &mut B,
    ) -> Result<UpdateReport<T, M, B::Report>, FilterError>
    where
        F: UpdateForm<T, N, ErrorMeasurement<T, N, M>, M>,
        B: NoiseAdapter<T, M>,
    {
        self.aided(|f| f.update_with(model, &model.z(), adapter))
    }

    /// As [`apply_with`](Self::apply_with), with the update's innovation
    /// covariances and noise ([`UpdateDetail`]).
    pub fn apply_detailed_with<B, const M: usize>(
        &mut self,
        model: &ErrorMeasurement<T, N, M>,
        adapter: &mut B,
    ) -> Result<UpdateDetail<T, M, B::Report>, FilterError>
    where
        F: UpdateForm<T, N, ErrorMeasurement<T, N, M>, M>,
        B: NoiseAdapter<T, M>,
    {
        self.aided(|f| f.update_detailed_with(model, &model.z(), adapter))
    }

    /// An aiding update: the pending covariance propagation, `update` on
    /// the filter, then the feedback of the estimate.
    fn aided<O>(
        &mut self,
        update: impl FnOnce(&mut Filter<T, N, F, A>) -> Result<O, FilterError>,
    ) -> Result<O, FilterError> {
        self.propagate_covariance()?;
        let outcome = update(&mut self.filter)?;
        self.close_loop()?;
        self.note_update();
        Ok(outcome)
    }

    /// A GNSS position and velocity update at the fix's time (m = 6). A fix
    /// without velocity is refused with
    /// [`FilterError::InvalidParameter`] (use
    /// [`gnss_position`](Self::gnss_position) for it).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// for k in 1..=100 {
    ///     engine.imu(&still(k)).unwrap();
    /// }
    /// let report = engine.gnss(&GnssFix::new(1.0, start.pos, Vector3::zeros())).unwrap();
    /// assert!(report.nis < 1.0);
    /// assert!(engine.gnss(&GnssFix::position_only(1.0, start.pos)).is_err());
    /// ```
    pub fn gnss(&mut self, fix: &GnssFix) -> Result<UpdateReport<T, 6, A::Report>, FilterError>
    where
        F: UpdateForm<T, N, ErrorMeasurement<T, N, 6>, 6>,
        A: NoiseAdapter<T, 6>,
    {
        if fix.vel.is_none() {
            return Err(FilterError::InvalidParameter {
                name: "GNSS fix velocity",
                valid: "present for a position-velocity update",
            });
        }
        let ins = self.ins_context(fix.time);
        let m = self.antenna.position_velocity(&self.system, &ins, fix);
        self.apply(&m)
    }

    /// A GNSS position-only update at the fix's time (m = 3).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// engine.imu(&still(1)).unwrap();
    /// let fix = GnssFix::new(0.01, earth.displace(&start.pos, &Vector3::new(0.0, 2.0, 0.0)),
    ///     Vector3::zeros());
    /// let report = engine.gnss_position(&fix).unwrap();
    /// assert!((report.innovation[1] + 2.0).abs() < 1e-6);
    /// ```
    pub fn gnss_position(
        &mut self,
        fix: &GnssFix,
    ) -> Result<UpdateReport<T, 3, A::Report>, FilterError>
    where
        F: UpdateForm<T, N, ErrorMeasurement<T, N, 3>, 3>,
        A: NoiseAdapter<T, 3>,
    {
        let ins = self.ins_context(fix.time);
        let m = self.antenna.position(&self.system, &ins, fix);
        self.apply(&m)
    }

    /// The odometer speed and non-holonomic constraint measurement (m = 3)
    /// at the reading's time, with the current scale-factor estimate; apply
    /// it with [`apply`](Self::apply) or [`apply_with`](Self::apply_with)
    /// (or inspect it first, e.g. for a fault detector).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// use kestrel_nav::measurement::{Odometer, OdometerReading};
    /// engine.imu(&still(1)).unwrap();
    /// let m = engine.odometer_measurement(&Odometer::new(0.05, 0.1), &OdometerReading::new(0.01, 0.2));
    /// assert!((m.z()[0] + 0.2).abs() < 1e-6); // standing still, the wheel says 0.2 m/s
    /// ```
    pub fn odometer_measurement(
        &self,
        odometer: &Odometer,
        reading: &OdometerReading,
    ) -> ErrorMeasurement<T, N, 3> {
        let ins = self.ins_context(reading.time);
        odometer.forward_nhc(&self.system, &ins, reading, self.corrections.odometer_scale)
    }

    /// The epoch record after an update: the posterior covariance.
    fn note_update(&mut self) {
        if let Some(r) = self.recording.as_mut() {
            r.open.posterior_covariance = self.filter.covariance();
        }
    }

    /// The covariance epoch closed by the last propagation, once (with
    /// [`record_epochs`](Self::record_epochs)). Take it after every call
    /// that may propagate ([`imu`](Self::imu), the updates): an epoch
    /// closed before the previous one was taken is counted by
    /// [`recording_overrun`](Self::recording_overrun).
    pub fn take_epoch(&mut self) -> Option<ForwardEpoch<T, N>> {
        self.recording.as_mut().and_then(|r| r.closed.take())
    }

    /// Ends the recording and returns the last epoch, still open (the
    /// epochs closed before it are [`take_epoch`](Self::take_epoch)'s).
    pub fn finish_epochs(&mut self) -> Option<ForwardEpoch<T, N>> {
        self.recording.take().map(|r| r.open)
    }

    /// Epochs lost because the one before was not taken in time (zero
    /// when the caller takes after every call).
    pub fn recording_overrun(&self) -> usize {
        self.recording.as_ref().map_or(0, |r| r.overrun)
    }

    /// Feeds the error-state estimate back and resets it to zero.
    fn close_loop(&mut self) -> Result<(), FilterError> {
        let dx = *self.filter.state();
        if dx.iter().all(|v| *v == T::zero()) {
            return Ok(());
        }
        if let Some(r) = self.recording.as_mut() {
            r.open.feedback += dx;
        }
        let earth = *self.ins.earth();
        feed_back::<T, N, S>(&dx, &earth, self.ins.state_mut(), &mut self.corrections);
        self.filter.set_state(SVector::zeros())
    }

    /// The navigation solution (at the last IMU sample).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.solution().pos, start.pos);
    /// ```
    pub fn solution(&self) -> &NavState {
        self.ins.state()
    }

    /// The error-state covariance (including process noise pending an
    /// update).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.covariance()[(6, 6)], 1.0);
    /// ```
    pub fn covariance(&self) -> SMatrix<T, N, N> {
        self.filter.covariance()
    }

    /// The standard deviations of the error state, `√diag(P)`.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.std_devs()[3], 0.1);
    /// ```
    pub fn std_devs(&self) -> SVector<T, N> {
        self.filter
            .covariance()
            .diagonal()
            .map(|v| v.max(T::zero()).sqrt())
    }

    /// The accumulated sensor-error estimates.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.corrections().imu.gyro, Vector3::zeros());
    /// ```
    pub fn corrections(&self) -> &SensorCorrections {
        &self.corrections
    }

    /// The error system (its layout builds measurements).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.system().spec.gyro_bias, 0.0);
    /// ```
    pub fn system(&self) -> &S {
        &self.system
    }

    /// The GNSS antenna.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.antenna().lever_arm, Vector3::zeros());
    /// ```
    pub fn antenna(&self) -> &GnssAntenna {
        &self.antenna
    }

    /// The error-state filter.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.filter().state(), &SVector::<f64, 15>::zeros());
    /// ```
    pub fn filter(&self) -> &Filter<T, N, F, A> {
        &self.filter
    }

    /// Mutable access to the filter (adapter configuration, covariance reset).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// let p = engine.covariance() * 2.0;
    /// engine.filter_mut().set_covariance(&p).unwrap();
    /// assert_eq!(engine.covariance()[(6, 6)], 2.0);
    /// ```
    pub fn filter_mut(&mut self) -> &mut Filter<T, N, F, A> {
        &mut self.filter
    }

    /// The mechanisation.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// assert_eq!(engine.ins().earth(), &earth);
    /// ```
    pub fn ins(&self) -> &Strapdown {
        &self.ins
    }

    /// The interval of the last IMU increment, s (0 before the first).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// engine.imu(&still(1)).unwrap();
    /// assert_eq!(engine.last_dt(), 0.01);
    /// ```
    pub fn last_dt(&self) -> f64 {
        self.last_dt
    }

    /// The seconds of IMU data not yet propagated into the covariance.
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// engine.imu(&still(1)).unwrap();
    /// assert_eq!(engine.pending_interval(), 0.01);
    /// ```
    pub fn pending_interval(&self) -> f64 {
        self.forcing.dt()
    }
}

impl<T, const N: usize, S, F, A> LooselyCoupled<T, N, S, F, A>
where
    T: Real,
    S: ErrorSystem<N>,
    S::Process: LinearizedProcess<T, N>,
    F: Form<T, N> + PredictForm<T, N, S::Process>,
    A: PriorAdapter<T>,
{
    /// Starts recording the forward pass for a smoother: from now on every
    /// covariance propagation opens a [`ForwardEpoch`] (with `Φ` of the
    /// same process model, evaluated where the filter evaluates it) and the
    /// updates and feedback at that sample complete it. The first epoch is
    /// the current solution and covariance. Call it before the first IMU
    /// sample; the error state must be zero (it is, between updates).
    ///
    /// ```
    /// # use kestrel_core::{Ekf, nalgebra::{SVector, Vector3}};
    /// # use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuIncrement, ImuSpec, NavState, Strapdown};
    /// # use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, Ins15, LooselyCoupled};
    /// # use kestrel_nav::measurement::{GnssAntenna, GnssFix};
    /// # let earth = Ellipsoid::wgs84();
    /// # let start = NavState::new(0.0, Geodetic::from_degrees(30.0, 114.0, 0.0), Vector3::zeros(),
    /// #     Euler::default());
    /// # let system = Ins15::new(ImuSpec::perfect().with_gyro_arw_deg_per_sqrt_h(0.1));
    /// # let p0 = system.initial_covariance(&InitialUncertainty::new(0.01, 0.1, 1.0));
    /// # let mut engine = LooselyCoupled::new(Strapdown::new(earth, start),
    /// #     Ekf::<f64, 15>::new(SVector::zeros(), p0).unwrap(), system,
    /// #     GnssAntenna::new(Vector3::zeros()), 0.1);
    /// # let g = earth.gravity(start.pos.lat, 0.0);
    /// # let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
    /// #     earth.earth_rate_ned(start.pos.lat), Vector3::new(0.0, 0.0, -g));
    /// engine.record_epochs();
    /// let mut epochs = Vec::new();
    /// for k in 1..=20 {
    ///     engine.imu(&still(k)).unwrap();
    ///     epochs.extend(engine.take_epoch());
    /// }
    /// engine.gnss(&GnssFix::new(0.2, start.pos, Vector3::zeros())).unwrap();
    /// epochs.extend(engine.take_epoch());
    /// epochs.extend(engine.finish_epochs());
    /// // The initial epoch, and propagations at 0.1 s and 0.2 s (the fix's).
    /// assert_eq!(epochs.len(), 3);
    /// assert!((epochs[2].time - 0.2).abs() < 1e-12);
    /// assert!(epochs[2].posterior_covariance[(6, 6)] < epochs[2].prior_covariance[(6, 6)]);
    /// ```
    pub fn record_epochs(&mut self) {
        self.recording = Some(Recording {
            transition: |system, earth, nav, forcing, x, dt| {
                system.process(earth, nav, forcing).transition(x, dt)
            },
            open: ForwardEpoch::initial(self.ins.state().time, self.filter.covariance()),
            closed: None,
            overrun: 0,
        });
    }
}
