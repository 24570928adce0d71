//! The baseline: predict and Joseph update written the straightforward way
//! with nalgebra fixed-size matrices.

use kestrel::nalgebra::{SMatrix, SVector};
use kestrel::Real;

use super::model::Model;

/// A Kalman filter state `(x, P)`.
#[derive(Clone)]
pub struct HandKf<T: Real, const N: usize> {
    /// State.
    pub x: SVector<T, N>,
    /// Covariance.
    pub p: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> HandKf<T, N> {
    /// The filter at `x0`, `p0`.
    pub fn new(x0: SVector<T, N>, p0: SMatrix<T, N, N>) -> Self {
        Self { x: x0, p: p0 }
    }

    /// One predict and one update with measurement `z` and noise `r`;
    /// `false` if the innovation covariance is not positive definite.
    pub fn step<const M: usize>(
        &mut self,
        m: &Model<T, N, M>,
        r: &SMatrix<T, M, M>,
        z: &SVector<T, M>,
    ) -> bool {
        let x = m.phi * self.x;
        let p = m.phi * self.p * m.phi.transpose() + m.q;
        let s = m.h * p * m.h.transpose() + r;
        let Some(chol) = s.cholesky() else {
            return false;
        };
        // K = P Hᵀ S⁻¹, i.e. Kᵀ = S⁻¹ H P (P and S symmetric).
        let k = chol.solve(&(m.h * p)).transpose();
        self.x = x + k * (z - m.h * x);
        let i_kh = SMatrix::<T, N, N>::identity() - k * m.h;
        self.p = i_kh * p * i_kh.transpose() + k * r * k.transpose();
        true
    }
}
