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
/// [`MIN_COMPONENTS`](Self::MIN_COMPONENTS) components one at a time in
/// filters of at most [`MAX_STATES`](Self::MAX_STATES) states: the sizes at
/// which the sequential update is the faster of the two in `f64`. With
/// fewer components the batch update is the faster, from 15 states on
/// neither is consistently, and in `f32` the batch update is as fast or
/// faster almost everywhere. The timings are in `docs/benchmarks.md`.
///
/// ```
/// use kestrel_core::form::SequentialUpdates;
/// assert!(!SequentialUpdates::BySize.applies(6, 3));
/// assert!(SequentialUpdates::BySize.applies(6, 4));
/// assert!(!SequentialUpdates::BySize.applies(15, 6));
/// assert!(SequentialUpdates::Always.applies(15, 1));
/// assert!(!SequentialUpdates::Never.applies(6, 6));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SequentialUpdates {
    /// One component at a time when the measurement has at least
    /// [`MIN_COMPONENTS`](Self::MIN_COMPONENTS) components and the state at
    /// most [`MAX_STATES`](Self::MAX_STATES) (default).
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

    /// The most states [`BySize`](Self::BySize) takes a measurement one
    /// component at a time in.
    pub const MAX_STATES: usize = 12;

    /// Whether a diagonal `R` of `components` components is taken one
    /// component at a time in a filter of `states` states.
    pub const fn applies(self, states: usize, components: usize) -> bool {
        match self {
            Self::BySize => components >= Self::MIN_COMPONENTS && states <= Self::MAX_STATES,
            Self::Always => true,
            Self::Never => false,
        }
    }
}
