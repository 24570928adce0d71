//! Paper 003's fuzzy adaptive odometer update: the fuzzy gain `α₁` on the
//! odometer velocity, then `R` from a window of corrected innovations.

use kestrel_adaptive::{
    match_factor, odometer_engine, FuzzyGain, OdometerInputs, WindowedNoise, ODOMETER_UNUSABLE,
};
use kestrel_core::{real::lit, FilterError, Real};
use nalgebra::Vector3;

use crate::measurement::{InsContext, OdometerReading};

/// The noise adapter of the fuzzy odometer update: [`FuzzyGain`] (the
/// paper's rule base, [`odometer_engine`]) followed by
/// [`WindowedNoise`] over `W` innovations (eq. 7–8), for the 3-row
/// odometer + non-holonomic measurement.
pub type FuzzyAdapter<T, const W: usize> = (FuzzyGain<T, 3>, WindowedNoise<T, 3, W>);

/// Paper 003's fuzzy adaptive odometer processing: holds the adapter and
/// forms its per-epoch inputs from the INS solution and the reading.
///
/// Inputs: the match factor `dm₁ = |v_SINS| / ŝ` (INS ground speed over the
/// scale-corrected odometer speed, 1 at standstill), the heading rate
/// `ΔH` (deg/s, the INS yaw rate over the Earth: the down component of
/// `C_b^n ω_ib^b − ω_ie^n`), and the odometer velocity of the measurement,
/// `[ŝ, 0, 0]` in the vehicle frame, which the gain scales:
/// `z = v^v − α₁ [ŝ, 0, 0]`.
///
/// ```
/// use kestrel_core::Ekf;
/// use kestrel_core::nalgebra::{SVector, Vector3};
/// use kestrel_nav::{Ellipsoid, Euler, Geodetic, ImuSpec, NavState, Strapdown};
/// use kestrel_nav::engine::{ErrorSystem, InitialUncertainty, LooselyCoupled};
/// use kestrel_nav::measurement::{GnssAntenna, Odometer, OdometerReading};
/// use kestrel_nav::odometer::{FuzzyOdometer, InsOdometer16, ScaleFactorProcess};
///
/// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 200.0),
///     Vector3::new(0.0, 20.0, 0.0), Euler::from_degrees(0.0, 0.0, 90.0));
/// let system = InsOdometer16::new(ImuSpec::perfect(), ScaleFactorProcess::as_published());
/// let p0 = system.initial_covariance(&InitialUncertainty::new(1e-3, 0.05, 0.1));
/// let mut engine = LooselyCoupled::new(Strapdown::new(Ellipsoid::wgs84(), nav),
///     Ekf::<f64, 16>::new(SVector::zeros(), p0).unwrap(), system,
///     GnssAntenna::new(Vector3::zeros()), 0.1);
/// let odometer = Odometer::new(0.1, 0.1);
/// let mut fuzzy = FuzzyOdometer::<f64, 20>::as_published().unwrap();
/// // Wheel spin: the odometer reads 1.5 × the speed.
/// let reading = OdometerReading::new(0.0, 30.0);
/// let m = engine.odometer_measurement(&odometer, &reading);
/// let adapter = fuzzy.prepare(&engine.ins_context(0.0), &reading, 0.0);
/// let report = engine.apply_with(&m, adapter).unwrap();
/// assert!(report.rejected); // dm₁ = 0.67 with a large innovation: unusable
/// ```
#[derive(Debug, Clone)]
pub struct FuzzyOdometer<T: Real, const W: usize> {
    adapter: FuzzyAdapter<T, W>,
    min_speed: f64,
}

impl<T: Real, const W: usize> FuzzyOdometer<T, W> {
    /// Speeds below this (m/s) count as standstill for `dm₁`.
    pub const DEFAULT_MIN_SPEED: f64 = 0.5;

    /// The published processing (Xu, Zhou and Wang, 2024; paper 003 in
    /// `crates/core/REFERENCES.md`): the rule base of [`odometer_engine`]
    /// (odometer unusable when `α₁` is tiny or large), innovation-mean
    /// smoothing 0.5, `R` from the last `W` corrected innovations with an
    /// eigenvalue floor of (0.01 m/s)².
    ///
    /// # Errors
    /// `InvalidParameter` for `W = 0`.
    ///
    /// ```
    /// let f = kestrel_nav::odometer::FuzzyOdometer::<f32, 20>::as_published().unwrap();
    /// assert_eq!(f.adapter().1.len(), 0);
    /// ```
    pub fn as_published() -> Result<Self, FilterError> {
        Ok(Self::new(
            (
                FuzzyGain::new(
                    odometer_engine()?,
                    ODOMETER_UNUSABLE,
                    lit(FuzzyGain::<T, 3>::DEFAULT_SMOOTHING),
                )?,
                WindowedNoise::new(lit(1e-4))?,
            ),
            Self::DEFAULT_MIN_SPEED,
        ))
    }

    /// The processing with a configured adapter and standstill speed (m/s).
    ///
    /// ```
    /// use kestrel_adaptive::{FuzzyGain, WindowedNoise};
    /// use kestrel_nav::odometer::FuzzyOdometer;
    /// let a = (FuzzyGain::odometer().unwrap(), WindowedNoise::<f64, 3, 10>::new(1e-4).unwrap());
    /// let f = FuzzyOdometer::new(a, 1.0);
    /// assert_eq!(f.min_speed(), 1.0);
    /// ```
    pub fn new(adapter: FuzzyAdapter<T, W>, min_speed: f64) -> Self {
        Self { adapter, min_speed }
    }

    /// The standstill speed of `dm₁`, m/s.
    ///
    /// ```
    /// let f = kestrel_nav::odometer::FuzzyOdometer::<f64, 20>::as_published().unwrap();
    /// assert_eq!(f.min_speed(), 0.5);
    /// ```
    pub fn min_speed(&self) -> f64 {
        self.min_speed
    }

    /// The adapter (its state: innovation mean, window).
    ///
    /// ```
    /// let f = kestrel_nav::odometer::FuzzyOdometer::<f64, 20>::as_published().unwrap();
    /// assert!(f.adapter().0.innovation_mean().is_none());
    /// ```
    pub fn adapter(&self) -> &FuzzyAdapter<T, W> {
        &self.adapter
    }

    /// The fuzzy inputs of an epoch: INS context `ins` at the reading's
    /// time, the reading and the current scale-factor estimate `scale`.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_nav::measurement::{InsContext, OdometerReading};
    /// use kestrel_nav::odometer::FuzzyOdometer;
    /// let nav = NavState::new(0.0, Geodetic::from_degrees(34.0, 120.0, 0.0),
    ///     Vector3::new(20.0, 0.0, 0.0), Euler::default());
    /// // Turning right at 10°/s.
    /// let rate = Ellipsoid::wgs84().earth_rate_ned(nav.pos.lat) + Vector3::z() * 10f64.to_radians();
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, rate);
    /// let f = FuzzyOdometer::<f64, 20>::as_published().unwrap();
    /// let i = f.inputs(&ins, &OdometerReading::new(0.0, 25.0), 0.0);
    /// assert!((i.match_factor - 0.8).abs() < 1e-12);
    /// assert!((i.heading_rate - 10.0).abs() < 1e-9);
    /// assert_eq!(i.odometer_velocity.x, 25.0);
    /// ```
    pub fn inputs(
        &self,
        ins: &InsContext,
        reading: &OdometerReading,
        scale: f64,
    ) -> OdometerInputs<T, 3> {
        let speed = reading.speed / (1.0 + scale);
        let s = &ins.state;
        let dm1 = match_factor(s.vel.norm(), speed.abs(), self.min_speed);
        let w = ins.c_bn() * ins.omega_ib - ins.earth.earth_rate_ned(s.pos.lat);
        OdometerInputs::new(
            lit(dm1),
            lit(w.z.to_degrees()),
            Vector3::new(speed, 0.0, 0.0).map(lit::<T>),
        )
    }

    /// Sets this epoch's inputs and returns the adapter to update with
    /// ([`LooselyCoupled::apply_with`](crate::engine::LooselyCoupled::apply_with));
    /// see the type's example.
    ///
    /// ```
    /// use kestrel_nav::{Ellipsoid, Euler, Geodetic, NavState, nalgebra::Vector3};
    /// use kestrel_nav::measurement::{InsContext, OdometerReading};
    /// use kestrel_nav::odometer::FuzzyOdometer;
    /// let nav = NavState::new(0.0, Geodetic::new(0.6, 2.1, 0.0), Vector3::new(20.0, 0.0, 0.0),
    ///     Euler::default());
    /// let ins = InsContext::new(Ellipsoid::wgs84(), nav, Vector3::zeros());
    /// let mut f = FuzzyOdometer::<f64, 20>::as_published().unwrap();
    /// let adapter = f.prepare(&ins, &OdometerReading::new(0.0, 20.0), 0.0);
    /// assert_eq!(adapter.1.len(), 0);
    /// ```
    pub fn prepare(
        &mut self,
        ins: &InsContext,
        reading: &OdometerReading,
        scale: f64,
    ) -> &mut FuzzyAdapter<T, W> {
        let inputs = self.inputs(ins, reading, scale);
        self.adapter.0.set_inputs(inputs);
        &mut self.adapter
    }
}
