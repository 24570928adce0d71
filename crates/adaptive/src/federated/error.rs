//! Typed failures of federated fusion, naming the local filter at fault.

use core::fmt;

use kestrel_core::FilterError;

/// Why a fusion (or a federated predict, record or reset) was refused.
///
/// ```
/// use kestrel_adaptive::federated::FusionError;
/// let e = FusionError::NotPositiveDefinite { local: 1, index: 0 };
/// assert_eq!(e.to_string(), "covariance of local filter 1 is not positive definite (pivot 0)");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FusionError {
    /// A local covariance has no Cholesky factor, so its information
    /// `P_i⁻¹` cannot be formed.
    NotPositiveDefinite {
        /// Which local filter.
        local: usize,
        /// The pivot where factorisation failed.
        index: usize,
    },
    /// A local's state, covariance, information or EDOP is not finite.
    NonFinite {
        /// Which local filter.
        local: usize,
    },
    /// The summed information `Σ P_i⁻¹` is singular to working precision.
    FusedNotPositiveDefinite {
        /// The pivot where factorisation failed.
        index: usize,
    },
    /// The fused estimate, or a reset covariance `P_g / β_i`, overflowed.
    FusedNonFinite,
    /// No local estimate took part: every local is isolated (or has just been
    /// re-admitted and joins at the next fusion). The last fused estimate is
    /// kept and the locals are not reset.
    AllIsolated,
    /// There is no local filter with this index.
    NoSuchLocal {
        /// The index asked for.
        local: usize,
    },
    /// A local filter refused its predict or reset.
    Local {
        /// Which local filter.
        local: usize,
        /// Its error.
        error: FilterError,
    },
}

impl fmt::Display for FusionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FusionError::NotPositiveDefinite { local, index } => write!(
                f,
                "covariance of local filter {local} is not positive definite (pivot {index})"
            ),
            FusionError::NonFinite { local } => {
                write!(f, "local filter {local} has a non-finite estimate")
            }
            FusionError::FusedNotPositiveDefinite { index } => {
                write!(
                    f,
                    "fused information is not positive definite (pivot {index})"
                )
            }
            FusionError::FusedNonFinite => f.write_str("fused estimate is not finite"),
            FusionError::AllIsolated => f.write_str("every local filter is isolated"),
            FusionError::NoSuchLocal { local } => write!(f, "no local filter {local}"),
            FusionError::Local { local, error } => write!(f, "local filter {local}: {error}"),
        }
    }
}

impl core::error::Error for FusionError {}
