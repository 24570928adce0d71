//! Per-axis kinematic chains: `K` states per axis (position, velocity, …)
//! stored contiguously for each of up to three axes.

use kestrel_core::nalgebra::{SMatrix, SVector};
use kestrel_core::Real;

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

impl<T: Real> Densities<T> {
    pub(crate) fn uniform(q: T, axes: usize) -> Self {
        Self {
            values: [q; 3],
            axes,
        }
    }

    /// `None` unless `q` has exactly `axes` entries.
    pub(crate) fn per_axis(q: &[T], axes: usize) -> Option<Self> {
        if q.len() != axes {
            return None;
        }
        let mut values = [T::zero(); 3];
        values[..axes].copy_from_slice(q);
        Some(Self { values, axes })
    }

    pub(crate) fn as_slice(&self) -> &[T] {
        &self.values[..self.axes]
    }

    pub(crate) fn get(&self, axis: usize) -> T {
        self.values[axis]
    }
}
