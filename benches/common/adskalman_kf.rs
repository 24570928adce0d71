//! The `adskalman` crate on the benchmark model: its linear transition and
//! observation model traits, implemented over nalgebra `Const` dimensions.

use adskalman::{ObservationModel, TransitionModelLinearNoControl};
use kestrel::nalgebra::{Const, DimMin, SMatrix};
use kestrel::Real;

use super::model::Model;

/// `Φ`, `Φᵀ` and `Q`.
pub struct AdsProcess<T: Real, const N: usize> {
    f: SMatrix<T, N, N>,
    ft: SMatrix<T, N, N>,
    q: SMatrix<T, N, N>,
}

/// `H`, `Hᵀ` and `R`.
pub struct AdsMeasurement<T: Real, const N: usize, const M: usize> {
    h: SMatrix<T, M, N>,
    ht: SMatrix<T, N, M>,
    r: SMatrix<T, M, M>,
}

/// The process and measurement models of `m` with measurement noise `r`.
pub fn models<T: Real, const N: usize, const M: usize>(
    m: &Model<T, N, M>,
    r: &SMatrix<T, M, M>,
) -> (AdsProcess<T, N>, AdsMeasurement<T, N, M>) {
    (
        AdsProcess {
            f: m.phi,
            ft: m.phi.transpose(),
            q: m.q,
        },
        AdsMeasurement {
            h: m.h,
            ht: m.h.transpose(),
            r: *r,
        },
    )
}

impl<T: Real, const N: usize> TransitionModelLinearNoControl<T, Const<N>> for AdsProcess<T, N> {
    fn F(&self) -> &SMatrix<T, N, N> {
        &self.f
    }
    fn FT(&self) -> &SMatrix<T, N, N> {
        &self.ft
    }
    fn Q(&self) -> &SMatrix<T, N, N> {
        &self.q
    }
}

impl<T: Real, const N: usize, const M: usize> ObservationModel<T, Const<N>, Const<M>>
    for AdsMeasurement<T, N, M>
where
    Const<M>: DimMin<Const<M>, Output = Const<M>>,
{
    fn H(&self) -> &SMatrix<T, M, N> {
        &self.h
    }
    fn HT(&self) -> &SMatrix<T, N, M> {
        &self.ht
    }
    fn R(&self) -> &SMatrix<T, M, M> {
        &self.r
    }
}
