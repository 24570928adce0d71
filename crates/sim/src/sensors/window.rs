//! Time windows for noise changes, faults and outages.

/// The half-open time interval `[start, end)`, s.
///
/// ```
/// use kestrel_sim::TimeWindow;
/// let w = TimeWindow::new(50.0, 100.0);
/// assert!(w.contains(50.0) && w.contains(99.99) && !w.contains(100.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeWindow {
    /// First instant inside, s.
    pub start: f64,
    /// First instant after, s.
    pub end: f64,
}

impl TimeWindow {
    /// The window `[start, end)`, s.
    ///
    /// ```
    /// assert_eq!(kestrel_sim::TimeWindow::new(1.0, 2.0).end, 2.0);
    /// ```
    pub const fn new(start: f64, end: f64) -> Self {
        Self { start, end }
    }

    /// The window `[start, start + duration)`, s.
    ///
    /// ```
    /// let w = kestrel_sim::TimeWindow::starting(600.0, 3.0);
    /// assert_eq!((w.start, w.end), (600.0, 603.0));
    /// ```
    pub const fn starting(start: f64, duration: f64) -> Self {
        Self {
            start,
            end: start + duration,
        }
    }

    /// Whether `t` lies inside.
    ///
    /// ```
    /// assert!(!kestrel_sim::TimeWindow::new(1.0, 2.0).contains(0.5));
    /// ```
    #[inline]
    pub fn contains(&self, t: f64) -> bool {
        t >= self.start && t < self.end
    }

    /// Length, s.
    ///
    /// ```
    /// assert_eq!(kestrel_sim::TimeWindow::new(200.0, 300.0).duration(), 100.0);
    /// ```
    pub fn duration(&self) -> f64 {
        self.end - self.start
    }
}
