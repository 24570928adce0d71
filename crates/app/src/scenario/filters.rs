//! The filters the papers compare, as data for a runner.

/// One filter configuration. Parameters the papers leave open carry the
/// values documented on each scenario.
///
/// ```
/// use kestrel_app::scenario::FilterKind;
/// assert_eq!(FilterKind::IctErekf { significance: 0.05 }.label(), "ICT-EREKF");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    /// The closed-loop error-state (extended) Kalman filter without any
    /// adaptation: paper 000's "standard KF", 002's "EKF", 003 without
    /// fault processing, 004's "conventional KF".
    Standard,
    /// Paper 000: simplified Sage–Husa estimation of R combined with fading
    /// memory triggered by the divergence test.
    SageHusaFading {
        /// Forgetting factor `b` of the Sage–Husa weights, in [0.95, 0.99].
        forgetting: f64,
        /// Reserve coefficient `γ ≥ 1` of the divergence test.
        reserve: f64,
        /// Upper clamp of the fading factor λ (dimensionless, ≥ 1).
        lambda_max: f64,
        /// The error states the fade scales.
        fade_states: FadeBlock,
    },
    /// Paper 000's improved adaptive filter: [`SageHusaFading`](Self::SageHusaFading)
    /// plus χ² outlier compression of the innovation.
    ImprovedAdaptive {
        /// Forgetting factor `b`.
        forgetting: f64,
        /// Reserve coefficient `γ`.
        reserve: f64,
        /// Upper clamp of λ (dimensionless, ≥ 1).
        lambda_max: f64,
        /// Significance α of the χ²(m) compression threshold.
        significance: f64,
        /// The error states the fade scales.
        fade_states: FadeBlock,
    },
    /// Paper 001: federated filter, local GNSS Kalman filter plus a local
    /// UKF on the nonlinear INS model, information sharing by EDOP.
    FederatedUkf {
        /// Sigma-point spread α.
        alpha: f64,
        /// Prior-knowledge parameter β (2 for Gaussian).
        beta: f64,
        /// Secondary scaling κ.
        kappa: f64,
    },
    /// Paper 001: as [`FederatedUkf`](Self::FederatedUkf) with the
    /// square-root UKF.
    FederatedSrUkf {
        /// Sigma-point spread α.
        alpha: f64,
        /// Prior-knowledge parameter β.
        beta: f64,
        /// Secondary scaling κ.
        kappa: f64,
    },
    /// Paper 002: extended robust KF with the global and per-component
    /// innovation χ² tests and Huber-like inflation of R.
    IctErekf {
        /// Significance α of the tests.
        significance: f64,
    },
    /// Paper 003's baseline: the odometer is isolated while
    /// `|v_SINS − v_OD|` exceeds `threshold` (m/s); optionally with the
    /// same windowed re-estimation of R as the fuzzy filter (not in the
    /// paper: the baseline given the fuzzy filter's adaptive R, so the
    /// comparison isolates the fuzzy gain).
    MaxThreshold {
        /// Speed difference threshold, m/s.
        threshold: f64,
        /// Innovations in the R window (10, 20 or 50), or `None` for the
        /// fixed R of the paper's baseline.
        r_window: Option<usize>,
    },
    /// Paper 003: fuzzy adaptive odometer gain with windowed re-estimation
    /// of R.
    FuzzyAdaptive {
        /// Number of corrected innovations in the R window.
        window: usize,
    },
    /// Paper 004: suboptimal (strong-tracking) fading factor.
    StrongTrackingFading {
        /// Forgetting factor ρ of the innovation covariance estimate.
        rho: f64,
        /// Softening coefficient β ≥ 1 on R.
        softening: f64,
        /// Upper clamp of λ (dimensionless, ≥ 1; `f64::INFINITY`: none, as
        /// in the paper).
        lambda_max: f64,
        /// The error states the fade scales.
        fade_states: FadeBlock,
    },
}

/// The block of error states a fading filter's fade `λ` scales:
/// `P⁻ = D Φ P Φᵀ D + Q` with `D = √λ` on the block and 1 elsewhere
/// (see `kestrel::form::FadeStates`). The papers write the scalar fade
/// ([`All`](Self::All)); fading only what the fixes measure keeps the fade
/// from inflating the unobservable directions (heading, sensor biases).
///
/// ```
/// use kestrel_app::scenario::FadeBlock;
/// assert_eq!(FadeBlock::VelocityPosition.states(18), 3..9);
/// assert_eq!(FadeBlock::All.states(15), 0..15);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FadeBlock {
    /// Every error state (the scalar fade `λ Φ P Φᵀ`).
    #[default]
    All,
    /// Velocity and position errors (states 3–8 of the 15/18-state
    /// models `[φ, δv, δr, …]`: δv and δr north, east, down, in m/s and m).
    VelocityPosition,
    /// Attitude, velocity and position errors (states 0–8: φ in rad, δv,
    /// δr).
    AttitudeVelocityPosition,
}

impl FadeBlock {
    /// The faded state indices for an `n`-state model (clamped to `n`).
    pub fn states(&self, n: usize) -> core::ops::Range<usize> {
        let range = match self {
            Self::All => 0..n,
            Self::VelocityPosition => 3..9,
            Self::AttitudeVelocityPosition => 0..9,
        };
        range.start.min(n)..range.end.min(n)
    }

    /// The name configuration files use for the block.
    ///
    /// ```
    /// use kestrel_app::scenario::FadeBlock;
    /// assert_eq!(FadeBlock::VelocityPosition.name(), "velocity-position");
    /// assert_eq!(FadeBlock::from_name("all"), Some(FadeBlock::All));
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Self::All => "all",
            Self::VelocityPosition => "velocity-position",
            Self::AttitudeVelocityPosition => "attitude-velocity-position",
        }
    }

    /// The block named `name` (as [`name`](Self::name) writes it).
    pub fn from_name(name: &str) -> Option<Self> {
        [
            Self::All,
            Self::VelocityPosition,
            Self::AttitudeVelocityPosition,
        ]
        .into_iter()
        .find(|b| b.name() == name)
    }
}

impl FilterKind {
    /// A short label for tables and plots.
    ///
    /// ```
    /// assert_eq!(kestrel_app::scenario::FilterKind::Standard.label(), "KF");
    /// ```
    pub fn label(&self) -> &'static str {
        match self {
            Self::Standard => "KF",
            Self::SageHusaFading { .. } => "Sage-Husa+fading",
            Self::ImprovedAdaptive { .. } => "improved adaptive",
            Self::FederatedUkf { .. } => "federated UKF",
            Self::FederatedSrUkf { .. } => "federated SR-UKF",
            Self::IctErekf { .. } => "ICT-EREKF",
            Self::MaxThreshold { r_window: None, .. } => "max threshold",
            Self::MaxThreshold { .. } => "max threshold + windowed R",
            Self::FuzzyAdaptive { .. } => "fuzzy adaptive",
            Self::StrongTrackingFading { .. } => "fading KF",
        }
    }
}
