//! The command line owns the signals: SIGINT and SIGTERM ask the running
//! command to stop (through the library's cancellation token, so it cleans
//! up its scratch files), and the process then exits with 130 or 143. A
//! second signal while the first is being handled ends the process at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use kestrel_app::transaction::Cancel;
use signal_hook::consts::{SIGINT, SIGTERM};

/// The signals this process has received, and the token they set.
#[derive(Clone, Debug)]
pub struct Signals {
    cancel: Cancel,
    interrupted: Arc<AtomicBool>,
    terminated: Arc<AtomicBool>,
}

impl Signals {
    /// Installs the handlers (once, at start).
    pub fn install() -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let interrupted = Arc::new(AtomicBool::new(false));
        let terminated = Arc::new(AtomicBool::new(false));
        for (signal, which) in [(SIGINT, &interrupted), (SIGTERM, &terminated)] {
            // A second signal after the first: exit now (status 1).
            let _ = signal_hook::flag::register_conditional_shutdown(signal, 1, Arc::clone(&stop));
            let _ = signal_hook::flag::register(signal, Arc::clone(&stop));
            let _ = signal_hook::flag::register(signal, Arc::clone(which));
        }
        Self {
            cancel: Cancel::from_flag(stop),
            interrupted,
            terminated,
        }
    }

    /// The token the library checks.
    pub fn cancel(&self) -> &Cancel {
        &self.cancel
    }

    /// The exit status for a run stopped by a signal: 128 + its number
    /// (130 for SIGINT, 143 for SIGTERM).
    pub fn exit_status(&self) -> Option<u8> {
        if self.terminated.load(Ordering::SeqCst) {
            Some(143)
        } else if self.interrupted.load(Ordering::SeqCst) {
            Some(130)
        } else {
            None
        }
    }
}
