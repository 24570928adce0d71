//! The filter: a state estimate, an update form and a noise adapter.

use nalgebra::{SMatrix, SVector};

use crate::adapter::{NoiseAdapter, PriorAdapter};
use crate::form::{CovarianceForm, Form, PredictForm, SquareRootForm, UnscentedForm, UpdateForm};
use crate::sigma::MerweParams;
use crate::{Euclidean, FilterError, Real, StateSpace, UpdateDetail, UpdateReport};

/// A recursive estimator of an `N`-dimensional state: an update form `F`
/// (covariance, unscented or square-root unscented), a noise adapter `A`
/// (`()` for none, or a tuple of adapters) and the state arithmetic `S`.
///
/// Models are passed to each [`predict`](Self::predict) and
/// [`update`](Self::update); the form decides which model traits it needs
/// (the covariance form needs Jacobians, the unscented forms do not).
/// Everything is sized at compile time; predict and update never allocate.
///
/// ```
/// use kestrel_core::{Ekf, LinearizedMeasurement, LinearizedProcess, MeasurementModel,
///     ProcessModel, nalgebra::{Matrix1, Vector1}};
///
/// struct Still;
/// impl ProcessModel<f64, 1> for Still {
///     fn propagate(&self, x: &Vector1<f64>, _dt: f64) -> Vector1<f64> { *x }
///     fn noise(&self, _x: &Vector1<f64>, dt: f64) -> Matrix1<f64> { Matrix1::new(0.01 * dt) }
/// }
/// impl LinearizedProcess<f64, 1> for Still {
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
/// let mut kf = Ekf::new(Vector1::new(0.0), Matrix1::new(1.0)).unwrap();
/// kf.predict(&Still, 1.0).unwrap();
/// let report = kf.update(&Direct, &Vector1::new(2.0)).unwrap();
/// // P⁻ = 1.01, K = 1.01 / 2.01
/// assert!((kf.state()[0] - 2.0 * 1.01 / 2.01).abs() < 1e-12);
/// assert!((report.nis - 4.0 / 2.01).abs() < 1e-12);
/// ```
#[derive(Debug, Clone)]
pub struct Filter<T: Real, const N: usize, F, A = (), S = Euclidean> {
    x: SVector<T, N>,
    form: F,
    adapter: A,
    space: S,
}

/// Kalman / extended Kalman filter in covariance form with the Joseph update.
pub type Ekf<T, const N: usize, A = (), S = Euclidean> = Filter<T, N, CovarianceForm<T, N>, A, S>;

/// Unscented Kalman filter (Merwe scaled sigma points).
pub type Ukf<T, const N: usize, A = (), S = Euclidean> = Filter<T, N, UnscentedForm<T, N>, A, S>;

/// Square-root unscented Kalman filter carrying the lower Cholesky factor.
pub type SrUkf<T, const N: usize, A = (), S = Euclidean> = Filter<T, N, SquareRootForm<T, N>, A, S>;

impl<T: Real, const N: usize> Filter<T, N, CovarianceForm<T, N>> {
    /// A covariance-form filter from the initial state and covariance (lower
    /// triangle used). Fails on non-finite input.
    pub fn new(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Result<Self, FilterError> {
        Self::with_form(x0, CovarianceForm::new(&p0)?)
    }
}

impl<T: Real, const N: usize> Filter<T, N, UnscentedForm<T, N>> {
    /// An unscented filter with the default sigma points (`α = 1, β = 2,
    /// κ = 0`, see [`MerweParams`](crate::sigma::MerweParams)).
    pub fn new(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Result<Self, FilterError> {
        Self::with_form(x0, UnscentedForm::new(&p0)?)
    }
}

impl<T: Real, const N: usize> Filter<T, N, SquareRootForm<T, N>> {
    /// A square-root unscented filter with the default sigma points. Fails if
    /// `p0` is not finite and positive semi-definite.
    pub fn new(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Result<Self, FilterError> {
        Self::with_form(x0, SquareRootForm::new(&p0)?)
    }
}

macro_rules! sigma_params {
    ($form:ident) => {
        impl<T: Real, const N: usize, A, S: StateSpace<T, N>> Filter<T, N, $form<T, N>, A, S> {
            /// The same filter with sigma-point parameters `params`.
            ///
            /// ```
            /// use kestrel_core::{SrUkf, Ukf, sigma::MerweParams, nalgebra::{Matrix2, Vector2}};
            /// let params = MerweParams::new(0.5, 2.0, 1.0);
            /// let ukf = Ukf::new(Vector2::zeros(), Matrix2::identity())?.with_sigma_params(params)?;
            /// let sr = SrUkf::new(Vector2::zeros(), Matrix2::identity())?.with_sigma_params(params)?;
            /// assert_eq!(ukf.sigma_params(), &params);
            /// assert_eq!(sr.sigma_params(), &params);
            /// # Ok::<(), kestrel_core::FilterError>(())
            /// ```
            ///
            /// # Errors
            /// [`MerweParams::INVALID`](crate::sigma::MerweParams::INVALID)
            /// for parameters without valid weights at this `N`.
            pub fn with_sigma_params(
                mut self,
                params: MerweParams<T>,
            ) -> Result<Self, FilterError> {
                self.set_sigma_params(params)?;
                Ok(self)
            }

            /// Replaces the sigma-point parameters (the filter is unchanged
            /// on error).
            pub fn set_sigma_params(&mut self, params: MerweParams<T>) -> Result<(), FilterError> {
                self.form = self.form.clone().with_params(params)?;
                Ok(())
            }

            /// The sigma-point parameters.
            pub fn sigma_params(&self) -> &MerweParams<T> {
                self.form.params()
            }
        }
    };
}

sigma_params!(UnscentedForm);
sigma_params!(SquareRootForm);

impl<T: Real, const N: usize, F: Form<T, N>> Filter<T, N, F> {
    /// A filter from an initial state and a configured form, without adapter.
    pub fn with_form(x0: SVector<T, N>, form: F) -> Result<Self, FilterError> {
        crate::error::ensure_finite(&x0, crate::Quantity::State)?;
        Ok(Self {
            x: x0,
            form,
            adapter: (),
            space: Euclidean,
        })
    }
}

impl<T: Real, const N: usize, F: Form<T, N>, A, S: StateSpace<T, N>> Filter<T, N, F, A, S> {
    /// The same filter with noise adapter `adapter` (a single adapter or a
    /// tuple run in order).
    pub fn with_adapter<B>(self, adapter: B) -> Filter<T, N, F, B, S> {
        Filter {
            x: self.x,
            form: self.form,
            adapter,
            space: self.space,
        }
    }

    /// The same filter with state arithmetic `space` (for wrapped angles and
    /// other non-vector states).
    pub fn with_state_space<S2: StateSpace<T, N>>(self, space: S2) -> Filter<T, N, F, A, S2> {
        Filter {
            x: self.x,
            form: self.form,
            adapter: self.adapter,
            space,
        }
    }

    /// Propagates the estimate over `dt` with process model `model`.
    ///
    /// On error (non-finite propagation, a covariance the form cannot
    /// factor) the filter is unchanged.
    pub fn predict<P>(&mut self, model: &P, dt: T) -> Result<(), FilterError>
    where
        F: PredictForm<T, N, P>,
        A: PriorAdapter<T>,
    {
        crate::contract::check_time_step(dt)?;
        self.form
            .predict(&mut self.x, model, dt, &mut self.adapter, &self.space)
    }

    /// Updates the estimate with measurement `z` of model `model`, running
    /// the filter's adapter.
    ///
    /// Errors: a non-finite measurement or model output, or an innovation
    /// covariance that is not positive definite, or a failed square-root
    /// downdate. On error the filter state is unchanged (the adapter may have
    /// updated its own bookkeeping).
    pub fn update<H, const M: usize>(
        &mut self,
        model: &H,
        z: &SVector<T, M>,
    ) -> Result<UpdateReport<T, M, A::Report>, FilterError>
    where
        F: UpdateForm<T, N, H, M>,
        A: NoiseAdapter<T, M>,
    {
        self.form
            .update(&mut self.x, model, z, &mut self.adapter, &self.space)
    }

    /// As [`update`](Self::update), with the update's innovation
    /// covariances and noise ([`UpdateDetail`]).
    pub fn update_detailed<H, const M: usize>(
        &mut self,
        model: &H,
        z: &SVector<T, M>,
    ) -> Result<UpdateDetail<T, M, A::Report>, FilterError>
    where
        F: UpdateForm<T, N, H, M>,
        A: NoiseAdapter<T, M>,
    {
        self.form
            .update(&mut self.x, model, z, &mut self.adapter, &self.space)
    }

    /// Updates with a different adapter than the filter's own, for a second
    /// measurement stream (say, an odometer next to GNSS): pass `&mut ()` for
    /// a plain update.
    pub fn update_with<H, B, const M: usize>(
        &mut self,
        model: &H,
        z: &SVector<T, M>,
        adapter: &mut B,
    ) -> Result<UpdateReport<T, M, B::Report>, FilterError>
    where
        F: UpdateForm<T, N, H, M>,
        B: NoiseAdapter<T, M>,
    {
        self.form
            .update(&mut self.x, model, z, adapter, &self.space)
    }

    /// As [`update_with`](Self::update_with), with the update's innovation
    /// covariances and noise ([`UpdateDetail`]).
    pub fn update_detailed_with<H, B, const M: usize>(
        &mut self,
        model: &H,
        z: &SVector<T, M>,
        adapter: &mut B,
    ) -> Result<UpdateDetail<T, M, B::Report>, FilterError>
    where
        F: UpdateForm<T, N, H, M>,
        B: NoiseAdapter<T, M>,
    {
        self.form
            .update(&mut self.x, model, z, adapter, &self.space)
    }

    /// The state estimate.
    pub fn state(&self) -> &SVector<T, N> {
        &self.x
    }

    /// Replaces the state estimate (e.g. the reset of an error-state filter
    /// after closed-loop feedback). Non-finite states are refused.
    pub fn set_state(&mut self, x: SVector<T, N>) -> Result<(), FilterError> {
        crate::error::ensure_finite(&x, crate::Quantity::State)?;
        self.x = x;
        Ok(())
    }

    /// The state covariance (including a pending process noise).
    pub fn covariance(&self) -> SMatrix<T, N, N> {
        self.form.covariance()
    }

    /// Replaces the covariance (see [`Form::set_covariance`]).
    pub fn set_covariance(&mut self, p: &SMatrix<T, N, N>) -> Result<(), FilterError> {
        self.form.set_covariance(p)
    }

    /// The update form (its configuration and covariance storage).
    pub fn form(&self) -> &F {
        &self.form
    }

    /// Mutable access to the update form's configuration.
    pub fn form_mut(&mut self) -> &mut F {
        &mut self.form
    }

    /// The noise adapter.
    pub fn adapter(&self) -> &A {
        &self.adapter
    }

    /// Mutable access to the noise adapter.
    pub fn adapter_mut(&mut self) -> &mut A {
        &mut self.adapter
    }

    /// The state arithmetic.
    pub fn state_space(&self) -> &S {
        &self.space
    }
}
