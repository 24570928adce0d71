//! Two adapters that take an update through part of the adapter path and no
//! further, so that the path's parts can be timed and counted apart (the
//! `adapter_parts` and `adapter_count` benchmarks).
//!
//! Neither changes what the filter estimates beyond what its name says;
//! they are measuring instruments, not noise models.

use kestrel::adapter::{GainStep, NoiseAdapter, PriorAdapter};
use kestrel::linalg::FactoredCovariance;
use kestrel::nalgebra::SMatrix;

/// An adapter that changes nothing, but is not the identity `()`: the
/// update goes the adapter way (the measurement-space view, the gain
/// through the factor of `C`, the posterior view and the report), so its
/// time over the plain step is the cost of that way alone.
#[derive(Debug, Clone, Copy)]
pub struct PassThrough;

impl PriorAdapter<f64> for PassThrough {}

impl<const M: usize> NoiseAdapter<f64, M> for PassThrough {
    type Report = ();

    fn before_gain(&mut self, _step: &mut GainStep<f64, M>, _report: &mut ()) {}
}

/// An adapter that puts a fixed `R̂` and its factor in place at every
/// update, as Sage–Husa does with its estimate, and does nothing else: over
/// [`PassThrough`], the cost of a new `R` (the copies, the factorisation of
/// the new `C`), without the estimate.
#[derive(Debug, Clone, Copy)]
pub struct FixedNoise<const M: usize>(FactoredCovariance<f64, M>);

impl<const M: usize> FixedNoise<M> {
    /// `R̂ = 1.25 R`: positive definite, and not the model's `R`.
    pub fn scaled(r: &SMatrix<f64, M, M>) -> Self {
        Self(FactoredCovariance::new(r * 1.25).expect("R is positive definite"))
    }
}

impl<const M: usize> PriorAdapter<f64> for FixedNoise<M> {}

impl<const M: usize> NoiseAdapter<f64, M> for FixedNoise<M> {
    type Report = ();

    fn before_gain(&mut self, step: &mut GainStep<f64, M>, _report: &mut ()) {
        step.set_factored_noise(&self.0);
    }
}
