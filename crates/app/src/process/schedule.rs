//! Fixed-rate events at IMU samples: the odometer updates and the output.

/// The epochs `k / rate`, `k = 1, 2, …` (relative to time 0), each taken at
/// the first IMU sample that reaches it — the rule the simulator's sensors
/// follow, so simulated odometer readings are used at the same samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Schedule {
    next: u64,
}

impl Schedule {
    pub(crate) fn new() -> Self {
        Self { next: 1 }
    }

    /// Whether an event is due at `t` s for `rate` Hz; if so, moves on to
    /// the first epoch after `t`. 1 ns absorbs the rounding of sample times.
    pub(crate) fn due(&mut self, t: f64, rate: f64) -> bool {
        if !(rate.is_finite() && rate > 0.0) || t < self.next as f64 / rate - 1e-9 {
            return false;
        }
        // Saturating: an absurd rate (1e308 Hz) must not overflow the count.
        self.next = ((t * rate + 1e-9).floor() as u64)
            .max(self.next)
            .saturating_add(1);
        true
    }
}
