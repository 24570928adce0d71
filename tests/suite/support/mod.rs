//! Helpers shared by the integration tests: closeness and bit-equality
//! checks, and `Probe`, a scriptable noise adapter that records what it saw.
//!
//! Each test binary uses only part of this module.
#![allow(dead_code)]

#[macro_use]
pub mod cv;

use std::cell::RefCell;
use std::rc::Rc;

use kestrel::adapter::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use kestrel::nalgebra::SMatrix;

/// Panics unless every element of `a` is within `tol` of `b`.
#[track_caller]
pub fn assert_close<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    tol: f64,
    what: &str,
) {
    let worst = (a - b).abs().max();
    assert!(
        worst <= tol,
        "{what}: differs by {worst:e} (> {tol:e})\n got {a}\n want {b}"
    );
}

/// Panics unless `a` is within `tol` of `b`.
#[track_caller]
pub fn assert_scalar(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: got {a}, want {b}");
}

/// Panics unless the slices have equal length and every element of `a` is
/// within `tol` of `b`.
#[track_caller]
pub fn assert_slice(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: length");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= tol, "{what}: got {a:?}, want {b:?}");
    }
}

/// The bit patterns of a matrix, so "unchanged" also catches `-0.0` and NaN.
pub fn bits<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> Vec<u64> {
    m.iter().map(|v| v.to_bits()).collect()
}

/// One entry of the shared log: which probe ran which hook.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// `after_predict` of the probe with this id.
    Predict(u32),
    /// `before_gain` of the probe with this id.
    Gain(u32),
    /// `after_update` of the probe with this id.
    Update(u32),
}

/// A shared, ordered log of hook calls.
pub type Log = Rc<RefCell<Vec<Event>>>;

/// A new empty log.
pub fn log() -> Log {
    Rc::new(RefCell::new(Vec::new()))
}

/// Something a probe does to the gain step, in order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// Multiply the current `R` by the factor.
    ScaleNoise(f64),
    /// Fade the propagated covariance by λ.
    Fade(f64),
    /// Multiply the innovation by the factor.
    ScaleInnovation(f64),
    /// Reject the measurement.
    Reject,
}

/// What a probe saw in `after_update`, flattened column-major.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SeenPosterior {
    pub innovation: Vec<f64>,
    pub noise: Vec<f64>,
    pub predicted: Vec<f64>,
    pub post_fit_residual: Vec<f64>,
    pub posterior_covariance: Vec<f64>,
    /// Both again, from `post_fit_residual_and_covariance`.
    pub together: (Vec<f64>, Vec<f64>),
    /// `|L⁻¹ ν|²` of the view's whitened innovation.
    pub whitened_norm2: f64,
}

/// The per-update report of a probe: its id and where in the log its hooks
/// ran (`None` if a hook did not run).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ProbeReport {
    pub id: u32,
    pub gain_at: Option<usize>,
    pub update_at: Option<usize>,
}

/// A scriptable adapter: applies `predict_fade` after each predict and
/// `actions` before each gain, logging every hook into a shared log and
/// recording the gain step's innovation covariance after each action.
/// `SPLIT` is its `NEEDS_SPLIT`.
#[derive(Debug, Clone)]
pub struct Probe<const SPLIT: bool = false> {
    pub id: u32,
    pub log: Log,
    pub predict_fade: Option<f64>,
    pub actions: Vec<Action>,
    /// Per update: `C` on entry, then after each action (flattened).
    pub seen_covariances: Vec<Vec<Vec<f64>>>,
    /// Per update: the step's NIS on entry, then after each action.
    pub seen_nis: Vec<Vec<Option<f64>>>,
    /// Per update: `R` on entry (flattened), showing earlier members' effect.
    pub seen_noise: Vec<Vec<f64>>,
    /// Per update: the split on entry, if any.
    pub seen_split: Vec<Option<(Vec<f64>, Vec<f64>)>>,
    /// Per accepted update: the posterior view.
    pub posteriors: Vec<SeenPosterior>,
}

impl<const SPLIT: bool> Probe<SPLIT> {
    /// A probe with id `id` logging into `log`, doing nothing.
    pub fn new(id: u32, log: &Log) -> Self {
        Self {
            id,
            log: log.clone(),
            predict_fade: None,
            actions: Vec::new(),
            seen_covariances: Vec::new(),
            seen_nis: Vec::new(),
            seen_noise: Vec::new(),
            seen_split: Vec::new(),
            posteriors: Vec::new(),
        }
    }

    /// The same probe with before-gain actions `actions`.
    pub fn with_actions(mut self, actions: &[Action]) -> Self {
        self.actions = actions.to_vec();
        self
    }

    /// The same probe fading by `lambda` after each predict.
    pub fn with_predict_fade(mut self, lambda: f64) -> Self {
        self.predict_fade = Some(lambda);
        self
    }

    fn push(&self, event: Event) -> usize {
        let mut log = self.log.borrow_mut();
        log.push(event);
        log.len() - 1
    }
}

fn flat<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> Vec<f64> {
    m.as_slice().to_vec()
}

impl<const SPLIT: bool> PriorAdapter<f64> for Probe<SPLIT> {
    const NEEDS_SPLIT: bool = SPLIT;

    fn after_predict(&mut self, prior: &mut PriorStep<f64>) {
        self.push(Event::Predict(self.id));
        if let Some(lambda) = self.predict_fade {
            prior.fade(lambda);
        }
    }
}

impl<const SPLIT: bool, const M: usize> NoiseAdapter<f64, M> for Probe<SPLIT> {
    type Report = ProbeReport;

    fn before_gain(&mut self, step: &mut GainStep<f64, M>, report: &mut ProbeReport) {
        report.id = self.id;
        report.gain_at = Some(self.push(Event::Gain(self.id)));
        self.seen_noise.push(flat(step.noise()));
        self.seen_split
            .push(step.split().map(|(p, q)| (flat(p), flat(q))));
        let mut covariances = vec![flat(step.innovation_covariance())];
        let mut nis = vec![step.mahalanobis()];
        for action in &self.actions {
            match *action {
                Action::ScaleNoise(k) => {
                    let r = step.noise() * k;
                    step.set_noise(r);
                }
                Action::Fade(lambda) => step.fade(lambda),
                Action::ScaleInnovation(s) => step.scale_innovation(s),
                Action::Reject => step.reject(),
            }
            covariances.push(flat(step.innovation_covariance()));
            nis.push(step.mahalanobis());
        }
        self.seen_covariances.push(covariances);
        self.seen_nis.push(nis);
    }

    fn after_update(&mut self, posterior: &Posterior<'_, f64, M>, report: &mut ProbeReport) {
        report.update_at = Some(self.push(Event::Update(self.id)));
        self.posteriors.push(SeenPosterior {
            innovation: flat(posterior.innovation()),
            noise: flat(posterior.noise()),
            predicted: flat(posterior.predicted_covariance()),
            post_fit_residual: flat(&posterior.post_fit_residual()),
            posterior_covariance: flat(&posterior.posterior_covariance()),
            together: {
                let (residual, covariance) = posterior.post_fit_residual_and_covariance();
                (flat(&residual), flat(&covariance))
            },
            whitened_norm2: posterior.whitened_innovation().norm_squared(),
        });
    }
}
