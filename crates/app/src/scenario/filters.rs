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
    /// The Kalman filter with a χ² gate on its innovations: an update whose
    /// NIS exceeds `χ²_{1−α}(m)` is rejected (the prior kept). Not in any
    /// paper: the protection against outliers a careful engineer gives a
    /// plain KF, a baseline for paper 000.
    ChiSquareGate {
        /// Significance α of the gate.
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

/// The state size of the federated filters' local filters (the 15-state
/// error model).
pub(crate) const FEDERATED_STATES: usize = 15;

impl FilterKind {
    /// Every kind's name in configuration files, in the order of the enum.
    pub const NAMES: [&'static str; 10] = [
        "ekf",
        "sage-husa-fading",
        "improved-adaptive",
        "federated-ukf",
        "federated-sr-ukf",
        "ict-erekf",
        "chi-square-gate",
        "max-threshold",
        "fuzzy-adaptive",
        "strong-tracking-fading",
    ];

    /// The name a file uses for `name`: one of [`NAMES`](Self::NAMES), or
    /// the earlier spellings `standard` (for `ekf`) and `fading` (for
    /// `strong-tracking-fading`).
    ///
    /// ```
    /// use kestrel_app::scenario::FilterKind;
    /// assert_eq!(FilterKind::canonical_name("standard"), Some("ekf"));
    /// assert_eq!(FilterKind::canonical_name("kalman"), None);
    /// ```
    pub fn canonical_name(name: &str) -> Option<&'static str> {
        match name {
            "standard" => Some("ekf"),
            "fading" => Some("strong-tracking-fading"),
            _ => Self::NAMES.iter().copied().find(|n| *n == name),
        }
    }

    /// The kind's name in configuration files.
    ///
    /// ```
    /// use kestrel_app::scenario::FilterKind;
    /// assert_eq!(FilterKind::IctErekf { significance: 0.05 }.name(), "ict-erekf");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Self::Standard => "ekf",
            Self::SageHusaFading { .. } => "sage-husa-fading",
            Self::ImprovedAdaptive { .. } => "improved-adaptive",
            Self::FederatedUkf { .. } => "federated-ukf",
            Self::FederatedSrUkf { .. } => "federated-sr-ukf",
            Self::IctErekf { .. } => "ict-erekf",
            Self::ChiSquareGate { .. } => "chi-square-gate",
            Self::MaxThreshold { .. } => "max-threshold",
            Self::FuzzyAdaptive { .. } => "fuzzy-adaptive",
            Self::StrongTrackingFading { .. } => "strong-tracking-fading",
        }
    }

    /// What the kind is, in a few words (the comment beside `kind` in
    /// written files).
    pub fn summary(&self) -> &'static str {
        match self {
            Self::Standard => "closed-loop error-state EKF, no adaptation",
            Self::SageHusaFading { .. } => "Sage-Husa R + fading memory",
            Self::ImprovedAdaptive { .. } => "Sage-Husa + fading + χ² compression",
            Self::FederatedUkf { .. } => "federated: local GNSS KF + local UKF",
            Self::FederatedSrUkf { .. } => "federated with the square-root UKF",
            Self::IctErekf { .. } => "innovation χ² tests + robust R inflation",
            Self::ChiSquareGate { .. } => "EKF rejecting updates beyond a χ² gate",
            Self::MaxThreshold { .. } => "isolate the odometer on a speed mismatch",
            Self::FuzzyAdaptive { .. } => "fuzzy odometer gain + windowed R",
            Self::StrongTrackingFading { .. } => "suboptimal (strong-tracking) fading factor",
        }
    }

    /// The kind named `name` (canonical, see
    /// [`canonical_name`](Self::canonical_name)) with its parameters from
    /// `p`: each parameter is asked for once, with its default.
    ///
    /// A name that is not one of [`NAMES`](Self::NAMES) gives
    /// [`Standard`](Self::Standard): callers look names up first
    /// ([`canonical_name`](Self::canonical_name)).
    ///
    /// # Errors
    /// The key path and message of a parameter of the wrong type.
    pub fn from_params(
        name: &str,
        p: &mut crate::config::filter::ParamReader<'_>,
    ) -> Result<Self, (String, String)> {
        Ok(match name {
            "sage-husa-fading" => Self::SageHusaFading {
                forgetting: p.number("forgetting", 0.97)?,
                reserve: p.number("reserve", 1.0)?,
                lambda_max: p.number("lambda_max", 10.0)?,
                fade_states: p.fade_states("fade_states")?,
            },
            "improved-adaptive" => Self::ImprovedAdaptive {
                forgetting: p.number("forgetting", 0.97)?,
                reserve: p.number("reserve", 1.0)?,
                lambda_max: p.number("lambda_max", 10.0)?,
                significance: p.number("significance", 0.05)?,
                fade_states: p.fade_states("fade_states")?,
            },
            "federated-ukf" => Self::FederatedUkf {
                alpha: p.number("alpha", 1e-3)?,
                beta: p.number("beta", 2.0)?,
                kappa: p.number("kappa", 0.0)?,
            },
            "federated-sr-ukf" => Self::FederatedSrUkf {
                alpha: p.number("alpha", 1e-3)?,
                beta: p.number("beta", 2.0)?,
                kappa: p.number("kappa", 0.0)?,
            },
            "ict-erekf" => Self::IctErekf {
                significance: p.number("significance", 0.05)?,
            },
            "chi-square-gate" => Self::ChiSquareGate {
                significance: p.number("significance", 0.01)?,
            },
            "max-threshold" => Self::MaxThreshold {
                threshold: p.number_or("threshold_m_s", "threshold", 1.0)?,
                r_window: p.window("window", None)?,
            },
            "fuzzy-adaptive" => Self::FuzzyAdaptive {
                window: p.window("window", Some(20))?.unwrap_or(20),
            },
            "strong-tracking-fading" => Self::StrongTrackingFading {
                rho: p.number("rho", 0.95)?,
                softening: p.number("softening", 1.0)?,
                lambda_max: p.number("lambda_max", f64::INFINITY)?,
                fade_states: p.fade_states("fade_states")?,
            },
            _ => Self::Standard,
        })
    }

    /// The kind's parameters in the order files write them, each with the
    /// comment writers put beside it.
    ///
    /// ```
    /// use kestrel_app::scenario::FilterKind;
    /// assert!(FilterKind::Standard.params().is_empty());
    /// let p = FilterKind::IctErekf { significance: 0.05 }.params();
    /// assert_eq!((p[0].key, p[0].value.to_string()), ("significance", "0.05".to_string()));
    /// ```
    pub fn params(&self) -> Vec<Param> {
        use ParamValue::{Fade, Number, Window};
        let n = |key, x| Param::new(key, Number(x));
        match *self {
            Self::Standard => vec![],
            Self::SageHusaFading {
                forgetting,
                reserve,
                lambda_max,
                fade_states,
            } => vec![
                n("forgetting", forgetting),
                n("reserve", reserve),
                n("lambda_max", lambda_max),
                Param::new("fade_states", Fade(fade_states)),
            ],
            Self::ImprovedAdaptive {
                forgetting,
                reserve,
                lambda_max,
                significance,
                fade_states,
            } => vec![
                n("forgetting", forgetting),
                n("reserve", reserve),
                n("lambda_max", lambda_max),
                n("significance", significance),
                Param::new("fade_states", Fade(fade_states)),
            ],
            Self::FederatedUkf { alpha, beta, kappa }
            | Self::FederatedSrUkf { alpha, beta, kappa } => {
                vec![n("alpha", alpha), n("beta", beta), n("kappa", kappa)]
            }
            Self::IctErekf { significance } => vec![Param {
                comment: "significance α of the χ² tests, [0.01, 0.15]",
                ..n("significance", significance)
            }],
            Self::ChiSquareGate { significance } => vec![Param {
                comment: "significance α of the gate, (0, 1)",
                ..n("significance", significance)
            }],
            Self::MaxThreshold {
                threshold,
                r_window,
            } => {
                let mut p = vec![n("threshold_m_s", threshold)];
                p.extend(r_window.map(|w| Param::new("window", Window(w))));
                p
            }
            Self::FuzzyAdaptive { window } => vec![Param::new("window", Window(window))],
            Self::StrongTrackingFading {
                rho,
                softening,
                lambda_max,
                fade_states,
            } => vec![
                n("rho", rho),
                n("softening", softening),
                n("lambda_max", lambda_max),
                Param::new("fade_states", Fade(fade_states)),
            ],
        }
    }

    /// The first parameter outside the range this module states for it
    /// (parameters the filter's constructor checks are left to it): the
    /// key, the range, the value.
    pub fn out_of_range(&self) -> Option<(&'static str, &'static str, f64)> {
        match *self {
            Self::FederatedUkf { alpha, beta, kappa }
            | Self::FederatedSrUkf { alpha, beta, kappa } => {
                if !(alpha > 0.0 && alpha <= 1.0) {
                    Some(("alpha", "0 < alpha ≤ 1", alpha))
                } else if !(beta >= 0.0 && beta.is_finite()) {
                    Some(("beta", "a finite beta ≥ 0", beta))
                } else if !kappa.is_finite() {
                    Some(("kappa", "a finite kappa", kappa))
                } else if kestrel::sigma::MerweParams::new(alpha, beta, kappa)
                    .weights(FEDERATED_STATES)
                    .is_none()
                {
                    Some((
                        "kappa",
                        "kappa > -15 (the 15 states of the local filter: n + kappa > 0)",
                        kappa,
                    ))
                } else {
                    None
                }
            }
            Self::MaxThreshold { threshold, .. } if !(threshold > 0.0 && threshold.is_finite()) => {
                Some(("threshold_m_s", "a finite threshold > 0 m/s", threshold))
            }
            _ => None,
        }
    }

    /// Whether the kind is a federated filter (paper 001's; they run their
    /// own loop, not the engine's).
    pub fn is_federated(&self) -> bool {
        matches!(
            self,
            Self::FederatedUkf { .. } | Self::FederatedSrUkf { .. }
        )
    }

    /// Whether the kind processes odometer readings (paper 003's).
    pub fn is_odometer(&self) -> bool {
        matches!(self, Self::MaxThreshold { .. } | Self::FuzzyAdaptive { .. })
    }

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
            Self::ChiSquareGate { .. } => "KF + χ² gate",
            Self::MaxThreshold { r_window: None, .. } => "max threshold",
            Self::MaxThreshold { .. } => "max threshold + windowed R",
            Self::FuzzyAdaptive { .. } => "fuzzy adaptive",
            Self::StrongTrackingFading { .. } => "fading KF",
        }
    }
}

/// One parameter of a filter kind, as files write it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// Its key.
    pub key: &'static str,
    /// Its value.
    pub value: ParamValue,
    /// What it is and its range (the comment writers put beside it).
    pub comment: &'static str,
}

impl Param {
    fn new(key: &'static str, value: ParamValue) -> Self {
        let comment = match key {
            "forgetting" => "Sage-Husa forgetting factor b, (0, 1]",
            "reserve" => "reserve coefficient γ of the divergence test, ≥ 1",
            "lambda_max" => "upper clamp of the fading factor λ, ≥ 1 (inf: none)",
            "significance" => "significance α of the χ² compression threshold, (0, 1)",
            "alpha" => "sigma-point spread α, (0, 1]",
            "beta" => "prior-knowledge β (2: Gaussian), ≥ 0",
            "kappa" => "secondary scaling κ",
            "rho" => "forgetting factor ρ of the innovation covariance, [0, 1]",
            "softening" => "softening β on R, ≥ 1",
            "threshold_m_s" => "|v_INS − v_odometer| limit, m/s, > 0",
            "window" => "innovations in the R window: 10, 20 or 50",
            "fade_states" => {
                "states the fade scales: \"all\" (papers), \"velocity-position\", \"attitude-velocity-position\""
            }
            _ => "",
        };
        Self {
            key,
            value,
            comment,
        }
    }
}

/// The value of a [`Param`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamValue {
    /// A number.
    Number(f64),
    /// An R window length.
    Window(usize),
    /// The states a fade scales.
    Fade(FadeBlock),
}

impl core::fmt::Display for ParamValue {
    /// In TOML syntax: a float that reads back to the same bits, an
    /// integer, or a quoted name.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Number(x) if x.is_infinite() => {
                f.write_str(if *x > 0.0 { "inf" } else { "-inf" })
            }
            Self::Number(x) if x.is_nan() => f.write_str("nan"),
            Self::Number(x) => write!(f, "{x:?}"),
            Self::Window(w) => write!(f, "{w}"),
            Self::Fade(b) => write!(f, "\"{}\"", b.name()),
        }
    }
}
