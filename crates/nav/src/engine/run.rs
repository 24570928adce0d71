//! Driving the engine from time-ordered sensor streams, one epoch at a time.

use kestrel_core::adapter::{NoiseAdapter, PriorAdapter};
use kestrel_core::form::{Form, PredictForm, UpdateForm};
use kestrel_core::{FilterError, Real, UpdateReport};
use nalgebra::{SMatrix, SVector};

use super::feedback::SensorCorrections;
use super::loosely::LooselyCoupled;
use super::system::ErrorSystem;
use crate::imu::ImuIncrement;
use crate::measurement::{ErrorMeasurement, GnssFix, OdometerReading};
use crate::state::NavState;

/// Something that happens at a time (s): an aiding reading.
///
/// ```
/// use kestrel_nav::engine::Timed;
/// let r = kestrel_nav::measurement::OdometerReading::new(2.5, 10.0);
/// assert_eq!(r.time(), 2.5);
/// ```
pub trait Timed {
    /// The time of validity, s.
    fn time(&self) -> f64;
}

impl Timed for GnssFix {
    fn time(&self) -> f64 {
        self.time
    }
}

impl Timed for OdometerReading {
    fn time(&self) -> f64 {
        self.time
    }
}

/// What the engine emits at an epoch: the navigation solution, the sensor
/// corrections, the error-state covariance and the update report (`None`
/// while coasting).
///
/// ```
/// use kestrel_nav::{Euler, Geodetic, NavState, nalgebra::{SMatrix, Vector3}};
/// use kestrel_nav::engine::{Epoch, SensorCorrections};
/// let nav = NavState::new(1.0, Geodetic::new(0.5, 2.0, 0.0), Vector3::zeros(), Euler::default());
/// let e: Epoch<f64, 15, ()> = Epoch { time: 1.0, nav, corrections: SensorCorrections::default(),
///     covariance: SMatrix::identity() * 4.0, report: None };
/// assert!(e.report.is_none());
/// assert_eq!(e.std()[14], 2.0);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Epoch<T: Real, const N: usize, R> {
    /// The epoch time (the aiding time, or the IMU time when coasting), s.
    pub time: f64,
    /// The navigation solution after the update (at the last IMU sample).
    pub nav: NavState,
    /// The sensor-error estimates after the update.
    pub corrections: SensorCorrections,
    /// The error-state covariance `P` after the update.
    pub covariance: SMatrix<T, N, N>,
    /// The update report, or `None` for a coasting epoch.
    pub report: Option<R>,
}

impl<T: Real, const N: usize, R> Epoch<T, N, R> {
    /// The error-state standard deviations `√diag(P)`.
    pub fn std(&self) -> SVector<T, N> {
        self.covariance.diagonal().map(|v| v.max(T::zero()).sqrt())
    }
}

impl<T, const N: usize, S, F, A> LooselyCoupled<T, N, S, F, A>
where
    T: Real,
    S: ErrorSystem<N>,
    F: Form<T, N> + PredictForm<T, N, S::Process>,
    A: PriorAdapter<T>,
{
    /// The current epoch output with `report`.
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
    /// let e = engine.epoch::<()>(0.0, None);
    /// assert_eq!(e.std()[6], 1.0);
    /// ```
    pub fn epoch<R>(&self, time: f64, report: Option<R>) -> Epoch<T, N, R> {
        Epoch {
            time,
            nav: *self.solution(),
            corrections: *self.corrections(),
            covariance: self.covariance(),
            report,
        }
    }

    /// Runs the IMU stream, calling `handle(engine, event)` for each event
    /// of the time-ordered `events` at the last IMU sample at or before it
    /// (see the epoch alignment of [`LooselyCoupled`]). Events before the
    /// first sample are handled at the initial solution, events within one
    /// IMU period after the last sample at the last sample; later ones are
    /// not handled. Nothing is stored.
    ///
    /// # Errors
    /// The first error of the IMU processing or of `handle`.
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
    /// use kestrel_nav::measurement::OdometerReading;
    /// let imu = (1..=100).map(still);
    /// let events = (1..=10).map(|k| OdometerReading::new(k as f64 * 0.1 + 0.005, 0.0));
    /// let mut seen = 0;
    /// engine.drive(imu, events, |e, r| {
    ///     // Handled at the sample before the reading.
    ///     assert!(r.time - e.solution().time < 0.01);
    ///     seen += 1;
    ///     Ok::<(), kestrel_core::FilterError>(())
    /// }).unwrap();
    /// assert_eq!(seen, 10);
    /// ```
    pub fn drive<I, J, H, X>(&mut self, imu: I, events: J, mut handle: H) -> Result<(), X>
    where
        I: IntoIterator<Item = ImuIncrement>,
        J: IntoIterator,
        J::Item: Timed,
        H: FnMut(&mut Self, J::Item) -> Result<(), X>,
        X: From<FilterError>,
    {
        let mut events = events.into_iter().peekable();
        for inc in imu {
            while let Some(e) = events.next_if(|e| e.time() < inc.time) {
                handle(self, e)?;
            }
            self.imu(&inc)?;
        }
        let end = self.solution().time + self.last_dt();
        for e in events {
            if e.time() > end {
                break;
            }
            handle(self, e)?;
        }
        Ok(())
    }

    /// INS/GNSS: runs the IMU stream with GNSS position and velocity updates
    /// at every fix (aligned as in [`drive`](Self::drive)), calling `on_epoch` after each update and, if
    /// `coast_output` is `Some(dt)`, also every `dt` seconds of IMU time
    /// without a fix (coasting epochs, `report: None`).
    ///
    /// # Errors
    /// The first filter error (prediction or update).
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
    /// let imu = (1..=500).map(still);
    /// let fixes = (1..=5).map(|k| GnssFix::new(k as f64, start.pos, Vector3::zeros()));
    /// let mut epochs = 0;
    /// engine.run_gnss(imu, fixes, None, |epoch| {
    ///     assert!(epoch.report.is_some());
    ///     epochs += 1;
    /// }).unwrap();
    /// assert_eq!(epochs, 5);
    /// ```
    pub fn run_gnss<I, G, C>(
        &mut self,
        imu: I,
        gnss: G,
        coast_output: Option<f64>,
        mut on_epoch: C,
    ) -> Result<(), FilterError>
    where
        I: IntoIterator<Item = ImuIncrement>,
        G: IntoIterator<Item = GnssFix>,
        C: FnMut(&Epoch<T, N, UpdateReport<T, 6, A::Report>>),
        F: UpdateForm<T, N, ErrorMeasurement<T, N, 6>, 6>,
        A: NoiseAdapter<T, 6>,
    {
        let mut last_output = self.solution().time;
        let mut fixes = gnss.into_iter().peekable();
        for inc in imu {
            while let Some(fix) = fixes.next_if(|f| f.time < inc.time) {
                let report = self.gnss(&fix)?;
                on_epoch(&self.epoch(fix.time, Some(report)));
                last_output = fix.time;
            }
            self.imu(&inc)?;
            if let Some(dt) = coast_output {
                let now = self.solution().time;
                if now - last_output >= dt {
                    on_epoch(&self.epoch(now, None));
                    last_output = now;
                }
            }
        }
        let end = self.solution().time + self.last_dt();
        for fix in fixes.take_while(|f| f.time <= end) {
            let report = self.gnss(&fix)?;
            on_epoch(&self.epoch(fix.time, Some(report)));
        }
        Ok(())
    }
}
