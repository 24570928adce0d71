//! Per-axis kinematic chains: `K` states per axis (position, velocity, …)
//! stored contiguously for each of up to three axes.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::{FilterError, Real};

/// The block-diagonal matrix with `block(axis)` on the `K × K` diagonal
/// block of each of the `N / K` axes.
pub(crate) fn block_diagonal<T: Real, const N: usize, const K: usize>(
    block: impl Fn(usize) -> SMatrix<T, K, K>,
) -> SMatrix<T, N, N> {
    let mut m = SMatrix::<T, N, N>::zeros();
    for axis in 0..N / K {
        m.fixed_view_mut::<K, K>(axis * K, axis * K)
            .copy_from(&block(axis));
    }
    m
}

/// `Φ x` for the block-diagonal `Φ` with the same block on every axis.
pub(crate) fn apply_per_axis<T: Real, const N: usize, const K: usize>(
    phi: &SMatrix<T, K, K>,
    x: &SVector<T, N>,
) -> SVector<T, N> {
    let mut out = SVector::<T, N>::zeros();
    for axis in 0..N / K {
        let r = axis * K;
        out.fixed_rows_mut::<K>(r)
            .copy_from(&(phi * x.fixed_rows::<K>(r)));
    }
    out
}

/// Per-axis spectral densities for up to three axes; `axes` of them in use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Densities<T> {
    values: [T; 3],
    axes: usize,
}

/// A spectral density out of range.
const NEGATIVE: FilterError = FilterError::InvalidParameter {
    name: "q",
    valid: "finite and at least 0 on every axis",
};

impl<T: Real> Densities<T> {
    /// The same density on every axis; refused unless finite and `≥ 0`.
    pub(crate) fn uniform(q: T, axes: usize) -> Result<Self, FilterError> {
        if !(q.is_finite() && q >= T::zero()) {
            return Err(NEGATIVE);
        }
        Ok(Self {
            values: [q; 3],
            axes,
        })
    }

    /// Refused unless `q` has exactly `axes` entries, each finite and `≥ 0`.
    pub(crate) fn per_axis(q: &[T], axes: usize) -> Result<Self, FilterError> {
        if q.len() != axes {
            return Err(FilterError::InvalidParameter {
                name: "q",
                valid: "one density per axis (N / 2 of a constant-velocity, N / 3 of a constant-acceleration model)",
            });
        }
        if !q.iter().all(|v| v.is_finite() && *v >= T::zero()) {
            return Err(NEGATIVE);
        }
        let mut values = [T::zero(); 3];
        values[..axes].copy_from_slice(q);
        Ok(Self { values, axes })
    }

    pub(crate) fn as_slice(&self) -> &[T] {
        &self.values[..self.axes]
    }

    pub(crate) fn get(&self, axis: usize) -> T {
        self.values[axis]
    }
}
