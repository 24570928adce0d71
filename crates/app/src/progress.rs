//! How far a run has come, told to whoever shows it (a terminal bar, a
//! log line, a Python callback).

/// Samples between two reports (keeps reporting off the per-sample path).
const EVERY: u32 = 4096;

/// Receives the progress of a run: a terminal bar, a log line, a GUI.
///
/// [`process`](crate::process::process) reports the time of the IMU
/// samples (once per 4096 samples, so an implementation may do real work
/// there); a Monte Carlo reports the runs done out of the runs planned.
///
/// ```
/// use kestrel_app::progress::Progress;
/// /// Remembers the last time reached.
/// struct Last(f64);
/// impl Progress for Last {
///     fn reached(&mut self, t: f64) { self.0 = t; }
/// }
/// let mut p = Last(0.0);
/// p.begin(100.0, 200.0);
/// p.reached(150.0);
/// p.finish();
/// assert_eq!(p.0, 150.0);
/// ```
pub trait Progress {
    /// A new stage of the work begins, named for the reader (e.g.
    /// `scenario 002`).
    fn stage(&mut self, name: &str) {
        let _ = name;
    }
    /// The stage goes from `start` to about `end` (GPS seconds of week for
    /// a log, runs for a Monte Carlo); `end` equals `start` when the
    /// length is not known in advance.
    fn begin(&mut self, start: f64, end: f64) {
        let _ = (start, end);
    }
    /// The stage has come to `t` (the time of the IMU sample processed,
    /// or the runs done).
    fn reached(&mut self, t: f64);
    /// The stage is over, whether it succeeded or not.
    fn finish(&mut self) {}

    /// Whether the run should stop (checked at every report): a caller's
    /// cancellation. The run then returns
    /// [`Error::Cancelled`](crate::Error::Cancelled) and leaves nothing.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Reports nothing.
///
/// ```
/// use kestrel_app::progress::{Progress, Silent};
/// Silent.reached(1.0);
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn reached(&mut self, _t: f64) {}
}

/// A [`Progress`] that also stops the run once a [`Cancel`] token is set
/// (checked where the run reports: every 4096 samples of a log, every
/// Monte Carlo run).
///
/// [`Cancel`]: crate::transaction::Cancel
pub(crate) struct Cancellable<'a, P: Progress + ?Sized> {
    inner: &'a mut P,
    cancel: &'a crate::transaction::Cancel,
}

impl<'a, P: Progress + ?Sized> Cancellable<'a, P> {
    /// `inner`, stopped by `cancel` as well as by its own `cancelled`.
    pub(crate) fn new(inner: &'a mut P, cancel: &'a crate::transaction::Cancel) -> Self {
        Self { inner, cancel }
    }
}

impl<P: Progress + ?Sized> Progress for Cancellable<'_, P> {
    fn stage(&mut self, name: &str) {
        self.inner.stage(name);
    }
    fn begin(&mut self, start: f64, end: f64) {
        self.inner.begin(start, end);
    }
    fn reached(&mut self, t: f64) {
        self.inner.reached(t);
    }
    fn finish(&mut self) {
        self.inner.finish();
    }
    fn cancelled(&self) -> bool {
        self.cancel.is_cancelled() || self.inner.cancelled()
    }
}

/// Passes every [`EVERY`]-th sample on to a [`Progress`].
pub(crate) struct Ticker<'p> {
    inner: &'p mut dyn Progress,
    count: u32,
}

impl<'p> Ticker<'p> {
    /// Starts `inner` on the span `start` … `end`.
    pub(crate) fn new(inner: &'p mut dyn Progress, start: f64, end: f64) -> Self {
        inner.begin(start, end);
        Self { inner, count: 0 }
    }

    /// One sample at `t`; [`Error::Cancelled`](crate::Error::Cancelled)
    /// once the receiver asks the run to stop.
    pub(crate) fn at(&mut self, t: f64) -> Result<(), crate::Error> {
        self.count += 1;
        if self.count >= EVERY {
            self.count = 0;
            self.inner.reached(t);
            if self.inner.cancelled() {
                return Err(crate::Error::Cancelled);
            }
        }
        Ok(())
    }

    /// The run is over.
    pub(crate) fn finish(&mut self) {
        self.inner.finish();
    }
}
