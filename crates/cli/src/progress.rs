//! Progress bars on stderr, hidden when stderr is not a terminal.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use kestrel_app::progress::Progress;

/// What a bar counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Counts {
    /// Seconds of a log processed.
    Time,
    /// Monte Carlo runs done.
    Runs,
}

/// A bar on stderr for a [`Progress`] of the library.
pub struct Bar {
    bar: ProgressBar,
    counts: Counts,
    start: f64,
    total: f64,
}

impl Bar {
    /// A bar of the seconds of a log processed.
    pub fn time() -> Self {
        Self::new(Counts::Time)
    }

    /// A bar of the Monte Carlo runs done, each stage's name before it.
    pub fn runs() -> Self {
        Self::new(Counts::Runs)
    }

    fn new(counts: Counts) -> Self {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(None, target);
        let template = match counts {
            Counts::Time => "{elapsed_precise} [{bar:40}] {msg} ({eta} left)",
            Counts::Runs => {
                "{prefix} [{bar:30}] {pos}/{len} runs  {elapsed_precise} elapsed, ~{eta} left"
            }
        };
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("=> "));
        }
        Self {
            bar,
            counts,
            start: 0.0,
            total: 0.0,
        }
    }
}

impl Progress for Bar {
    fn stage(&mut self, name: &str) {
        if self.counts == Counts::Runs && !self.bar.is_hidden() {
            eprintln!("{name}");
            self.bar.set_prefix(name.to_string());
        }
    }

    fn begin(&mut self, start: f64, end: f64) {
        self.start = start;
        self.total = (end - start).max(0.0);
        self.bar.reset();
        match self.counts {
            Counts::Time => self.bar.set_length((self.total * 10.0) as u64),
            Counts::Runs => self.bar.set_length(self.total as u64),
        }
    }

    fn reached(&mut self, t: f64) {
        let done = (t - self.start).max(0.0);
        match self.counts {
            Counts::Time => {
                self.bar.set_position((done * 10.0) as u64);
                if !self.bar.is_hidden() {
                    self.bar
                        .set_message(format!("{done:.1} / {:.1} s", self.total));
                }
            }
            Counts::Runs => self.bar.set_position(done as u64),
        }
    }

    fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}
