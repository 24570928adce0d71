//! One interface to every form, for code that runs `Ekf`, `Ukf` and `SrUkf`
//! side by side.

use nalgebra::{SMatrix, SVector};

use crate::adapter::{NoiseAdapter, PriorAdapter};
use crate::form::{CovarianceForm, SquareRootForm, UnscentedForm};
use crate::{
    Filter, FilterError, LinearizedMeasurement, LinearizedProcess, Real, StateSpace, UpdateReport,
};

/// A recursive estimator of an `N`-dimensional state that can predict with
/// any linearised process model and update with any linearised
/// measurement model: implemented by [`Ekf`](crate::Ekf),
/// [`Ukf`](crate::Ukf) and [`SrUkf`](crate::SrUkf) with any adapter and
/// state space, so one generic function can run all three on the same
/// data. (The unscented forms ignore the Jacobians; to use them without
/// Jacobians, call [`Filter::predict`] and [`Filter::update`] directly.)
///
/// ```
/// use kestrel_core::{Ekf, Estimator, SrUkf, Ukf, FilterError, adapter::NoiseAdapter,
///     LinearizedMeasurement, LinearizedProcess, MeasurementModel, ProcessModel,
///     nalgebra::{Matrix1, Vector1}};
///
/// struct Walk;
/// impl ProcessModel<f64, 1> for Walk {
///     fn propagate(&self, x: &Vector1<f64>, _dt: f64) -> Vector1<f64> { *x }
///     fn noise(&self, _x: &Vector1<f64>, dt: f64) -> Matrix1<f64> { Matrix1::new(dt) }
/// }
/// impl LinearizedProcess<f64, 1> for Walk {
///     fn transition(&self, _x: &Vector1<f64>, _dt: f64) -> Matrix1<f64> { Matrix1::new(1.0) }
/// }
/// struct Direct;
/// impl MeasurementModel<f64, 1, 1> for Direct {
///     fn predict(&self, x: &Vector1<f64>) -> Vector1<f64> { *x }
///     fn noise(&self) -> Matrix1<f64> { Matrix1::new(1.0) }
/// }
/// impl LinearizedMeasurement<f64, 1, 1> for Direct {
///     fn jacobian(&self, _x: &Vector1<f64>) -> Matrix1<f64> { Matrix1::new(1.0) }
/// }
///
/// /// The same run for any form (and any adapter of 1-D measurements).
/// fn run<E>(f: &mut E) -> Result<f64, FilterError>
/// where
///     E: Estimator<f64, 1>,
///     E::Adapter: NoiseAdapter<f64, 1>,
/// {
///     for z in [1.0, 2.0, 3.0] {
///         f.predict(&Walk, 1.0)?;
///         f.update(&Direct, &Vector1::new(z))?;
///     }
///     Ok(f.state()[0])
/// }
/// let (x0, p0) = (Vector1::new(0.0), Matrix1::new(1.0));
/// let ekf = run(&mut Ekf::new(x0, p0)?)?;
/// let ukf = run(&mut Ukf::new(x0, p0)?)?;
/// let srukf = run(&mut SrUkf::new(x0, p0)?)?;
/// // On a linear model the three agree to rounding.
/// assert!((ekf - ukf).abs() < 1e-12 && (ekf - srukf).abs() < 1e-12);
/// # Ok::<(), FilterError>(())
/// ```
pub trait Estimator<T: Real, const N: usize> {
    /// The filter's noise adapter (`()` for none).
    type Adapter;

    /// The state estimate.
    fn state(&self) -> &SVector<T, N>;

    /// The state covariance.
    fn covariance(&self) -> SMatrix<T, N, N>;

    /// Propagates over `dt` (see [`Filter::predict`]).
    fn predict<P: LinearizedProcess<T, N>>(&mut self, model: &P, dt: T) -> Result<(), FilterError>;

    /// Updates with `z` (see [`Filter::update`]).
    #[allow(clippy::type_complexity)]
    fn update<H: LinearizedMeasurement<T, N, M>, const M: usize>(
        &mut self,
        model: &H,
        z: &SVector<T, M>,
    ) -> Result<UpdateReport<T, M, <Self::Adapter as NoiseAdapter<T, M>>::Report>, FilterError>
    where
        Self::Adapter: NoiseAdapter<T, M>;
}

macro_rules! estimator_for_form {
    ($form:ident) => {
        impl<T: Real, const N: usize, A: PriorAdapter<T>, S: StateSpace<T, N>> Estimator<T, N>
            for Filter<T, N, $form<T, N>, A, S>
        {
            type Adapter = A;

            fn state(&self) -> &SVector<T, N> {
                Filter::state(self)
            }

            fn covariance(&self) -> SMatrix<T, N, N> {
                Filter::covariance(self)
            }

            fn predict<P: LinearizedProcess<T, N>>(
                &mut self,
                model: &P,
                dt: T,
            ) -> Result<(), FilterError> {
                Filter::predict(self, model, dt)
            }

            fn update<H: LinearizedMeasurement<T, N, M>, const M: usize>(
                &mut self,
                model: &H,
                z: &SVector<T, M>,
            ) -> Result<UpdateReport<T, M, <A as NoiseAdapter<T, M>>::Report>, FilterError>
            where
                A: NoiseAdapter<T, M>,
            {
                Filter::update(self, model, z)
            }
        }
    };
}

estimator_for_form!(CovarianceForm);
estimator_for_form!(UnscentedForm);
estimator_for_form!(SquareRootForm);
