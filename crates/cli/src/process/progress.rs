//! The progress bar: processed time of the IMU file against its span.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A bar on stderr, hidden when stderr is not a terminal.
pub(crate) struct Bar {
    bar: ProgressBar,
    start: f64,
    total: f64,
}

impl Bar {
    /// A bar not yet started.
    pub(crate) fn new() -> Self {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(None, target);
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {msg} ({eta} left)")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        Self {
            bar,
            start: 0.0,
            total: 0.0,
        }
    }
}

impl kestrel_io::process::Progress for Bar {
    fn begin(&mut self, start: f64, end: f64) {
        self.start = start;
        self.total = (end - start).max(0.0);
        self.bar.set_length((self.total * 10.0) as u64);
    }

    fn reached(&mut self, t: f64) {
        let done = (t - self.start).max(0.0);
        self.bar.set_position((done * 10.0) as u64);
        if !self.bar.is_hidden() {
            self.bar
                .set_message(format!("{done:.1} / {:.1} s", self.total));
        }
    }

    fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}
