//! What an update's adapters did, as the runner's [`Adaptation`].

use kestrel::adaptive::{
    CompositionReport, CompressionReport, DivergenceReport, FuzzyGainReport, HuberReport,
    StrongTrackingReport, WindowedNoiseReport,
};
use kestrel::nav::experiment::Adaptation;
use kestrel::nav::odometer::ThresholdReport;
use kestrel::UpdateReport;

/// Adapter reports that say what they did (the same reading of each
/// report as the experiment runner's).
pub(crate) trait Describe {
    fn describe(&self, a: &mut Adaptation);
}

/// The [`Adaptation`] of an update report.
pub(crate) fn adaptation<const M: usize, R: Describe>(r: &UpdateReport<f64, M, R>) -> Adaptation {
    let mut a = Adaptation {
        nis: r.nis,
        rejected: r.rejected,
        fade: r.fade,
        noise_trace: r.noise.trace(),
        ..Adaptation::default()
    };
    r.adapters.describe(&mut a);
    a
}

impl Describe for () {
    fn describe(&self, _: &mut Adaptation) {}
}

impl<A: Describe, B: Describe> Describe for (A, B) {
    fn describe(&self, a: &mut Adaptation) {
        self.0.describe(a);
        self.1.describe(a);
    }
}

impl<R: Describe, T> Describe for CompositionReport<R, T> {
    fn describe(&self, a: &mut Adaptation) {
        self.tests.describe(a);
    }
}

// The fade itself is in the update report.
impl Describe for DivergenceReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl Describe for StrongTrackingReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl Describe for CompressionReport<f64> {
    fn describe(&self, a: &mut Adaptation) {
        a.compression = self.factor;
    }
}

impl<const M: usize> Describe for HuberReport<f64, M> {
    fn describe(&self, a: &mut Adaptation) {
        a.inflated = self.inflated;
        let smallest = self.factors.min();
        if smallest > 0.0 {
            a.inflation = 1.0 / smallest;
        }
    }
}

impl Describe for ThresholdReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}

impl<const O: usize, const R: usize> Describe for FuzzyGainReport<f64, O, R> {
    fn describe(&self, a: &mut Adaptation) {
        a.alpha1 = self.alpha;
    }
}

impl Describe for WindowedNoiseReport<f64> {
    fn describe(&self, _: &mut Adaptation) {}
}
