//! Fusion in information form: `P_g = (Σ P_i⁻¹)⁻¹`, `x_g = P_g Σ P_i⁻¹ x_i`.

use kestrel_core::linalg::{cholesky, solve_lower, solve_lower_transpose};
use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::Real;

use super::FusionError;

/// A running sum of information matrices `Σ P_i⁻¹` and information vectors
/// `Σ P_i⁻¹ d_i` (paper 001, the federated fusion of Carlson's filter).
///
/// No covariance is ever inverted: each `P_i = L_i L_iᵀ` is factored,
/// `W = L_i⁻¹` comes from a triangular solve and `P_i⁻¹ = Wᵀ W`, which is
/// symmetric and positive definite by construction; [`solve`](Self::solve)
/// factors the sum the same way. States enter as deviations `d_i` from a
/// common reference (the caller adds the fused deviation back), which keeps
/// large states such as positions in metres free of cancellation.
///
/// ```
/// use kestrel_adaptive::federated::Information;
/// use kestrel_core::nalgebra::{Matrix1, Vector1};
/// let mut info = Information::<f64, 1>::new();
/// info.add(0, &Vector1::new(1.0), &Matrix1::new(2.0)).unwrap();
/// info.add(1, &Vector1::new(4.0), &Matrix1::new(1.0)).unwrap();
/// let (x, p) = info.solve().unwrap();
/// // P = (1/2 + 1)⁻¹ = 2/3, x = 2/3 (1/2 + 4) = 3.
/// assert!((p[0] - 2.0 / 3.0).abs() < 1e-15);
/// assert!((x[0] - 3.0).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Information<T: Real, const N: usize> {
    matrix: SMatrix<T, N, N>,
    vector: SVector<T, N>,
    count: usize,
}

impl<T: Real, const N: usize> Default for Information<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real, const N: usize> Information<T, N> {
    /// No information.
    pub fn new() -> Self {
        Self {
            matrix: SMatrix::zeros(),
            vector: SVector::zeros(),
            count: 0,
        }
    }

    /// Adds the estimate `deviation` (from the common reference) with
    /// covariance `covariance` (lower triangle used) of local `local`.
    ///
    /// # Errors
    /// [`FusionError::NonFinite`] for non-finite input or information that
    /// overflows, [`FusionError::NotPositiveDefinite`] if `covariance` has no
    /// Cholesky factor; both name `local`, and the sum is then unchanged.
    pub fn add(
        &mut self,
        local: usize,
        deviation: &SVector<T, N>,
        covariance: &SMatrix<T, N, N>,
    ) -> Result<(), FusionError> {
        let finite = |v: &[T]| v.iter().all(|e| e.is_finite());
        if !finite(deviation.as_slice()) || !finite(covariance.as_slice()) {
            return Err(FusionError::NonFinite { local });
        }
        let l = cholesky(covariance).map_err(|e| FusionError::NotPositiveDefinite {
            local,
            index: e.index,
        })?;
        let (matrix, vector) = inverse_and_solve(&l, deviation);
        if !finite(matrix.as_slice()) || !finite(vector.as_slice()) {
            return Err(FusionError::NonFinite { local });
        }
        self.matrix += matrix;
        self.vector += vector;
        self.count += 1;
        Ok(())
    }

    /// How many estimates were added.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The information matrix `Σ P_i⁻¹`.
    pub fn matrix(&self) -> &SMatrix<T, N, N> {
        &self.matrix
    }

    /// The information vector `Σ P_i⁻¹ d_i`.
    pub fn vector(&self) -> &SVector<T, N> {
        &self.vector
    }

    /// The fused deviation `P_g Σ P_i⁻¹ d_i` and covariance `P_g = (Σ P_i⁻¹)⁻¹`.
    ///
    /// # Errors
    /// [`FusionError::AllIsolated`] if nothing was added,
    /// [`FusionError::FusedNotPositiveDefinite`] if the sum is singular to
    /// working precision, [`FusionError::FusedNonFinite`] on overflow.
    pub fn solve(&self) -> Result<(SVector<T, N>, SMatrix<T, N, N>), FusionError> {
        if self.count == 0 {
            return Err(FusionError::AllIsolated);
        }
        let l = cholesky(&self.matrix)
            .map_err(|e| FusionError::FusedNotPositiveDefinite { index: e.index })?;
        let (p, x) = inverse_and_solve(&l, &self.vector);
        let finite = p.iter().chain(x.iter()).all(|e| e.is_finite());
        if finite {
            Ok((x, p))
        } else {
            Err(FusionError::FusedNonFinite)
        }
    }
}

/// `(A⁻¹, A⁻¹ b)` for `A = L Lᵀ`: `A⁻¹ = Wᵀ W` with `W = L⁻¹` (symmetric by
/// construction) and `A⁻¹ b` by two triangular solves.
fn inverse_and_solve<T: Real, const N: usize>(
    l: &SMatrix<T, N, N>,
    b: &SVector<T, N>,
) -> (SMatrix<T, N, N>, SVector<T, N>) {
    let mut w = SMatrix::<T, N, N>::identity();
    solve_lower(l, &mut w);
    let inverse = w.tr_mul(&w);
    let mut x = *b;
    solve_lower(l, &mut x);
    solve_lower_transpose(l, &mut x);
    (inverse, x)
}

/// Fuses plain vector estimates `(x_i, P_i)`:
/// `P_g = (Σ P_i⁻¹)⁻¹`, `x_g = P_g Σ P_i⁻¹ x_i`, through
/// [`Information`] with deviations from the first estimate. Errors name the
/// estimate's position in `estimates`.
///
/// ```
/// use kestrel_adaptive::federated::fuse;
/// use kestrel_core::nalgebra::{Matrix2, Vector2};
/// let a = (Vector2::new(1.0, 0.0), Matrix2::new(1.0, 0.0, 0.0, 4.0));
/// let b = (Vector2::new(3.0, 2.0), Matrix2::new(1.0, 0.0, 0.0, 4.0));
/// let (x, p) = fuse(&[a, b]).unwrap();
/// assert!((x - Vector2::new(2.0, 1.0)).norm() < 1e-15);
/// assert!((p - Matrix2::new(0.5, 0.0, 0.0, 2.0)).norm() < 1e-15);
/// ```
pub fn fuse<T: Real, const N: usize>(
    estimates: &[(SVector<T, N>, SMatrix<T, N, N>)],
) -> Result<(SVector<T, N>, SMatrix<T, N, N>), FusionError> {
    let Some((reference, _)) = estimates.first() else {
        return Err(FusionError::AllIsolated);
    };
    let mut info = Information::new();
    for (i, (x, p)) in estimates.iter().enumerate() {
        info.add(i, &(x - reference), p)?;
    }
    let (dx, p) = info.solve()?;
    let x = reference + dx;
    if x.iter().all(|v| v.is_finite()) {
        Ok((x, p))
    } else {
        Err(FusionError::FusedNonFinite)
    }
}
