//! Drawing samples from a multivariate normal distribution, for simulation
//! and Monte Carlo.

use kestrel_core::contract::check_covariance;
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{FilterError, Quantity, Real};

/// The normal distribution `N(μ, P)`, ready to sample: `x = μ + L w` with
/// `P = L Lᵀ` (the lower Cholesky factor, computed once) and `w` standard
/// normal. `P` may be singular (a state without uncertainty): it must pass
/// the same contract as a filter's covariance (finite, symmetric, positive
/// semi-definite).
///
/// ```
/// use kestrel_models::Gaussian;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let g = Gaussian::new(Vector2::new(1.0, 2.0), Matrix2::new(4.0, 2.0, 2.0, 2.0)).unwrap();
/// // With a supplied standard-normal source (here a fixed draw):
/// let mut draws = [1.0, -1.0].into_iter();
/// let x = g.sample_with(|| draws.next().unwrap());
/// // L = [[2, 0], [1, 1]]: x = μ + L (1, −1) = (3, 2).
/// assert_eq!(x, Vector2::new(3.0, 2.0));
/// assert!(Gaussian::new(Vector2::zeros(), Matrix2::new(1.0, 0.0, 0.0, -1.0)).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gaussian<T: Real, const N: usize> {
    mean: SVector<T, N>,
    factor: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> Gaussian<T, N> {
    /// `N(mean, covariance)`.
    ///
    /// # Errors
    /// [`FilterError::NonFinite`] for a non-finite mean (as
    /// [`Quantity::State`]) or covariance, and the contract's errors
    /// ([`FilterError::NotSymmetric`], [`FilterError::NotPositiveDefinite`])
    /// naming [`Quantity::Covariance`].
    pub fn new(mean: SVector<T, N>, covariance: SMatrix<T, N, N>) -> Result<Self, FilterError> {
        if let Some(i) = mean.iter().position(|v| !v.is_finite()) {
            return Err(FilterError::NonFinite {
                what: Quantity::State,
                row: i,
                col: 0,
            });
        }
        let factor = check_covariance(&covariance, Quantity::Covariance)?;
        Ok(Self { mean, factor })
    }

    /// `N(0, covariance)`.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn zero_mean(covariance: SMatrix<T, N, N>) -> Result<Self, FilterError> {
        Self::new(SVector::zeros(), covariance)
    }

    /// The mean `μ`.
    pub fn mean(&self) -> &SVector<T, N> {
        &self.mean
    }

    /// The lower Cholesky factor `L` of the covariance.
    pub fn factor(&self) -> &SMatrix<T, N, N> {
        &self.factor
    }

    /// One sample, with the standard normal draws supplied by `normal`
    /// (called `N` times): any random number generator, no dependency.
    pub fn sample_with(&self, mut normal: impl FnMut() -> T) -> SVector<T, N> {
        let w = SVector::<T, N>::from_fn(|_, _| normal());
        self.mean + self.factor * w
    }

    /// One sample drawn with `rng` (feature `rand`, on in the `kestrel`
    /// crate).
    ///
    /// ```
    /// use kestrel_models::Gaussian;
    /// use kestrel_core::nalgebra::{Matrix2, Vector2};
    /// use rand::SeedableRng;
    /// let g = Gaussian::zero_mean(Matrix2::new(4.0_f32, 0.0, 0.0, 1.0)).unwrap();
    /// let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    /// let x: Vector2<f32> = g.sample(&mut rng);
    /// assert!(x.iter().all(|v| v.is_finite()));
    /// ```
    #[cfg(feature = "rand")]
    pub fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> SVector<T, N> {
        use rand_distr::{Distribution, StandardNormal};
        self.sample_with(|| kestrel_core::real::lit(StandardNormal.sample(&mut *rng)))
    }
}

#[cfg(all(test, feature = "rand"))]
mod tests {
    use super::*;
    use kestrel_core::nalgebra::{Matrix3, Vector3};
    use rand::SeedableRng;

    /// 40 000 draws: the sample mean within 4 standard errors of μ and each
    /// sample covariance entry within 4 of its standard errors of P
    /// (`√((Pᵢᵢ Pⱼⱼ + Pᵢⱼ²) / n)` for a normal distribution).
    #[test]
    fn sample_moments_match() {
        let p = Matrix3::new(4.0, 1.0, 0.0, 1.0, 2.0, -0.5, 0.0, -0.5, 1.0);
        let mu = Vector3::new(1.0, -2.0, 0.5);
        let g = Gaussian::new(mu, p).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let n = 40_000;
        let (mut sum, mut outer) = (Vector3::zeros(), Matrix3::zeros());
        for _ in 0..n {
            // Deviations from μ keep the sums well scaled.
            let d = g.sample(&mut rng) - mu;
            sum += d;
            outer += d * d.transpose();
        }
        let nf = n as f64;
        let mean_dev = sum / nf;
        let mean = mu + mean_dev;
        let cov = (outer - mean_dev * mean_dev.transpose() * nf) / (nf - 1.0);
        for i in 0..3 {
            assert!(
                (mean[i] - mu[i]).abs() < 4.0 * (p[(i, i)] / nf).sqrt(),
                "mean {i}"
            );
            for j in 0..3 {
                let se = ((p[(i, i)] * p[(j, j)] + p[(i, j)].powi(2)) / nf).sqrt();
                assert!((cov[(i, j)] - p[(i, j)]).abs() < 4.0 * se, "cov ({i}, {j})");
            }
        }
    }

    /// A singular covariance samples on its subspace: the third component
    /// is exactly the mean.
    #[test]
    fn singular_covariance() {
        let p = Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0);
        let g = Gaussian::new(Vector3::new(0.0, 0.0, 3.0), p).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        for _ in 0..100 {
            assert_eq!(g.sample(&mut rng)[2], 3.0);
        }
    }
}
