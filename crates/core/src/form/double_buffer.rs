//! Two `N × N` buffers, one current and one spare.

use nalgebra::SMatrix;

use crate::Real;

/// Two `N × N` buffers: a form writes the next covariance (or factor) into
/// the spare one, checks it, and only then makes it current. A step that
/// fails its checks leaves the current buffer as it was, and a step that
/// passes them needs no copy of `N × N` values into place.
///
/// Not comparable as a whole: the spare buffer holds whatever the last step
/// left there, so the forms compare [`current`](Self::current) only.
#[derive(Clone)]
pub(crate) struct DoubleBuffer<T: Real, const N: usize> {
    buffers: [SMatrix<T, N, N>; 2],
    /// 0 or 1.
    current: usize,
}

/// The current buffer only: the spare one is scratch.
impl<T: Real, const N: usize> core::fmt::Debug for DoubleBuffer<T, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.current().fmt(f)
    }
}

impl<T: Real, const N: usize> DoubleBuffer<T, N> {
    /// `current` as the current buffer; the spare one zero.
    pub fn new(current: SMatrix<T, N, N>) -> Self {
        Self {
            buffers: [current, SMatrix::zeros()],
            current: 0,
        }
    }

    /// The current buffer.
    pub fn current(&self) -> &SMatrix<T, N, N> {
        // `& 1`: the index is provably in bounds, so no check.
        &self.buffers[self.current & 1]
    }

    /// The spare buffer, to write the next value into.
    pub fn spare(&mut self) -> &mut SMatrix<T, N, N> {
        // `& 1`: provably in bounds, so no check.
        &mut self.buffers[(self.current ^ 1) & 1]
    }

    /// The current buffer (read) and the spare one (to write), for a
    /// result computed from the current value.
    pub fn current_and_spare(&mut self) -> (&SMatrix<T, N, N>, &mut SMatrix<T, N, N>) {
        let [a, b] = &mut self.buffers;
        if self.current & 1 == 0 {
            (a, b)
        } else {
            (b, a)
        }
    }

    /// Makes the spare buffer current.
    ///
    /// The index is written whole. `current ^= 1` compiles to a one-byte
    /// store, which the next step's eight-byte load of the index cannot
    /// take from the store buffer: that load, and every access to the
    /// buffers through it, would wait until the store reaches the cache.
    pub fn swap(&mut self) {
        self.current = 1 - self.current;
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Matrix2;

    use super::*;

    #[test]
    fn the_spare_buffer_becomes_current_only_when_swapped() {
        let a = Matrix2::new(2.0, 0.5, 0.5, 1.0);
        let mut buffers = DoubleBuffer::new(a);
        assert_eq!(buffers.current(), &a);
        // Written but not swapped (a step that failed its checks): the
        // current buffer is unchanged.
        *buffers.spare() = Matrix2::from_element(f64::NAN);
        assert_eq!(buffers.current(), &a);
        // Computed from the current buffer into the spare one, then swapped.
        let (current, spare) = buffers.current_and_spare();
        *spare = current * 2.0;
        buffers.swap();
        assert_eq!(buffers.current(), &(a * 2.0));
        // And back the other way, so both orders of the pair are used.
        let (current, spare) = buffers.current_and_spare();
        assert_eq!(current, &(a * 2.0));
        assert_eq!(spare, &a);
        *spare = current * 3.0;
        buffers.swap();
        assert_eq!(buffers.current(), &(a * 6.0));
    }
}
