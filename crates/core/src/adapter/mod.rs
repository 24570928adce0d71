//! The noise-adapter hook: how adaptive and robust schemes (noise estimation,
//! fading, innovation inflation and compression, gating) plug into every
//! update form without dynamic dispatch.
//!
//! An adapter sees the update in **measurement space** only — the innovation,
//! its covariance and how that splits into the propagated part, the process
//! noise part and `R` — so one adapter works unchanged with the covariance,
//! unscented and square-root forms. (The unscented forms supply `H P Hᵀ`
//! through their sigma points and, for the split, the statistical
//! linearisation `H = P_xzᵀ P⁻¹`.)
//!
//! Adapters compose as tuples of up to six members, run in order; `()` is the
//! identity. A filter stores its adapter: `Ekf<f64, 4, (A, B)>`.
//!
//! ```
//! use kestrel_core::adapter::{GainStep, NoiseAdapter, PriorAdapter};
//!
//! /// Doubles R on every update and counts updates.
//! #[derive(Default)]
//! struct DoubleR { updates: u32 }
//! impl<T: kestrel_core::Real> PriorAdapter<T> for DoubleR {}
//! impl<T: kestrel_core::Real, const M: usize> NoiseAdapter<T, M> for DoubleR {
//!     type Report = u32;
//!     fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut u32) {
//!         let r = step.noise() * kestrel_core::real::lit::<T>(2.0);
//!         step.set_noise(r);
//!         self.updates += 1;
//!         *report = self.updates;
//!     }
//! }
//! ```

mod gain_step;
mod posterior;
mod prior_step;
mod tuple;

pub use gain_step::GainStep;
pub use posterior::Posterior;
pub use prior_step::PriorStep;

use crate::Real;

/// The hook run right after every predict, before the process noise is added
/// to the propagated covariance. It may fade the propagated part
/// (`P⁻ = λ Φ P Φᵀ + Q`). Most adapters need nothing here and implement it
/// empty: `impl<T: Real> PriorAdapter<T> for MyAdapter {}`.
pub trait PriorAdapter<T: Real> {
    /// Whether the update needs the propagated covariance and the process
    /// noise kept apart ([`GainStep::split`]): fading adapters set this. It
    /// costs a few extra products per update (and, in the square-root form,
    /// a separate factor of `Q`), so the others leave it `false`.
    const NEEDS_SPLIT: bool = false;

    /// Called after each predict with the time step and a fade control.
    #[inline(always)]
    fn after_predict(&mut self, prior: &mut PriorStep<T>) {
        let _ = prior;
    }
}

/// The update hooks of a noise adapter for `M`-dimensional measurements.
///
/// Order within one update: the form computes the innovation and its
/// covariance, then [`before_gain`](Self::before_gain) may inflate or replace
/// `R`, scale the innovation, fade the propagated covariance, or reject the
/// measurement; the form recomputes what changed, applies the gain, and
/// [`after_update`](Self::after_update) may learn from the result (for example
/// estimate `R` from the post-fit residual). In the covariance and
/// unscented forms the gain is taken on an `L D Lᵀ` of `C` as the adapters
/// left it (the form's own while they kept `R` and the fade), so an epoch
/// in which the adapters changed nothing is updated as without adapters
/// (the same state, covariance and report, bit for bit), and the
/// [`Posterior`] view computes on that `L D Lᵀ` only what `after_update`
/// reads.
#[diagnostic::on_unimplemented(
    message = "the noise adapter `{Self}` does not work on {M}-dimensional measurements",
    label = "the filter's adapter fixes the measurement size of `update`",
    note = "for a sensor whose size differs from the adapter's, call `update_with(&model, &z, &mut adapter)` with an adapter of that size, or `&mut ()` for none"
)]
pub trait NoiseAdapter<T: Real, const M: usize>: PriorAdapter<T> {
    /// What the adapter reports of each update (λ, inflation factors, …); it
    /// is returned in [`UpdateReport::adapters`](crate::UpdateReport::adapters).
    type Report: Copy + Default + core::fmt::Debug;

    /// `true` only for adapters that never change anything and need no
    /// call (`()` and tuples of such). The covariance form then skips the
    /// update hooks entirely: sequential scalar updates for a diagonal `R`
    /// (when its [`SequentialUpdates`](crate::form::SequentialUpdates)
    /// setting selects them), a batch update without the adapter round
    /// otherwise.
    const IS_IDENTITY: bool = false;

    /// Runs before the gain is computed.
    fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report);

    /// Runs after a successful (not rejected) update.
    #[inline(always)]
    fn after_update(&mut self, posterior: &Posterior<'_, T, M>, report: &mut Self::Report) {
        let _ = (posterior, report);
    }
}

impl<T: Real> PriorAdapter<T> for () {}

impl<T: Real, const M: usize> NoiseAdapter<T, M> for () {
    type Report = ();
    const IS_IDENTITY: bool = true;
    #[inline(always)]
    fn before_gain(&mut self, _step: &mut GainStep<T, M>, _report: &mut ()) {}
}
