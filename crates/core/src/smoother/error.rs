//! Why recording or smoothing failed.

use core::fmt;

use crate::FilterError;

/// A failure of the RTS record or of its backward pass.
///
/// ```
/// use kestrel_core::smoother::SmootherError;
/// use kestrel_core::{FilterError, Quantity};
/// let e = SmootherError::Full { capacity: 100 };
/// assert_eq!(e.to_string(), "the smoother record is full (100 epochs)");
/// let e = SmootherError::Backward {
///     epoch: 7,
///     error: FilterError::NotPositiveDefinite { what: Quantity::PropagatedCovariance, index: 2 },
/// };
/// assert!(e.to_string().starts_with("smoothing epoch 7: propagated covariance"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SmootherError {
    /// The caller's storage has no room for another epoch.
    Full {
        /// Epochs the storage holds.
        capacity: usize,
    },
    /// A predict or update was recorded before [`start`](super::RtsRecord::start).
    NotStarted,
    /// The output slice is shorter than the record.
    OutputTooShort {
        /// Epochs recorded.
        needed: usize,
        /// Length of the output slice.
        given: usize,
    },
    /// The filter refused the predict being recorded (the record is
    /// unchanged).
    Filter(FilterError),
    /// The backward pass failed at an epoch (counted from 0): the next
    /// epoch's prior covariance is not positive definite, or a result is not
    /// finite.
    Backward {
        /// The epoch being smoothed.
        epoch: usize,
        /// What failed.
        error: FilterError,
    },
}

impl fmt::Display for SmootherError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Full { capacity } => {
                write!(f, "the smoother record is full ({capacity} epochs)")
            }
            Self::NotStarted => f.write_str("the smoother record was not started"),
            Self::OutputTooShort { needed, given } => write!(
                f,
                "the smoother output holds {given} epochs, the record {needed}"
            ),
            Self::Filter(e) => write!(f, "{e}"),
            Self::Backward { epoch, error } => write!(f, "smoothing epoch {epoch}: {error}"),
        }
    }
}

impl core::error::Error for SmootherError {}

impl From<FilterError> for SmootherError {
    fn from(e: FilterError) -> Self {
        Self::Filter(e)
    }
}
