//! Update forms: how a filter represents its covariance and carries out
//! predict and update. Every form keeps the propagated covariance and the
//! process noise apart until the next update (or predict), so an adapter can
//! fade the propagated part before `Q` is added.

// Each form writes out the steps its update shares with the others (input
// checks, the shortcut without adapters, the adapter round, the gain,
// commit and report) rather than calling one driver for them: why, with
// the measurements, is in docs/notes/forms-driver.md.
mod checked_noise;
mod covariance;
mod double_buffer;
mod fade_states;
mod outcome;
mod pending;
mod pending_factor;
mod sequential;
mod sequential_updates;
mod square_root;
mod unscented;

pub use covariance::CovarianceForm;
pub use fade_states::FadeStates;
pub use sequential_updates::SequentialUpdates;
pub use square_root::{SquareRootForm, TimeUpdate};
pub use unscented::UnscentedForm;

use nalgebra::{SMatrix, SVector};

use crate::adapter::{NoiseAdapter, PriorAdapter};
use crate::{FilterError, Real, StateSpace, UpdateOutcome};

/// A covariance representation shared by all forms.
pub trait Form<T: Real, const N: usize> {
    /// The state covariance (the prior with process noise added, if a
    /// prediction is pending an update).
    fn covariance(&self) -> SMatrix<T, N, N>;

    /// Replaces the covariance (the lower triangle is used). Fails if it is
    /// not finite or, for the square-root form, not positive semi-definite.
    fn set_covariance(&mut self, p: &SMatrix<T, N, N>) -> Result<(), FilterError>;
}

/// A form that can predict with process model `P`.
pub trait PredictForm<T: Real, const N: usize, P>: Form<T, N> {
    /// Propagates `x` and the covariance over `dt`, running the adapter's
    /// after-predict hook. On error nothing is changed.
    fn predict<A: PriorAdapter<T>, S: StateSpace<T, N>>(
        &mut self,
        x: &mut SVector<T, N>,
        model: &P,
        dt: T,
        adapter: &mut A,
        space: &S,
    ) -> Result<(), FilterError>;
}

/// A form that can update with measurement model `H` of dimension `M`.
pub trait UpdateForm<T: Real, const N: usize, H, const M: usize>: Form<T, N> {
    /// Updates `x` and the covariance with measurement `z`, running the
    /// adapter's hooks, and returns the outcome `O` (an
    /// [`UpdateReport`](crate::UpdateReport) or an
    /// [`UpdateDetail`](crate::UpdateDetail)). On error nothing is changed.
    fn update<A, S, O>(
        &mut self,
        x: &mut SVector<T, N>,
        model: &H,
        z: &SVector<T, M>,
        adapter: &mut A,
        space: &S,
    ) -> Result<O, FilterError>
    where
        A: NoiseAdapter<T, M>,
        S: StateSpace<T, N>,
        O: UpdateOutcome<T, M, A::Report>;
}
