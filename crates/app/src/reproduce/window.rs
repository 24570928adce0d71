//! Errors inside time windows of a run: how large the position error got
//! and how much it grew, e.g. around a sensor fault or a manoeuvre.

use crate::experiment::EpochRecord;
use kestrel::nalgebra::Vector3;

/// A closed time window `[start, end]`, seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// Start, s.
    pub start: f64,
    /// End, s.
    pub end: f64,
}

/// What the position error (3-D, metres) did inside a [`Window`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct WindowError {
    /// The largest position error norm in the window, metres.
    pub max: f64,
    /// The largest change of the position error vector since the last
    /// epoch before the window, metres: the error the window's event added,
    /// free of what earlier events left.
    pub growth: f64,
}

/// Follows the records of a run and measures each window.
///
/// ```
/// use kestrel_app::reproduce::{Window, WindowProbe};
/// use kestrel_app::experiment::EpochRecord;
/// use kestrel::nalgebra::Vector3;
/// let rec = |t: f64, n: f64| EpochRecord {
///     time: t,
///     position: Vector3::new(n, 0.0, 0.0),
///     velocity: Vector3::zeros(),
///     attitude: Vector3::zeros(),
///     adaptation: Default::default(), position_nees: None,
/// };
/// let mut p = WindowProbe::new(&[Window { start: 10.0, end: 20.0 }]);
/// for (t, n) in [(9.0, 5.0), (10.0, 7.0), (15.0, -2.0), (21.0, 50.0)] {
///     p.add(&rec(t, n));
/// }
/// let w = p.finish()[0];
/// assert_eq!((w.max, w.growth), (7.0, 7.0)); // |−2 − 5|
/// ```
#[derive(Clone, Debug)]
pub struct WindowProbe {
    windows: Vec<Window>,
    before: Vec<Vector3<f64>>,
    errors: Vec<WindowError>,
}

impl WindowProbe {
    /// A probe for `windows`.
    pub fn new(windows: &[Window]) -> Self {
        Self {
            windows: windows.to_vec(),
            before: vec![Vector3::zeros(); windows.len()],
            errors: vec![WindowError::default(); windows.len()],
        }
    }

    /// Takes the next record (in time order).
    pub fn add(&mut self, r: &EpochRecord) {
        for ((w, before), e) in self
            .windows
            .iter()
            .zip(&mut self.before)
            .zip(&mut self.errors)
        {
            if r.time < w.start {
                *before = r.position;
            } else if r.time <= w.end {
                e.max = e.max.max(r.position.norm());
                e.growth = e.growth.max((r.position - *before).norm());
            }
        }
    }

    /// The measurements, one per window.
    pub fn finish(self) -> Vec<WindowError> {
        self.errors
    }
}
