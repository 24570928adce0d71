//! The common shape of every error-state measurement: `z`, `H`, `R`.

use kestrel_core::{real::lit, LinearizedMeasurement, MeasurementModel, Real};
use nalgebra::{SMatrix, SVector};

/// A linear error-state measurement built for one epoch: the INS-minus-sensor
/// difference `z`, its matrix `H` with respect to the error state
/// (`z ≈ H x + v`), and the noise covariance `R` of `v`.
///
/// It implements [`MeasurementModel`] with `predict(x) = H x` and
/// [`LinearizedMeasurement`] with `jacobian(x) = H`, so any filter form takes
/// it; pass [`z`](Self::z) as the measurement. The matrices are computed in
/// `f64` and converted to the filter scalar `T` once, at construction.
///
/// ```
/// use kestrel_core::{Ekf, nalgebra::{SMatrix, SVector, Vector1}};
/// use kestrel_nav::measurement::ErrorMeasurement;
/// // The first state seen with variance 4.
/// let mut h = SMatrix::<f64, 1, 2>::zeros();
/// h[0] = 1.0;
/// let m = ErrorMeasurement::<f32, 2, 1>::new(Vector1::new(1.0), h, Vector1::new(4.0));
/// let mut kf = Ekf::<f32, 2>::new(SVector::zeros(), SMatrix::identity() * 4.0).unwrap();
/// kf.update(&m, &m.z()).unwrap();
/// assert!((kf.state()[0] - 0.5).abs() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorMeasurement<T: Real, const N: usize, const M: usize> {
    z: SVector<T, M>,
    h: SMatrix<T, M, N>,
    r: SMatrix<T, M, M>,
}

impl<T: Real, const N: usize, const M: usize> ErrorMeasurement<T, N, M> {
    /// A measurement from `z`, `H` and the noise variances (diagonal of
    /// `R`), all in `f64`.
    ///
    /// ```
    /// use kestrel_core::nalgebra::{SMatrix, Vector1};
    /// use kestrel_nav::measurement::ErrorMeasurement;
    /// let m = ErrorMeasurement::<f64, 3, 1>::new(Vector1::new(2.0), SMatrix::zeros(),
    ///     Vector1::new(0.25));
    /// assert_eq!(m.noise_covariance()[0], 0.25);
    /// ```
    pub fn new(z: SVector<f64, M>, h: SMatrix<f64, M, N>, variances: SVector<f64, M>) -> Self {
        Self {
            z: z.map(lit::<T>),
            h: h.map(lit::<T>),
            r: SMatrix::from_diagonal(&variances.map(lit::<T>)),
        }
    }

    /// The INS-minus-sensor difference, the measurement to update with.
    ///
    /// ```
    /// use kestrel_core::nalgebra::{SMatrix, Vector2};
    /// use kestrel_nav::measurement::ErrorMeasurement;
    /// let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    /// let m = ErrorMeasurement::<f32, 3, 2>::new(Vector2::new(0.5, -1.0), h, Vector2::new(1.0, 4.0));
    /// assert_eq!(m.z(), Vector2::new(0.5, -1.0));
    /// ```
    pub fn z(&self) -> SVector<T, M> {
        self.z
    }

    /// `H`: the difference's sensitivity to the error state.
    ///
    /// ```
    /// use kestrel_core::nalgebra::{SMatrix, Vector2};
    /// use kestrel_nav::measurement::ErrorMeasurement;
    /// let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    /// let m = ErrorMeasurement::<f32, 3, 2>::new(Vector2::new(0.5, -1.0), h, Vector2::new(1.0, 4.0));
    /// assert_eq!(m.h()[(1, 1)], 1.0);
    /// ```
    pub fn h(&self) -> &SMatrix<T, M, N> {
        &self.h
    }

    /// `R`: the measurement noise covariance (diagonal).
    ///
    /// ```
    /// use kestrel_core::nalgebra::{SMatrix, Vector2};
    /// use kestrel_nav::measurement::ErrorMeasurement;
    /// let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    /// let m = ErrorMeasurement::<f32, 3, 2>::new(Vector2::new(0.5, -1.0), h, Vector2::new(1.0, 4.0));
    /// assert_eq!(m.noise_covariance()[(1, 1)], 4.0);
    /// ```
    pub fn noise_covariance(&self) -> &SMatrix<T, M, M> {
        &self.r
    }
}

impl<T: Real, const N: usize, const M: usize> MeasurementModel<T, N, M>
    for ErrorMeasurement<T, N, M>
{
    #[inline]
    fn predict(&self, x: &SVector<T, N>) -> SVector<T, M> {
        self.h * x
    }

    #[inline]
    fn noise(&self) -> SMatrix<T, M, M> {
        self.r
    }
}

impl<T: Real, const N: usize, const M: usize> LinearizedMeasurement<T, N, M>
    for ErrorMeasurement<T, N, M>
{
    #[inline]
    fn jacobian(&self, _x: &SVector<T, N>) -> SMatrix<T, M, N> {
        self.h
    }
}
