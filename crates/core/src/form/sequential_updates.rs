//! When the covariance form updates with a diagonal `R` one measurement
//! component at a time.

/// When [`CovarianceForm`](super::CovarianceForm) takes a diagonal
/// measurement noise `R` one component at a time (sequential scalar updates)
/// instead of all at once (the batch update, through a factor of
/// `H P Hᵀ + R`). Either gives the same posterior to rounding; only the cost
/// differs. Sequential updates apply only to filters without an adapter:
/// adapters see the whole innovation.
///
/// The default, [`BySize`](Self::BySize), takes measurements of at least
/// [`MIN_COMPONENTS`](Self::MIN_COMPONENTS) components one at a time. Timed
/// on the project's benchmark machine (the twenty-fifth round of
/// `docs/benchmarks.md`, default `x86-64` target), the batch update was
/// faster for one to three components at every state size tried (by up to
/// a third at 2 to 6 states), the sequential one faster at four to six
/// components from 4 to 12 states (by up to a quarter), and from 15 states
/// on neither was consistently faster.
///
/// ```
/// use kestrel_core::form::SequentialUpdates;
/// assert!(!SequentialUpdates::BySize.applies(3));
/// assert!(SequentialUpdates::BySize.applies(4));
/// assert!(SequentialUpdates::Always.applies(1));
/// assert!(!SequentialUpdates::Never.applies(6));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SequentialUpdates {
    /// One component at a time when the measurement has at least
    /// [`MIN_COMPONENTS`](Self::MIN_COMPONENTS) components (default).
    #[default]
    BySize,
    /// One component at a time for every diagonal `R`.
    Always,
    /// Always the batch update.
    Never,
}

impl SequentialUpdates {
    /// The fewest measurement components [`BySize`](Self::BySize) takes one
    /// at a time.
    pub const MIN_COMPONENTS: usize = 4;

    /// Whether a diagonal `R` of `components` components is taken one
    /// component at a time.
    pub const fn applies(self, components: usize) -> bool {
        match self {
            Self::BySize => components >= Self::MIN_COMPONENTS,
            Self::Always => true,
            Self::Never => false,
        }
    }
}
