//! The progress bar: processed time of the IMU file against its span.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Samples between two updates of the bar (keeps it off the hot path).
const EVERY: u32 = 4096;

/// A bar on stderr, hidden when stderr is not a terminal.
pub(crate) struct Progress {
    bar: ProgressBar,
    start: f64,
    total: f64,
    count: u32,
}

impl Progress {
    /// A bar from `start` to `end` (seconds of week).
    pub(crate) fn new(start: f64, end: f64) -> Self {
        let total = (end - start).max(0.0);
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some((total * 10.0) as u64), target);
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {msg} ({eta} left)")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        Self {
            bar,
            start,
            total,
            count: 0,
        }
    }

    /// The run has reached `t`.
    pub(crate) fn at(&mut self, t: f64) {
        self.count += 1;
        if self.count < EVERY {
            return;
        }
        self.count = 0;
        let done = (t - self.start).max(0.0);
        self.bar.set_position((done * 10.0) as u64);
        if !self.bar.is_hidden() {
            self.bar
                .set_message(format!("{done:.1} / {:.1} s", self.total));
        }
    }

    /// Removes the bar.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
