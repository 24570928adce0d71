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

use crate::linalg::{mirror_lower, mul_vector};
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

/// The sequential update of the prior `prior`.
pub(crate) fn update<T: Real, const N: usize, const M: usize>(
    prior: &SMatrix<T, N, N>,
    h: &SMatrix<T, M, N>,
    r: &SMatrix<T, M, M>,
    nu: &SVector<T, M>,
) -> Result<Sequential<T, N, M>, FilterError> {
    // The caller's frame keeps its slot for the result: working in the
    // caller's spare buffer instead moves the dense update's stack slots,
    // which slows it at large sizes with the same instructions.
    let mut p = *prior;
    let mut dx = SVector::<T, N>::zeros();
    let mut gains = [SVector::<T, N>::zeros(); M];
    let mut scalars = SVector::<T, M>::zeros();
    let mut nis = T::zero();
    let eps = crate::real::epsilon::<T>();
    for i in 0..M {
        let hi = h.row(i).transpose();
        let b = mul_vector(&p, &hi);
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
        joseph_scalar(&mut p, &(k * c - b), &k, &b);
        gains[i] = k;
        scalars[i] = c;
    }
    Ok(Sequential {
        correction: dx,
        covariance: p,
        innovation_covariance: innovation_covariance(h, &gains, &scalars),
        nis,
    })
}

/// `C = L D Lᵀ` from the components' gains `kᵢ` and innovation variances
/// `D = diag(cᵢ)`, with unit lower `L`, `Lᵢⱼ = hᵢ kⱼ`.
fn innovation_covariance<T: Real, const N: usize, const M: usize>(
    h: &SMatrix<T, M, N>,
    gains: &[SVector<T, N>; M],
    scalars: &SVector<T, M>,
) -> SMatrix<T, M, M> {
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
    c
}

/// The scalar Joseph update, expanded: `P + (c k − b) kᵀ − k bᵀ` with
/// `resid = c k − b`, on the lower triangle, which is then mirrored. Each
/// column is updated from the first row of the block of four that holds
/// its diagonal, so that the loop starts on whole vector registers; the
/// few elements above the diagonal this writes are overwritten by the
/// mirror. (Whole columns, a loop of fixed length, would also compute the
/// blocks above the diagonal's.)
#[inline(always)]
fn joseph_scalar<T: Real, const N: usize>(
    p: &mut SMatrix<T, N, N>,
    resid: &SVector<T, N>,
    k: &SVector<T, N>,
    b: &SVector<T, N>,
) {
    let (resid, k_all) = (&resid.data.0[0], &k.data.0[0]);
    let columns = p.data.0.iter_mut().zip(k_all).zip(b.as_slice());
    for (j, ((column, &kj), &bj)) in columns.enumerate() {
        let from = j - j % 4;
        let rows = column[from..].iter_mut().zip(&resid[from..]);
        for ((pij, &ri), &ki) in rows.zip(&k_all[from..]) {
            *pij += ri * kj - ki * bj;
        }
    }
    mirror_lower(p);
}

#[cfg(test)]
mod tests {
    use nalgebra::{SMatrix, SVector};
    use proptest::prelude::*;

    use super::*;

    /// The update as written before: nalgebra's product `P hᵢ` and the
    /// Joseph update of each column's lower part over its own length.
    fn reference<T: Real, const N: usize, const M: usize>(
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
        for i in 0..M {
            let hi = h.row(i).transpose();
            let b = p * hi;
            let hb = hi.dot(&b);
            let c = hb + r[(i, i)];
            let eps = crate::real::epsilon::<T>();
            if !(c.is_finite() && c > eps * (hb.abs() + r[(i, i)].abs())) {
                let what = Quantity::InnovationCovariance;
                return Err(FilterError::NotPositiveDefinite { what, index: i });
            }
            let e = nu[i] - hi.dot(&dx);
            let k = b / c;
            dx += k * e;
            nis += e * e / c;
            let resid = k * c - b;
            let ps = p.as_mut_slice();
            for j in 0..N {
                let (kj, bj) = (k[j], b[j]);
                let rows = ps[j * N + j..j * N + N]
                    .iter_mut()
                    .zip(&resid.as_slice()[j..]);
                for ((pij, ri), ki) in rows.zip(&k.as_slice()[j..]) {
                    *pij += *ri * kj - *ki * bj;
                }
            }
            mirror_lower(&mut p);
            (gains[i], scalars[i]) = (k, c);
        }
        let innovation_covariance = innovation_covariance(h, &gains, &scalars);
        Ok(Sequential {
            correction: dx,
            covariance: p,
            innovation_covariance,
            nis,
        })
    }

    /// [`update`] against [`reference`] on `P = A Aᵀ`, `H`,
    /// `R = diag(½ + |rᵢ|)` and `ν` from `values`: the same results (`==`, so only
    /// the sign of a zero may differ: its product starts each sum from
    /// zero, nalgebra's from the first term) or the same error.
    /// `zero_rows` rows of `A` are zero, so `P` is singular; with two, the
    /// first component measures the first state, whose variance is zero,
    /// without noise, and both fail at it.
    fn check<T: Real, const N: usize, const M: usize>(values: &[f64], zero_rows: usize) {
        let mut next = values.iter().cycle().map(|&v| T::from_f64(v).unwrap());
        let mut a = SMatrix::<T, N, N>::from_fn(|_, _| next.next().unwrap());
        for i in 0..zero_rows.min(N) {
            a.row_mut(i).fill(T::zero());
        }
        let prior = a * a.transpose();
        let fails = zero_rows == 2;
        let mut h = SMatrix::<T, M, N>::from_fn(|_, _| next.next().unwrap());
        // Variances of ½ or more: only the failing case has a zero one.
        let half = T::from_f64(0.5).unwrap();
        let variances = SVector::from_fn(|_, _| half + next.next().unwrap().abs());
        let mut r = SMatrix::<T, M, M>::from_diagonal(&variances);
        if fails {
            h.row_mut(0).fill(T::zero());
            h[(0, 0)] = T::one();
            r[(0, 0)] = T::zero();
        }
        let nu = SVector::<T, M>::from_fn(|_, _| next.next().unwrap());
        match (update(&prior, &h, &r, &nu), reference(&prior, &h, &r, &nu)) {
            (Ok(fast), Ok(slow)) => {
                assert!(!fails);
                assert_eq!(fast.covariance, slow.covariance);
                assert_eq!(fast.correction, slow.correction);
                assert_eq!(fast.innovation_covariance, slow.innovation_covariance);
                assert_eq!(fast.nis, slow.nis);
            }
            (Err(fast), Err(slow)) => {
                assert!(fails);
                assert_eq!(fast, slow);
            }
            (fast, slow) => panic!(
                "update {:?}, reference {:?}",
                fast.map(|o| o.nis),
                slow.map(|o| o.nis)
            ),
        }
    }

    proptest! {
        #[test]
        fn the_update_equals_the_reference(
            values in prop::collection::vec(-2.0..2.0f64, 1..64),
            zero_rows in 0usize..3,
        ) {
            check::<f64, 1, 1>(&values, zero_rows);
            check::<f64, 2, 2>(&values, zero_rows);
            check::<f64, 3, 2>(&values, zero_rows);
            check::<f64, 4, 4>(&values, zero_rows);
            check::<f64, 7, 3>(&values, zero_rows);
            check::<f64, 15, 6>(&values, zero_rows);
            check::<f64, 32, 6>(&values, zero_rows);
            check::<f32, 9, 4>(&values, zero_rows);
            check::<f32, 15, 6>(&values, zero_rows);
        }
    }
}
