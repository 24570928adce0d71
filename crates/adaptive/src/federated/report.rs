//! What one fusion did, per local.

use kestrel_core::Real;

use super::{LocalStatus, Verdict};

/// One local's part in a fusion.
///
/// ```
/// use kestrel_adaptive::federated::{LocalReport, Verdict};
/// let r = LocalReport::<f32>::default();
/// assert!(r.status.admitted && !r.fused && r.verdict == Verdict::Untested);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalReport<T: Real> {
    /// Its status after this fusion (admitted or isolated, and the counts).
    pub status: LocalStatus,
    /// Whether its estimate took part in this fusion (admitted before and
    /// after it; a re-admitted local joins at the next fusion).
    pub fused: bool,
    /// Its innovation-test verdict over the epoch.
    pub verdict: Verdict,
    /// The share `β_i` it was reset with, which its
    /// [`SharedNoise`](super::SharedNoise) uses until the next fusion: 1 for
    /// an isolated local (it then monitors its sensor against the full
    /// fused estimate); the configured share without reset.
    pub share: T,
    /// `EDOP_i = sqrt(tr(P_i P_iᵀ))` of its covariance before the fusion.
    pub edop: T,
}

impl<T: Real> Default for LocalReport<T> {
    fn default() -> Self {
        Self {
            status: LocalStatus::default(),
            fused: false,
            verdict: Verdict::Untested,
            share: T::zero(),
            edop: T::zero(),
        }
    }
}

/// What a fusion of `L` locals did.
///
/// ```
/// use kestrel_adaptive::federated::FusionReport;
/// let r = FusionReport::<f64, 3>::default();
/// assert_eq!(r.fused, 0);
/// assert_eq!(r.shares(), [0.0; 3]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FusionReport<T: Real, const L: usize> {
    /// Per local.
    pub locals: [LocalReport<T>; L],
    /// How many estimates were fused.
    pub fused: usize,
}

impl<T: Real, const L: usize> Default for FusionReport<T, L> {
    fn default() -> Self {
        Self {
            locals: [LocalReport::default(); L],
            fused: 0,
        }
    }
}

impl<T: Real, const L: usize> FusionReport<T, L> {
    /// The shares `β_i` used for the reset.
    pub fn shares(&self) -> [T; L] {
        self.locals.map(|l| l.share)
    }

    /// The locals' EDOPs before fusion.
    pub fn edops(&self) -> [T; L] {
        self.locals.map(|l| l.edop)
    }

    /// Which locals are admitted after the fusion.
    pub fn admitted(&self) -> [bool; L] {
        self.locals.map(|l| l.status.admitted)
    }
}
