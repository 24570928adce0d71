//! Per-epoch output of a run: navigation errors and what the adapters did.

use kestrel::adaptive::{
    CompositionReport, CompressionReport, DivergenceReport, FuzzyGainReport, GateReport,
    HuberReport, StrongTrackingReport, WindowedNoiseReport,
};
use kestrel::nalgebra::Vector3;
use kestrel::UpdateDetail;

use super::RunError;
use kestrel::nav::odometer::ThresholdReport;
use kestrel::nav::{Ellipsoid, NavError, NavState};

/// What the filter and its adapters did at one update. Neutral values
/// (`1`, `0`, `false`) where a filter has no such adapter.
///
/// ```
/// let a = kestrel_app::experiment::Adaptation::default();
/// assert_eq!((a.fade, a.inflation, a.compression, a.alpha1), (1.0, 1.0, 1.0, 1.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptation {
    /// NIS of the raw innovation against the nominal covariance (the
    /// filter's model before its noise adapters changed `R`).
    pub nis: f64,
    /// NIS of the innovation the gain used against the covariance it used
    /// (after compression, inflation or a new `R`): what the filter itself
    /// claims about the innovation. Equal to [`nis`](Self::nis) without
    /// adapters.
    pub adapted_nis: f64,
    /// The measurement's size `m` (the degrees of freedom of both NIS).
    pub rows: usize,
    /// Whether the update was rejected (the prior kept).
    pub rejected: bool,
    /// The fading factor λ applied to the propagated covariance.
    pub fade: f64,
    /// The largest inflation of an `R` component (`1/αᵢ` of the Huber
    /// weights).
    pub inflation: f64,
    /// How many `R` components were inflated.
    pub inflated: usize,
    /// The factor the innovation was compressed by (outlier compression).
    pub compression: f64,
    /// The fuzzy odometer gain α₁.
    pub alpha1: f64,
    /// The trace of the `R` the gain used.
    pub noise_trace: f64,
}

impl Default for Adaptation {
    fn default() -> Self {
        Self {
            nis: 0.0,
            adapted_nis: 0.0,
            rows: 0,
            rejected: false,
            fade: 1.0,
            inflation: 1.0,
            inflated: 0,
            compression: 1.0,
            alpha1: 1.0,
            noise_trace: 0.0,
        }
    }
}

impl Adaptation {
    /// From an update's detail and its adapters' reports (what each
    /// adapter did, through [`Describe`]).
    ///
    /// ```
    /// use kestrel::{Ekf, nalgebra::{SMatrix, Vector1}};
    /// use kestrel::models::{LinearMeasurement, LinearProcess};
    /// use kestrel_app::experiment::Adaptation;
    /// let mut f = Ekf::<f64, 1>::new(Vector1::zeros(), SMatrix::identity()).unwrap();
    /// let h = LinearMeasurement::new(SMatrix::identity(), SMatrix::identity() * 3.0);
    /// let d = f.update_detailed(&h, &Vector1::new(2.0)).unwrap();
    /// let a = Adaptation::from_update(&d);
    /// // innovation 2, S = P + R = 4: NIS = 1; no adapter, so no fade.
    /// assert_eq!((a.nis, a.fade, a.noise_trace), (1.0, 1.0, 3.0));
    /// ```
    pub fn from_update<const M: usize, R: Describe>(d: &UpdateDetail<f64, M, R>) -> Self {
        let r = &d.report;
        let mut a = Self {
            nis: r.nis,
            adapted_nis: r.adapted_nis,
            rows: M,
            rejected: r.rejected,
            fade: r.fade,
            noise_trace: d.noise.trace(),
            ..Self::default()
        };
        r.adapters.describe(&mut a);
        a
    }
}

/// One aiding epoch of a run: the errors of the navigation solution after
/// the update against the truth at the same instant, and the update.
///
/// ```
/// use kestrel_app::experiment::{Adaptation, EpochRecord};
/// use kestrel::nav::nalgebra::Vector3;
/// let r = EpochRecord { time: 1.0, position: Vector3::new(3.0, 4.0, 0.0),
///     velocity: Vector3::zeros(), attitude: Vector3::zeros(), adaptation: Adaptation::default(),
///     position_nees: None };
/// assert_eq!(r.horizontal_error(), 5.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EpochRecord {
    /// Time, s.
    pub time: f64,
    /// Position error δr (computed − true), NED, m.
    pub position: Vector3<f64>,
    /// Velocity error δv (computed − true), NED, m/s.
    pub velocity: Vector3<f64>,
    /// Attitude error φ, NED, rad (`C(computed) = (I − [φ×]) C(true)`).
    pub attitude: Vector3<f64>,
    /// What the update did.
    pub adaptation: Adaptation,
    /// The normalised estimation error squared of the position,
    /// `δrᵀ P_rr⁻¹ δr` against the filter's posterior position covariance
    /// (χ²(3) for a consistent filter); `None` where the runner has no
    /// single covariance (the federated filters) or it is not positive
    /// definite.
    pub position_nees: Option<f64>,
}

impl EpochRecord {
    /// The errors of `nav` against `truth` at `time` with what the update
    /// did; a non-finite error is reported as `NonFinite` naming `filter`.
    pub(crate) fn measure(
        earth: &Ellipsoid,
        nav: &NavState,
        truth: &NavState,
        adaptation: Adaptation,
        filter: &'static str,
    ) -> Result<Self, RunError> {
        let time = truth.time;
        let e = NavError::between(earth, nav, truth);
        if !e.to_vector().iter().all(|v| v.is_finite()) {
            return Err(RunError::NonFinite { filter, time });
        }
        Ok(Self {
            time,
            position: e.dr,
            velocity: e.dv,
            attitude: e.phi,
            adaptation,
            position_nees: None,
        })
    }

    /// The record with its [`position_nees`](Self::position_nees) against
    /// the position covariance `p` (NED, m²); unchanged without one, `None`
    /// if `p` is not positive definite.
    ///
    /// ```
    /// use kestrel_app::experiment::{Adaptation, EpochRecord};
    /// use kestrel::nav::nalgebra::{Matrix3, Vector3};
    /// let r = EpochRecord { time: 1.0, position: Vector3::new(2.0, 0.0, 3.0),
    ///     velocity: Vector3::zeros(), attitude: Vector3::zeros(),
    ///     adaptation: Adaptation::default(), position_nees: None };
    /// let p = Matrix3::from_diagonal(&Vector3::new(4.0, 1.0, 9.0));
    /// // 2²/4 + 3²/9 = 2.
    /// assert_eq!(r.with_position_covariance(Some(&p)).position_nees, Some(2.0));
    /// assert_eq!(r.with_position_covariance(Some(&-p)).position_nees, None);
    /// ```
    pub fn with_position_covariance(mut self, p: Option<&kestrel::nalgebra::Matrix3<f64>>) -> Self {
        if let Some(p) = p {
            self.position_nees = p
                .cholesky()
                .map(|c| self.position.dot(&c.solve(&self.position)))
                .filter(|v| v.is_finite());
        }
        self
    }

    /// The record with its [`position_nees`](Self::position_nees) set to
    /// `nees`.
    ///
    /// ```
    /// use kestrel_app::experiment::{Adaptation, EpochRecord};
    /// use kestrel::nav::nalgebra::Vector3;
    /// let r = EpochRecord { time: 1.0, position: Vector3::zeros(), velocity: Vector3::zeros(),
    ///     attitude: Vector3::zeros(), adaptation: Adaptation::default(), position_nees: None };
    /// assert_eq!(r.with_nees(Some(2.5)).position_nees, Some(2.5));
    /// ```
    pub fn with_nees(mut self, nees: Option<f64>) -> Self {
        self.position_nees = nees;
        self
    }

    /// The horizontal position error, m.
    ///
    /// ```
    /// # use kestrel_app::experiment::{Adaptation, EpochRecord};
    /// # use kestrel::nav::nalgebra::Vector3;
    /// let r = EpochRecord { time: 0.0, position: Vector3::new(0.0, 0.0, 7.0),
    ///     velocity: Vector3::zeros(), attitude: Vector3::zeros(), adaptation: Adaptation::default(),
    ///     position_nees: None };
    /// assert_eq!(r.horizontal_error(), 0.0);
    /// ```
    pub fn horizontal_error(&self) -> f64 {
        self.position.xy().norm()
    }
}

/// Adapter reports that say what they did, for [`Adaptation::from_update`]
/// (implemented by the reports of the adapters the experiments use, and
/// pairs of them).
///
/// ```
/// use kestrel_app::experiment::{Adaptation, Describe};
/// let mut a = Adaptation::default();
/// ((), ()).describe(&mut a);
/// assert_eq!(a, Adaptation::default());
/// ```
pub trait Describe {
    /// Writes what this report knows into `a`.
    fn describe(&self, a: &mut Adaptation);
}

impl Describe for () {
    fn describe(&self, _: &mut Adaptation) {}
}

impl<A: Describe, B: Describe> Describe for (A, B) {
    fn describe(&self, a: &mut Adaptation) {
        self.0.describe(a);
        self.1.describe(a);
    }
}

impl<R: Describe, T> Describe for CompositionReport<R, T> {
    fn describe(&self, a: &mut Adaptation) {
        self.tests.describe(a);
    }
}

// The fade itself is in the update report.
impl Describe for DivergenceReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl Describe for StrongTrackingReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl Describe for CompressionReport<f64> {
    fn describe(&self, a: &mut Adaptation) {
        a.compression = self.factor;
    }
}

impl<const M: usize> Describe for HuberReport<f64, M> {
    fn describe(&self, a: &mut Adaptation) {
        a.inflated = self.inflated;
        let smallest = self.factors.min();
        if smallest > 0.0 {
            a.inflation = 1.0 / smallest;
        }
    }
}

// The rejection itself is in the update report.
impl Describe for GateReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl Describe for ThresholdReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl<const O: usize, const R: usize> Describe for FuzzyGainReport<f64, O, R> {
    fn describe(&self, a: &mut Adaptation) {
        a.alpha1 = self.alpha;
    }
}

impl Describe for WindowedNoiseReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}
