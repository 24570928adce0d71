//! How the solution drifts without GNSS: the horizontal and vertical
//! errors in each `--outage` window and in each gap of the GNSS data.
//!
//! A data gap is an interval between two used fixes (or from the initial
//! time to the first fix, or from the last fix to the end of the run)
//! longer than 1.5 × the nominal GNSS interval, the median of the file's
//! first 21 intervals. Windows are half-open, `[start, end)`, as outage
//! windows are.

use kestrel::nav::nalgebra::Vector3;

use super::stats::SumOfSquares;
use super::Outage;

/// What a drift window is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WindowKind {
    /// An `--outage` window given on the command line.
    Outage,
    /// A gap in the GNSS data.
    Gap,
}

impl WindowKind {
    /// The name in the table.
    pub fn name(self) -> &'static str {
        match self {
            Self::Outage => "outage",
            Self::Gap => "gap",
        }
    }
}

/// The errors in one window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowDrift {
    /// What the window is.
    pub kind: WindowKind,
    /// Start, s of week (inclusive).
    pub start: f64,
    /// End, s of week (exclusive).
    pub end: f64,
    /// Compared epochs inside.
    pub epochs: usize,
    /// RMS and largest horizontal error, m (`None` without epochs).
    pub horizontal: Option<(f64, f64)>,
    /// RMS and largest |vertical error|, m (`None` without epochs).
    pub vertical: Option<(f64, f64)>,
}

#[derive(Clone, Copy, Debug)]
struct Window {
    kind: WindowKind,
    start: f64,
    end: f64,
    n: usize,
    h: SumOfSquares,
    v: SumOfSquares,
    max_h: f64,
    max_v: f64,
}

impl Window {
    fn new(kind: WindowKind, start: f64, end: f64) -> Self {
        Self {
            kind,
            start,
            end,
            n: 0,
            h: SumOfSquares::default(),
            v: SumOfSquares::default(),
            max_h: 0.0,
            max_v: 0.0,
        }
    }

    fn contains(&self, t: f64) -> bool {
        t >= self.start && t < self.end
    }

    fn add(&mut self, horizontal: f64, vertical: f64) {
        self.n += 1;
        self.h.add(horizontal);
        self.v.add(vertical);
        self.max_h = self.max_h.max(horizontal);
        self.max_v = self.max_v.max(vertical);
    }

    fn drift(&self) -> WindowDrift {
        let stats = |s: &SumOfSquares, max: f64| (self.n > 0).then(|| (s.rms(self.n), max));
        WindowDrift {
            kind: self.kind,
            start: self.start,
            end: self.end,
            epochs: self.n,
            horizontal: stats(&self.h, self.max_h),
            vertical: stats(&self.v, self.max_v),
        }
    }
}

/// The windows of a run, filled as the compared epochs go by.
#[derive(Clone, Debug)]
pub(crate) struct DriftTable {
    outages: Vec<Window>,
    /// Closed gaps, then the intervals between fixes still open to epochs.
    gaps: Vec<Window>,
    /// The interval since the last used fix (end unknown yet).
    open: Option<Window>,
    /// Intervals between fixes longer than this are gaps, s.
    threshold: Option<f64>,
}

impl DriftTable {
    /// The table for the outage windows `outages`, with data gaps longer
    /// than `threshold` s (none without) counted from `start`.
    pub(crate) fn new(outages: &[Outage], threshold: Option<f64>, start: f64) -> Self {
        Self {
            outages: outages
                .iter()
                .map(|o| Window::new(WindowKind::Outage, o.start, o.end))
                .collect(),
            gaps: Vec::new(),
            open: threshold.map(|_| Window::new(WindowKind::Gap, start, f64::INFINITY)),
            threshold,
        }
    }

    /// A GNSS fix at `t` was used: the interval before it ends there.
    pub(crate) fn fix(&mut self, t: f64) {
        let Some(threshold) = self.threshold else {
            return;
        };
        if let Some(mut w) = self.open.take() {
            w.end = t;
            // Epochs before `t` may still arrive (the solution's samples
            // trail the fixes by less than one IMU interval): the interval
            // stays until the next fix closes the one after it.
            self.gaps.retain(|g| g.end - g.start > threshold);
            self.gaps.push(w);
        }
        self.open = Some(Window::new(WindowKind::Gap, t, f64::INFINITY));
    }

    /// A compared epoch at `t` with the position error `dr` (NED, m).
    pub(crate) fn add(&mut self, t: f64, dr: &Vector3<f64>) {
        let horizontal = dr.x.hypot(dr.y);
        let vertical = dr.z.abs();
        let windows = self
            .outages
            .iter_mut()
            .chain(self.gaps.iter_mut().rev().take(2));
        for w in windows.chain(self.open.as_mut()) {
            if w.contains(t) {
                w.add(horizontal, vertical);
            }
        }
    }

    /// The windows, outages first, then the gaps in time order; the run
    /// ended at `end`.
    pub(crate) fn finish(mut self, end: f64) -> Vec<WindowDrift> {
        if let Some(mut w) = self.open.take() {
            w.end = end;
            self.gaps.push(w);
        }
        let threshold = self.threshold.unwrap_or(f64::INFINITY);
        self.outages
            .iter()
            .chain(self.gaps.iter().filter(|g| g.end - g.start > threshold))
            .map(Window::drift)
            .collect()
    }
}

/// The nominal interval of fix times `times` (the median of their
/// intervals) × 1.5: longer intervals are data gaps. `None` for fewer than
/// two times.
///
/// ```
/// # use kestrel_app::process::gap_threshold;
/// assert_eq!(gap_threshold(&[1.0, 2.0, 3.0, 10.0]), Some(1.5));
/// assert_eq!(gap_threshold(&[1.0]), None);
/// ```
pub fn gap_threshold(times: &[f64]) -> Option<f64> {
    let mut d: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    Some(1.5 * d[d.len() / 2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_and_outages_collect_their_epochs() {
        let outage: Outage = "10:20".parse().unwrap();
        let mut t = DriftTable::new(&[outage], Some(1.5), 0.0);
        // Fixes at 1 Hz from 1 to 9 and from 21 on; epochs at 10 Hz.
        let mut fixes = (1..=9).chain(21..=30).map(f64::from).peekable();
        for k in 0..=300 {
            let time = f64::from(k) * 0.1;
            while fixes.peek().is_some_and(|&f| f <= time) {
                t.fix(fixes.next().unwrap());
            }
            t.add(time, &Vector3::new(3.0, 4.0, -f64::from(k)));
        }
        let w = t.finish(30.05);
        assert_eq!(w.len(), 2);
        assert_eq!(
            (w[0].kind, w[0].start, w[0].end, w[0].epochs),
            (WindowKind::Outage, 10.0, 20.0, 100)
        );
        assert_eq!(
            (w[1].kind, w[1].start, w[1].end, w[1].epochs),
            (WindowKind::Gap, 9.0, 21.0, 120)
        );
        assert_eq!(w[0].horizontal.unwrap(), (5.0, 5.0));
        // |vertical| = 10 t from 100 to 199 (×0.1 s): the largest is 199.
        assert_eq!(w[0].vertical.unwrap().1, 199.0);
    }

    #[test]
    fn a_window_without_epochs_has_no_statistics() {
        let outage: Outage = "10:20".parse().unwrap();
        let w = DriftTable::new(&[outage], None, 0.0).finish(5.0);
        assert_eq!(w[0].epochs, 0);
        assert!(w[0].horizontal.is_none() && w[0].vertical.is_none());
    }
}
