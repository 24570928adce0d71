//! The parameters of a filter kind in the order both configuration files
//! (scenario files and `process` configurations) write them: one list, so
//! the two writers cannot disagree on what a kind carries.

use crate::scenario::{FadeBlock, FilterKind};

/// One parameter of a filter kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Param {
    /// A number under its key.
    Number(&'static str, f64),
    /// The R window length (`window`) of the fuzzy filter and of the
    /// max-threshold baseline with windowed R.
    Window(usize),
    /// The states the fade scales (`fade_states`).
    Fade(FadeBlock),
}

/// The parameters of `kind`, in file order.
///
/// ```
/// use kestrel_app::scenario::FilterKind;
/// use kestrel_app::process::filter_params::filter_params;
/// assert!(filter_params(&FilterKind::Standard).is_empty());
/// ```
pub fn filter_params(kind: &FilterKind) -> Vec<Param> {
    use Param::{Fade, Number};
    match *kind {
        FilterKind::Standard => vec![],
        FilterKind::SageHusaFading {
            forgetting,
            reserve,
            lambda_max,
            fade_states,
        } => vec![
            Number("forgetting", forgetting),
            Number("reserve", reserve),
            Number("lambda_max", lambda_max),
            Fade(fade_states),
        ],
        FilterKind::ImprovedAdaptive {
            forgetting,
            reserve,
            lambda_max,
            significance,
            fade_states,
        } => vec![
            Number("forgetting", forgetting),
            Number("reserve", reserve),
            Number("lambda_max", lambda_max),
            Number("significance", significance),
            Fade(fade_states),
        ],
        FilterKind::FederatedUkf { alpha, beta, kappa }
        | FilterKind::FederatedSrUkf { alpha, beta, kappa } => vec![
            Number("alpha", alpha),
            Number("beta", beta),
            Number("kappa", kappa),
        ],
        FilterKind::IctErekf { significance } => vec![Number("significance", significance)],
        FilterKind::MaxThreshold {
            threshold,
            r_window,
        } => {
            let mut p = vec![Number("threshold", threshold)];
            p.extend(r_window.map(Param::Window));
            p
        }
        FilterKind::FuzzyAdaptive { window } => vec![Param::Window(window)],
        FilterKind::StrongTrackingFading {
            rho,
            softening,
            lambda_max,
            fade_states,
        } => vec![
            Number("rho", rho),
            Number("softening", softening),
            Number("lambda_max", lambda_max),
            Fade(fade_states),
        ],
    }
}
