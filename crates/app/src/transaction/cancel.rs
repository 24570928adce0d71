//! Stopping a run from outside: a signal handler, a Python thread, a Dask
//! worker. The library never installs handlers or exits the process; it
//! checks the token at its progress points and returns
//! [`Error::Cancelled`](crate::Error::Cancelled), cleaning up on the way.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::Error;

/// A cancellation token, cheap to clone and share between threads.
///
/// ```
/// use kestrel_app::transaction::Cancel;
/// let c = Cancel::default();
/// let handle = c.clone();
/// assert!(c.check().is_ok());
/// handle.cancel();
/// assert!(c.is_cancelled() && c.check().is_err());
/// ```
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token whose flag is `flag` (a signal handler's, say).
    pub fn from_flag(flag: Arc<AtomicBool>) -> Self {
        Self(flag)
    }

    /// Asks the run to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether the run was asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// `Err(Error::Cancelled)` once the run was asked to stop.
    ///
    /// # Errors
    /// [`Error::Cancelled`].
    pub fn check(&self) -> Result<(), Error> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
}
