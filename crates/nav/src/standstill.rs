//! Standstill detection from the IMU alone: the vehicle stands still when,
//! over a window, the specific force and the angular rate barely vary.
//!
//! The test uses the spread of the vectors — the square root of the sum of
//! the three per-axis variances over the window — not their values, so
//! sensor biases, gravity and the Earth rate do not matter; engine
//! vibration and any motion raise the spread (a horizontal acceleration
//! changes the direction of the specific force, hardly its magnitude, so
//! the vector is tested, not the magnitude). The thresholds depend on the
//! IMU and the vehicle: a MEMS IMU in a car with the engine running shows a
//! specific-force spread of about 0.02–0.05 m/s² standing and well above
//! 0.1 m/s² driving. A slow, perfectly smooth constant-velocity motion is
//! not told apart from standstill by any IMU-only test; the window (1 s or
//! more) makes that unlikely on a road vehicle.

use std::collections::VecDeque;

use crate::imu::ImuIncrement;

/// Running standstill test over the IMU samples of the last `window`
/// seconds.
///
/// ```
/// use kestrel_nav::{ImuIncrement, nalgebra::Vector3};
/// use kestrel_nav::standstill::StandstillDetector;
/// let mut d = StandstillDetector::new(0.5, 0.05, 0.01);
/// let still = |k: usize| ImuIncrement::from_rates(k as f64 * 0.01, 0.01,
///     Vector3::new(1e-3, 0.0, 2e-3), Vector3::new(0.1, 0.0, -9.8));
/// let standing: Vec<bool> = (1..=60).map(|k| d.push(&still(k))).collect();
/// // Not before the window is full, then standing.
/// assert!(!standing[40] && standing[59]);
/// // A jolt of 0.5 m/s² ends it.
/// let jolt = ImuIncrement::from_rates(0.61, 0.01, Vector3::zeros(), Vector3::new(0.6, 0.0, -9.8));
/// assert!(!d.push(&jolt));
/// ```
#[derive(Clone, Debug)]
pub struct StandstillDetector {
    window: f64,
    accel_std: f64,
    gyro_std: f64,
    /// (time, f, ω) of the samples in the window, offset by the first
    /// sample's values (keeps the variances free of cancellation).
    samples: VecDeque<(f64, [f64; 6])>,
    /// Sums over the window of each component and of its square.
    sums: [f64; 6],
    squares: [f64; 6],
    offset: [f64; 6],
    /// Samples since the sums were last recomputed from the window.
    since_exact: u32,
}

impl StandstillDetector {
    /// A detector over `window` seconds, standing when the spread of the
    /// specific force is below `accel_std` (m/s²) and that of the angular
    /// rate below `gyro_std` (rad/s).
    pub fn new(window: f64, accel_std: f64, gyro_std: f64) -> Self {
        Self {
            window,
            accel_std,
            gyro_std,
            samples: VecDeque::new(),
            sums: [0.0; 6],
            squares: [0.0; 6],
            offset: [0.0; 6],
            since_exact: 0,
        }
    }

    /// Adds a sample; returns whether the vehicle stands still over the
    /// window ending with it. Samples with `dt ≤ 0` are ignored (and
    /// answer `false`).
    pub fn push(&mut self, imu: &ImuIncrement) -> bool {
        if imu.dt.is_nan() || imu.dt <= 0.0 {
            return false;
        }
        let f = imu.dvel / imu.dt;
        let w = imu.dtheta / imu.dt;
        let v = [f.x, f.y, f.z, w.x, w.y, w.z];
        if v.iter().any(|x| !x.is_finite()) {
            self.reset();
            return false;
        }
        if self.samples.is_empty() {
            self.offset = v;
        }
        let d: [f64; 6] = core::array::from_fn(|i| v[i] - self.offset[i]);
        self.samples.push_back((imu.time, d));
        self.add(&d, 1.0);
        let span_start = imu.time - self.window;
        while let Some(&(t, d)) = self.samples.front() {
            if t > span_start {
                break;
            }
            self.samples.pop_front();
            self.add(&d, -1.0);
        }
        // Running sums drift by rounding over long runs: recompute them now
        // and then (a few hundred additions per 4096 samples).
        self.since_exact += 1;
        if self.since_exact >= 4096 {
            self.since_exact = 0;
            let (mut sums, mut squares) = ([0.0; 6], [0.0; 6]);
            for (_, d) in &self.samples {
                for ((sum, square), x) in sums.iter_mut().zip(&mut squares).zip(d) {
                    *sum += x;
                    *square += x * x;
                }
            }
            (self.sums, self.squares) = (sums, squares);
        }
        // The window is full when its first sample is within one interval
        // of its start.
        let full = self
            .samples
            .front()
            .is_some_and(|&(t, _)| t - imu.dt <= span_start + 1e-9);
        if !full || self.samples.len() < 2 {
            return false;
        }
        let n = self.samples.len() as f64;
        let spread = |axes: core::ops::Range<usize>| {
            axes.map(|i| ((self.squares[i] - self.sums[i] * self.sums[i] / n) / (n - 1.0)).max(0.0))
                .sum::<f64>()
                .sqrt()
        };
        spread(0..3) < self.accel_std && spread(3..6) < self.gyro_std
    }

    /// Forgets the window (after a gap in the data).
    pub fn reset(&mut self) {
        self.samples.clear();
        self.sums = [0.0; 6];
        self.squares = [0.0; 6];
    }

    fn add(&mut self, d: &[f64; 6], sign: f64) {
        for ((sum, square), x) in self.sums.iter_mut().zip(&mut self.squares).zip(d) {
            *sum += sign * x;
            *square += sign * x * x;
        }
    }
}
