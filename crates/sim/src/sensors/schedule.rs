//! When a sensor sampling at a fixed rate delivers.

/// The epochs `k / rate`, `k = 1, 2, …`, at which a sensor delivers; it is
/// asked at every truth epoch and answers at most once per call, catching
/// up when calls skip epochs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Schedule {
    /// Index of the next delivery (delivery `k` falls at `k / rate`).
    next: u64,
}

impl Schedule {
    /// The first delivery at `1 / rate`.
    pub(super) fn new() -> Self {
        Self { next: 1 }
    }

    /// Whether a delivery is due at `t` s for `rate` Hz (never for a rate
    /// that is not finite and positive); if so, moves on to the first epoch
    /// after `t`. The 1 ns tolerance absorbs the rounding of truth times.
    pub(super) fn due(&mut self, t: f64, rate: f64) -> bool {
        if !(rate.is_finite() && rate > 0.0) || t < self.next as f64 / rate - 1e-9 {
            return false;
        }
        self.next = ((t * rate + 1e-9).floor() as u64).max(self.next) + 1;
        true
    }
}
