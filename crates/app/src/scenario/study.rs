//! The free choices of the built-in scenarios, as data: the variants a
//! sensitivity study runs, the configurations with competently tuned
//! baselines, the fault-free form a consistency check runs, and which
//! seeds were looked at while choosing parameters.
//!
//! A reproduction must test a paper's claim, not build the conditions
//! under which it holds. Every scenario fixes things its paper leaves
//! open (a fault's shape, a GNSS rate, a baseline's tuning); the
//! [`variants`] make each such choice the other way, so a study can show
//! how much of a result is owed to it.

use core::ops::RangeInclusive;

use kestrel::nalgebra::Vector3;

use super::{by_name, FilterKind, Scenario};
use crate::config::units::MG;
use kestrel::sim::{NoiseWindow, OdometerFault, Outlier, OutlierKind, TimeWindow};

/// The seeds each built-in scenario's parameters were chosen on (the
/// headline runs of `reproduce` start at the scenario's own seed and may
/// overlap them; the sensitivity study and the claim tests do not).
///
/// ```
/// let (_, seeds) = kestrel_app::scenario::TUNING_SEEDS[0];
/// assert_eq!(seeds, &[0..=7]);
/// ```
pub const TUNING_SEEDS: [(&str, &[RangeInclusive<u64>]); 5] = [
    // 000: the outlier patch, the GNSS rate, λ clamp, γ and the fade block.
    ("000", &[0..=7]),
    // 001: nothing was tuned (the paper's sigma-point parameters); the
    // f32 failure set-up was looked at on seeds 1–3.
    ("001", &[1..=3]),
    // 002: the multipath calibration against the paper's EKF row and the
    // burst cap.
    ("002", &[0..=7]),
    // 003: the fuzzy plateau (seed 3), the max-threshold sweep of the
    // tuned baseline (seeds 100–103).
    ("003", &[3..=3, 100..=103]),
    // 004: the scale factors, β, the λ clamp, the fade block (0–3), the
    // removed surge and the realistic bias model (4–11).
    ("004", &[0..=11]),
];

/// First seed of the claim tests: disjoint from every [`TUNING_SEEDS`] range.
pub const TEST_SEEDS_FROM: u64 = 1000;

/// First seed of the sensitivity study: disjoint from the tuning seeds and
/// from the tests.
pub const STUDY_SEEDS_FROM: u64 = 2000;

// The tests use fewer than 1000 seeds.
const _: () = assert!(STUDY_SEEDS_FROM >= TEST_SEEDS_FROM + 1000);

/// One way of making a scenario's free choices: a scenario whose first
/// filter is the baseline and whose last is the filter the paper favours.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// What differs, e.g. `"patch biased, GNSS 10 Hz"`.
    pub name: String,
    /// Whether this is the choice the built-in scenario makes.
    pub headline: bool,
    /// Whether the baseline is a competent one (protected or tuned as a
    /// careful engineer would) on the headline's fault: the comparisons a
    /// computed verdict rests on besides the headline.
    pub competent: bool,
    /// The scenario with this choice; filters `[baseline, …, favoured]`.
    pub scenario: Scenario,
}

/// The variants of built-in scenario `name` (none for 001, whose claim is
/// about arithmetic, not a fault).
///
/// - 000: the outlier fault (none, zero-mean ±15 m/s, biased 10 ± 5 m/s,
///   at 1 and 10 Hz; split 5 ± 10 m/s and random 5–15 m/s spikes at
///   10 Hz), each against the plain KF and the protected baselines
///   [`PROTECTED_000`]; the improved filter favoured.
/// - 002: the multipath burst sizes as capped, doubled (±30, 30, 50 m,
///   Doppler ±1.2, 1.2, 0.8 m/s), and code multipath only (no Doppler
///   errors).
/// - 003: the max-threshold baseline over threshold (0.1–3 m/s), R
///   (0.1, 0.5 m/s), fixed or windowed R, each against the fuzzy filter
///   with the same R; and sustained slips and a skid (`SUSTAINED_003`),
///   against the tuned threshold with fixed and with windowed R.
/// - 004: with and without the unmodelled scale factors, with the GNSS
///   noise surge, with a realistic accelerometer-bias model in both
///   filters.
///
/// ```
/// let v = kestrel_app::scenario::variants("000");
/// assert_eq!(v.len(), 24);
/// assert_eq!(v.iter().filter(|v| v.headline).count(), 1);
/// assert!(kestrel_app::scenario::variants("001").is_empty());
/// ```
pub fn variants(name: &str) -> Vec<Variant> {
    let Some(base) = by_name(name) else {
        return Vec::new();
    };
    match name {
        "000" => variants_000(&base),
        "002" => variants_002(&base),
        "003" => variants_003(&base),
        "004" => variants_004(&base),
        _ => Vec::new(),
    }
}

fn variant(name: impl Into<String>, headline: bool, scenario: Scenario) -> Variant {
    Variant {
        name: name.into(),
        headline,
        competent: false,
        scenario,
    }
}

/// [`variant`] with a competent baseline on the headline's fault.
fn competent(name: impl Into<String>, scenario: Scenario) -> Variant {
    Variant {
        competent: true,
        ..variant(name, false, scenario)
    }
}

/// The shape of paper 000's outlier fault on north and east velocity
/// (peak 15 m/s in each patch; the headline is `Biased`).
#[derive(Clone, Copy)]
enum Patch {
    /// No outliers.
    None,
    /// A uniform error in ±15 m/s at each fix of 350–360 s.
    ZeroMean,
    /// 10 m/s plus a uniform ±5 m/s (the scenario's).
    Biased,
    /// 5 m/s plus a uniform ±10 m/s: the same peak, split the other way.
    Split,
    /// No patch; instead 2 % of the fixes over the whole flight get a
    /// velocity error of 5–15 m/s in a random direction.
    Spikes,
}

/// The protected baselines a careful engineer gives paper 000's plain KF:
/// the library's per-component χ² / Huber inflation of R (paper 002's
/// filter) and a χ² gate, at conventional significances (0.05 and 0.01),
/// neither tuned.
pub const PROTECTED_000: [FilterKind; 2] = [
    FilterKind::IctErekf { significance: 0.05 },
    FilterKind::ChiSquareGate { significance: 0.01 },
];

/// `base` with paper 000's outlier fault made `patch` and GNSS at `rate`
/// Hz.
fn with_patch(base: &Scenario, patch: Patch, rate: f64) -> Scenario {
    let mut s = base.clone();
    let Some(g) = s.gnss.as_mut() else {
        return s;
    };
    g.rate = rate;
    for o in &mut g.outliers {
        if let OutlierKind::Patch {
            velocity_offset,
            velocity_amplitude,
            ..
        } = &mut o.kind
        {
            let peak = *velocity_offset + *velocity_amplitude;
            let (offset, amplitude) = match patch {
                Patch::Biased => (*velocity_offset, *velocity_amplitude),
                Patch::ZeroMean => (Vector3::zeros(), peak),
                Patch::Split => (peak / 3.0, peak * (2.0 / 3.0)),
                Patch::None | Patch::Spikes => (Vector3::zeros(), Vector3::zeros()),
            };
            *velocity_offset = offset;
            *velocity_amplitude = amplitude;
        }
    }
    if matches!(patch, Patch::Spikes) {
        g.outliers.push(Outlier {
            window: TimeWindow::new(0.0, 500.0),
            kind: OutlierKind::Spikes {
                probability: 0.02,
                position: (0.0, 0.0),
                velocity: (5.0, 15.0),
            },
        });
    }
    s
}

fn variants_000(base: &Scenario) -> Vec<Variant> {
    let improved = base.filters[2];
    let mut out = Vec::new();
    let shapes = [
        (Patch::None, "no patch", [1.0, 10.0].as_slice()),
        (Patch::ZeroMean, "zero-mean patch", &[1.0, 10.0]),
        (Patch::Biased, "biased patch", &[1.0, 10.0]),
        (Patch::Split, "split patch 5 ± 10 m/s", &[10.0]),
        (Patch::Spikes, "random spikes 5–15 m/s", &[10.0]),
    ];
    for (patch, name, rates) in shapes {
        for &rate in rates {
            let s = with_patch(base, patch, rate);
            let headline = matches!(patch, Patch::Biased) && rate == 10.0;
            let name = format!("{name}, GNSS {rate} Hz");
            let baselines = core::iter::once(base.filters[0]).chain(PROTECTED_000);
            for (i, baseline) in baselines.enumerate() {
                let mut v = s.clone();
                v.filters = vec![baseline, improved];
                out.push(match i {
                    0 => variant(name.clone(), headline, v),
                    _ if headline => competent(name.clone(), v),
                    _ => variant(name.clone(), false, v),
                });
            }
        }
    }
    out
}

fn variants_002(base: &Scenario) -> Vec<Variant> {
    let mut uncapped = base.clone();
    if let Some(g) = uncapped.gnss.as_mut() {
        for o in &mut g.outliers {
            // The short bursts are the first multipath process.
            if let OutlierKind::Multipath(b) = &mut o.kind
                && b.rise == 0.0
            {
                b.position *= 2.0;
                b.velocity_bias *= 2.0;
            }
        }
    }
    // Code multipath only: every velocity (Doppler) error of the
    // multipath processes removed, the position errors kept.
    let mut code_only = base.clone();
    if let Some(g) = code_only.gnss.as_mut() {
        for o in &mut g.outliers {
            match &mut o.kind {
                OutlierKind::Patch {
                    velocity_offset,
                    velocity_amplitude,
                    ..
                } => {
                    *velocity_offset = Vector3::zeros();
                    *velocity_amplitude = Vector3::zeros();
                }
                OutlierKind::Multipath(b) => {
                    b.velocity_bias = Vector3::zeros();
                    b.velocity = Vector3::zeros();
                }
                OutlierKind::Spikes { velocity, .. } => *velocity = (0.0, 0.0),
            }
        }
    }
    vec![
        variant("bursts capped (±15, 15, 25 m)", true, base.clone()),
        variant("bursts doubled (±30, 30, 50 m)", false, uncapped),
        variant("code multipath only (no Doppler errors)", false, code_only),
    ]
}

/// The threshold (m/s) of paper 003's max-threshold baseline, tuned on
/// the [`TUNING_SEEDS`] (100–103): a sweep of thresholds 0.1, 0.2, 0.3,
/// 0.5, 1, 2, 3 m/s with the scenario's R of 0.1 m/s, fixed or windowed,
/// whole-run horizontal RMS averaged over the seeds. Best with fixed R:
/// 0.3 m/s (12.04 m; 0.1: 12.08, 0.2: 12.25, 0.5: 14.30, 1: 793 with one
/// run lost, 2 and 3: kilometres), an optimum inside the grid; with
/// windowed R every threshold from 0.3 m/s up gave 11.7–11.8 m (0.1:
/// 11.5). The earlier sweep stopped at 0.5 m/s, its grid's edge.
pub const TUNED_003_THRESHOLD: f64 = 0.3;

/// The (threshold m/s, R m/s, windowed R) combinations of the 003 study's
/// baseline, each against the fuzzy filter with the same R.
const STUDY_003: [(f64, f64, bool); 13] = [
    (0.1, 0.1, false),
    (0.2, 0.1, false),
    (0.3, 0.1, false),
    (0.5, 0.1, false),
    (1.0, 0.1, false),
    (2.0, 0.1, false),
    (3.0, 0.1, false),
    (0.3, 0.1, true),
    (1.0, 0.1, true),
    (3.0, 0.1, true),
    (0.3, 0.5, false),
    (1.0, 0.5, false),
    (3.0, 0.5, false),
];

/// The sustained odometer faults of the 003 study (factor, start s,
/// length s, after the paper's faults), on the long south-east leg
/// (1900–2900 s) unless stated: slips (reading fast) of 3, 5 and 10 % and
/// a skid (reading slow) of 5 %, 100 or 300 s; the last one follows the
/// paper's three faults.
const SUSTAINED_003: [(f64, f64, f64, bool); 6] = [
    (1.03, 2500.0, 300.0, false),
    (1.05, 2500.0, 100.0, false),
    (1.05, 2500.0, 300.0, false),
    (1.10, 2500.0, 300.0, false),
    (0.95, 2500.0, 300.0, false),
    (1.05, 2500.0, 300.0, true),
];

fn variants_003(base: &Scenario) -> Vec<Variant> {
    let fuzzy = *base.filters.last().expect("003 has filters");
    let mut out: Vec<Variant> = STUDY_003
        .iter()
        .map(|&(threshold, r, windowed)| {
            let mut s = base.clone();
            s.filter.r.odometer = Some(Vector3::repeat(r));
            let baseline = FilterKind::MaxThreshold {
                threshold,
                r_window: windowed.then_some(20),
            };
            // The built-in scenario's baseline: 1 m/s with R 0.1 m/s.
            let headline = baseline == base.filters[1] && r == 0.1;
            s.filters = vec![baseline, fuzzy];
            let window = if windowed { "windowed R" } else { "fixed R" };
            let name = format!("threshold {threshold} m/s, R {r} m/s, {window}");
            // The tuned baselines of [`tuned`]: the threshold of the sweep.
            if threshold == TUNED_003_THRESHOLD && r == 0.1 {
                competent(name, s)
            } else {
                variant(name, headline, s)
            }
        })
        .collect();
    for &(factor, start, length, after) in &SUSTAINED_003 {
        let mut s = base.clone();
        if let Some(o) = s.odometer.as_mut() {
            if !after {
                o.faults.clear();
            }
            o.faults.push(OdometerFault::wheel_spin(
                TimeWindow::starting(start, length),
                factor,
            ));
        }
        let kind = if factor > 1.0 { "slip" } else { "skid" };
        let name = format!(
            "{}{kind} ×{factor} for {length} s from {start} s",
            if after { "paper's faults + " } else { "" }
        );
        for windowed in [false, true] {
            let mut v = s.clone();
            v.filters = vec![
                FilterKind::MaxThreshold {
                    threshold: TUNED_003_THRESHOLD,
                    r_window: windowed.then_some(20),
                },
                fuzzy,
            ];
            out.push(variant(name.clone(), false, v));
        }
    }
    out
}

/// The 3× GNSS noise surge of 004 (position and velocity, 1400–1550 s),
/// unreported by the receiver.
fn with_surge(s: &mut Scenario) {
    if let Some(g) = s.gnss.as_mut() {
        g.noise_windows.push(NoiseWindow {
            window: TimeWindow::new(1400.0, 1550.0),
            position_std: Some(g.position_std * 3.0),
            velocity_std: g.velocity_std.map(|v| v * 3.0),
        });
    }
}

/// The accelerometer-bias model a careful engineer gives both 004 filters:
/// the effective bias is the 100 µg bias plus up to 1 mg from the scale
/// factor on the vertical axis (1 g × 10⁻³), changing in manoeuvres, so
/// P0 1 mg and a first-order Markov bias of 1 mg, τ = 3600 s.
fn realistic_accel_bias(s: &mut Scenario) {
    s.filter.p0.accel_bias = Vector3::repeat(MG.si(1.0));
    s.filter.imu_model.accel_markov_sigma = MG.si(1.0);
    s.filter.imu_model.accel_markov_tau = 3600.0;
}

fn variants_004(base: &Scenario) -> Vec<Variant> {
    let mut no_scale = base.clone();
    no_scale.imu_errors.gyro_scale = Vector3::zeros();
    no_scale.imu_errors.accel_scale = Vector3::zeros();
    let mut surge = base.clone();
    with_surge(&mut surge);
    let mut realistic = base.clone();
    realistic_accel_bias(&mut realistic);
    let mut realistic_surge = realistic.clone();
    with_surge(&mut realistic_surge);
    vec![
        variant("scale factors, paper's bias model", true, base.clone()),
        variant("no scale factors", false, no_scale),
        variant("scale factors + GNSS surge", false, surge),
        competent("scale factors, realistic bias model", realistic),
        variant(
            "scale factors + surge, realistic bias model",
            false,
            realistic_surge,
        ),
    ]
}

/// The built-in scenario `name` with its baselines tuned as a careful
/// engineer would, where that differs from the paper's configuration
/// (`None` where the paper's baseline already models the simulated errors).
///
/// - 000: the plain KF given the outlier protection of
///   [`PROTECTED_000`] (χ² / Huber inflation of R, a χ² gate), untuned.
/// - 003: the max-threshold baseline with the threshold of a sweep on the
///   tuning seeds ([`TUNED_003_THRESHOLD`]), with fixed and with windowed
///   R (the fuzzy filter is unchanged).
/// - 004: both filters with the realistic accelerometer-bias model (P0
///   1 mg, Markov σ 1 mg, τ = 3600 s) instead of the paper's P0 of
///   10–15 µg and no process noise.
///
/// ```
/// let t = kestrel_app::scenario::tuned("004").unwrap();
/// assert!(t.filter.imu_model.has_accel_markov());
/// assert_eq!(kestrel_app::scenario::tuned("000").unwrap().filters.len(), 2);
/// assert!(kestrel_app::scenario::tuned("002").is_none());
/// ```
pub fn tuned(name: &str) -> Option<Scenario> {
    let mut s = by_name(name)?;
    match name {
        "000" => s.filters = PROTECTED_000.to_vec(),
        "003" => {
            s.filters = vec![
                FilterKind::MaxThreshold {
                    threshold: TUNED_003_THRESHOLD,
                    r_window: None,
                },
                FilterKind::MaxThreshold {
                    threshold: TUNED_003_THRESHOLD,
                    r_window: Some(20),
                },
            ];
        }
        "004" => realistic_accel_bias(&mut s),
        _ => return None,
    }
    Some(s)
}

/// `s` without its faults: no GNSS outliers or noise changes, no odometer
/// faults (outages stay: a filter must be consistent across them). What a
/// consistency (NEES) check of a baseline runs on.
///
/// ```
/// let s = kestrel_app::scenario::by_name("000").unwrap();
/// let clean = kestrel_app::scenario::fault_free(&s);
/// assert!(clean.gnss.unwrap().outliers.is_empty());
/// ```
pub fn fault_free(s: &Scenario) -> Scenario {
    let mut clean = s.clone();
    if let Some(g) = clean.gnss.as_mut() {
        g.outliers.clear();
        g.noise_windows.clear();
    }
    if let Some(o) = clean.odometer.as_mut() {
        o.faults.clear();
    }
    clean
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::v3;

    #[test]
    fn tuning_test_and_study_seeds_are_disjoint() {
        for (_, ranges) in TUNING_SEEDS {
            assert!(ranges.iter().all(|r| *r.end() < TEST_SEEDS_FROM));
        }
    }

    #[test]
    fn the_headline_variant_is_the_built_in_scenario() {
        for name in ["000", "002", "003", "004"] {
            let base = by_name(name).unwrap();
            let heads: Vec<_> = variants(name).into_iter().filter(|v| v.headline).collect();
            assert_eq!(heads.len(), 1, "{name}");
            let mut h = heads[0].scenario.clone();
            // Same data and set-up; only the filter list is trimmed.
            h.filters = base.filters.clone();
            assert_eq!(h, base, "{name}");
        }
    }

    #[test]
    fn variants_change_what_they_say() {
        let v = variants("000");
        // Three baselines per set-up: none 1 Hz, none 10 Hz, zero-mean 1 Hz.
        assert_eq!(v[6].name, "zero-mean patch, GNSS 1 Hz");
        let zero = &v[6].scenario.gnss.as_ref().unwrap().outliers[0].kind;
        assert_eq!(
            *zero,
            OutlierKind::Patch {
                position_offset: Vector3::zeros(),
                position_amplitude: Vector3::zeros(),
                velocity_offset: Vector3::zeros(),
                velocity_amplitude: v3(15.0, 15.0, 0.0),
            }
        );
        assert_eq!(v[0].scenario.gnss.as_ref().unwrap().rate, 1.0);
        let v4 = variants("004");
        assert_eq!(v4[1].scenario.imu_errors.accel_scale, Vector3::zeros());
        assert_eq!(
            v4[2].scenario.gnss.as_ref().unwrap().noise_windows[0].position_std,
            Some(v3(30.0, 30.0, 60.0))
        );
        let v2 = variants("002");
        assert_ne!(v2[0].scenario, v2[1].scenario);
        let split = v
            .iter()
            .find(|v| v.name.starts_with("split"))
            .unwrap()
            .scenario
            .gnss
            .as_ref()
            .unwrap()
            .outliers[0]
            .kind;
        assert_eq!(
            split,
            OutlierKind::Patch {
                position_offset: Vector3::zeros(),
                position_amplitude: Vector3::zeros(),
                velocity_offset: v3(5.0, 5.0, 0.0),
                velocity_amplitude: v3(10.0, 10.0, 0.0),
            }
        );
        // Code multipath only: no velocity error left in any process.
        let code = &v2[2].scenario.gnss.as_ref().unwrap().outliers;
        assert!(code.iter().all(|o| match o.kind {
            OutlierKind::Patch {
                velocity_offset,
                velocity_amplitude,
                ..
            } => velocity_offset == Vector3::zeros() && velocity_amplitude == Vector3::zeros(),
            OutlierKind::Multipath(b) => b.velocity_bias == Vector3::zeros(),
            OutlierKind::Spikes { velocity, .. } => velocity == (0.0, 0.0),
        }));
        // 003: sustained faults replace the paper's, except the last.
        let v3s = variants("003");
        let slip = v3s
            .iter()
            .find(|v| v.name.starts_with("slip ×1.05 for 300"))
            .unwrap();
        assert_eq!(slip.scenario.odometer.as_ref().unwrap().faults.len(), 1);
        let after = v3s
            .iter()
            .find(|v| v.name.starts_with("paper's faults"))
            .unwrap();
        assert_eq!(after.scenario.odometer.as_ref().unwrap().faults.len(), 4);
    }
}
