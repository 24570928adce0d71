//! Sequential scalar processing of a measurement with diagonal `R`.
//!
//! Each component is a scalar update with gain `k = P hᵢᵀ / cᵢ`; the
//! innovation of component `i` is corrected for the earlier components,
//! `eᵢ = νᵢ − hᵢ Σⱼ<ᵢ kⱼ eⱼ`, which makes the result equal to the batch
//! update with `H` evaluated at the prior (the EKF linearisation). The
//! scalar innovations whiten the batch innovation: with
//! `Lᵢⱼ = hᵢ kⱼ (j < i)`, `ν = L e` and `C = L diag(c) Lᵀ`, so the NIS is
//! `Σ eᵢ² / cᵢ` and `C` is recovered for the report.

use nalgebra::{SMatrix, SVector};

use crate::linalg::mirror_lower;
use crate::{FilterError, Quantity, Real};

pub(crate) struct Sequential<T: Real, const N: usize, const M: usize> {
    pub correction: SVector<T, N>,
    pub covariance: SMatrix<T, N, N>,
    pub innovation_covariance: SMatrix<T, M, M>,
    pub nis: T,
}

pub(crate) fn is_diagonal<T: Real, const M: usize>(r: &SMatrix<T, M, M>) -> bool {
    (0..M).all(|j| (0..M).all(|i| i == j || r[(i, j)] == T::zero()))
}

pub(crate) fn update<T: Real, const N: usize, const M: usize>(
    prior: &SMatrix<T, N, N>,
    h: &SMatrix<T, M, N>,
    r: &SMatrix<T, M, M>,
    nu: &SVector<T, M>,
) -> Result<Sequential<T, N, M>, FilterError> {
    let mut p = *prior;
    let mut dx = SVector::<T, N>::zeros();
    let mut gains = [SVector::<T, N>::zeros(); M];
    let mut scalars = SVector::<T, M>::zeros();
    let mut nis = T::zero();
    let eps = crate::real::epsilon::<T>();
    for i in 0..M {
        let hi = h.row(i).transpose();
        let b = p * hi;
        let hb = hi.dot(&b);
        let c = hb + r[(i, i)];
        if !(c.is_finite() && c > eps * (hb.abs() + r[(i, i)].abs())) {
            return Err(FilterError::NotPositiveDefinite {
                what: Quantity::InnovationCovariance,
                index: i,
            });
        }
        let e = nu[i] - hi.dot(&dx);
        let k = b / c;
        dx += k * e;
        nis += e * e / c;
        // Joseph, expanded for a scalar: P + (c k − b) kᵀ − k bᵀ, lower half.
        let resid = k * c - b;
        {
            let ps = p.as_mut_slice();
            for j in 0..N {
                let (kj, bj) = (k[j], b[j]);
                for ((pij, ri), ki) in ps[j * N + j..j * N + N]
                    .iter_mut()
                    .zip(&resid.as_slice()[j..])
                    .zip(&k.as_slice()[j..])
                {
                    *pij += *ri * kj - *ki * bj;
                }
            }
        }
        mirror_lower(&mut p);
        gains[i] = k;
        scalars[i] = c;
    }
    // C = L D Lᵀ with unit lower L, Lᵢⱼ = hᵢ kⱼ.
    let mut l = SMatrix::<T, M, M>::identity();
    for j in 0..M {
        for i in j + 1..M {
            l[(i, j)] = h.row(i).transpose().dot(&gains[j]);
        }
    }
    let mut c = SMatrix::<T, M, M>::zeros();
    for j in 0..M {
        for i in j..M {
            let mut acc = T::zero();
            for t in 0..=j {
                acc += l[(i, t)] * scalars[t] * l[(j, t)];
            }
            c[(i, j)] = acc;
        }
    }
    mirror_lower(&mut c);
    Ok(Sequential {
        correction: dx,
        covariance: p,
        innovation_covariance: c,
        nis,
    })
}
