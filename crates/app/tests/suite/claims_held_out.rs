//! The papers' claims, and the comparisons their verdicts rest on, on
//! held-out seeds.
//!
//! Every scenario's parameters were chosen on the seeds listed in
//! `TUNING_SEEDS`; these tests run the 20 seeds 1000–1019, which nothing
//! was chosen on. Each ratio is the baseline's RMS over the favoured
//! filter's, per seed, summarised by its median over the seeds.
//!
//! **Bands.** Each band is the median `m` and interquartile range `IQR` of
//! the same per-seed ratio measured on the study's seeds 2000–2019
//! (`kestrel reproduce <paper> --study-runs 20`, seeds the tests never run),
//! widened to `m ± 3·√2·0.93·IQR/√20` (= `m ± 0.88·IQR`): three standard
//! errors of the difference of two medians of 20 seeds, the standard error
//! of one median being about `1.25·σ/√n` with `σ ≈ IQR/1.35`. A band of
//! `m ± 3·IQR` would be about 3.4 times wider and admit 002's null case
//! (1.10×). Each band is shown to reject its named null case. A band that
//! fails means the documented result does not hold on other seeds: a
//! finding to report, not a tolerance to widen.
//!
//! **Comparisons.** The verdicts read a comparison with
//! [`Comparison::of`](kestrel_app::reproduce::Comparison::of) (better when
//! the first quartile of the per-seed ratio exceeds 1, worse when the third
//! is below 1); the readings they rest on are asserted on these seeds.
//!
//! Release only (about two minutes on one core): `cargo test --release -p
//! kestrel-app --test suite claims_held_out`. The main job (`reproduce
//! all`) computes the same comparisons on the study seeds.

use kestrel_app::experiment::{run_together, run_with, RunOptions, RunSummary};
use kestrel_app::reproduce::{Comparison, Quartiles};
use kestrel_app::scenario::{
    by_name, fault_free, tuned, variants, FilterKind, Scenario, TEST_SEEDS_FROM,
    TUNED_003_THRESHOLD,
};

/// Seeds per test.
const SEEDS: u64 = 20;

/// Horizontal, vertical and 3-D velocity RMS of one run.
fn figures(s: &RunSummary) -> [f64; 3] {
    [
        s.horizontal_rms(),
        s.rms_position[2].abs(),
        s.velocity_rms(),
    ]
}

/// `figures` of every filter of `s` (sharing one simulation) for each of
/// the test seeds, two threads: `[seed][filter]`.
fn runs(s: &Scenario) -> Vec<Vec<[f64; 3]>> {
    let options = RunOptions::default().without_records();
    let seeds: Vec<u64> = (TEST_SEEDS_FROM..TEST_SEEDS_FROM + SEEDS).collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = seeds
            .chunks(seeds.len().div_ceil(2))
            .map(|chunk| {
                let options = &options;
                scope.spawn(move || {
                    chunk
                        .iter()
                        .map(|&seed| {
                            run_together(s, &s.filters, seed, options, |_, _| {})
                                .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", s.name))
                                .into_iter()
                                .map(|r| figures(&r.unwrap_or_else(|e| panic!("seed {seed}: {e}"))))
                                .collect::<Vec<_>>()
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a run thread"))
            .collect()
    })
}

/// Quartiles of the per-seed ratio filter `base` ÷ filter `fav` in figure
/// `m`, printed.
fn ratio(what: &str, runs: &[Vec<[f64; 3]>], base: usize, fav: usize, m: usize) -> Quartiles {
    let r: Vec<f64> = runs.iter().map(|f| f[base][m] / f[fav][m]).collect();
    let q = Quartiles::of(&r).expect("ratios");
    println!("{what}: {q:.3}, {}", Comparison::of(&q));
    q
}

/// The band around a study median `m` with interquartile range `iqr`
/// (module documentation).
fn band(m: f64, iqr: f64) -> (f64, f64) {
    let half = 3.0 * 2f64.sqrt() * 0.93 * iqr / (SEEDS as f64).sqrt();
    (m - half, m + half)
}

/// Asserts the median of `q` inside the band of (`m`, `iqr`).
fn within(what: &str, q: &Quartiles, m: f64, iqr: f64) {
    let (lo, hi) = band(m, iqr);
    assert!(
        (lo..=hi).contains(&q.median),
        "{what}: median {:.3} outside [{lo:.3}, {hi:.3}] (study {m} ± IQR {iqr})",
        q.median
    );
}

fn variant(name: &str, which: &str) -> Scenario {
    variants(name)
        .into_iter()
        .find(|v| v.name == which)
        .unwrap_or_else(|| panic!("{name} has no variant {which}"))
        .scenario
}

/// Mean position NEES of `kind` on the fault-free `s` after the first 10 %.
fn nees(s: &Scenario, kind: &FilterKind, seed: u64) -> f64 {
    let clean = fault_free(s);
    let start = 0.1 * clean.trajectory().expect("trajectory").duration();
    let (mut sum, mut n) = (0.0, 0usize);
    run_with(&clean, kind, seed, &RunOptions::default(), |r| {
        if let (true, Some(v)) = (r.time >= start, r.position_nees) {
            sum += v;
            n += 1;
        }
    })
    .expect("run");
    assert!(n > 0);
    sum / n as f64
}

/// The bands reject their named null cases: 002's at a true ratio of
/// 1.10 (horizontal and velocity), 000's headline band a ratio of 2 (the
/// study's median without the outlier patch).
#[test]
fn each_band_rejects_its_null_case() {
    let (lo, hi) = band(1.43, 0.24);
    assert!(!(lo..=hi).contains(&1.10), "002 horizontal [{lo}, {hi}]");
    let (lo, hi) = band(2.30, 0.36);
    assert!(!(lo..=hi).contains(&1.10), "002 velocity [{lo}, {hi}]");
    let (lo, hi) = band(13.03, 1.73);
    assert!(!(lo..=hi).contains(&2.00), "000 headline [{lo}, {hi}]");
    // A band of ±3 IQR would admit 002's null case.
    let wide = |m: f64, iqr: f64| (m - 3.0 * iqr)..=(m + 3.0 * iqr);
    assert!(wide(1.43, 0.24).contains(&1.10));
}

/// Paper 000: the improved filter beats the plain KF (study: 13.03×
/// horizontal, IQR 1.73; velocity 6.14×, IQR 1.15) and a KF with a χ²
/// gate (1.96×, IQR 0.63), but not the KF with the library's χ²/Huber
/// inflation (ICT-EREKF, α = 0.05: 1.00×, IQR 0.09, no difference), the
/// comparison its verdict rests on. Null case: without the outlier patch
/// the ratio over the KF is about 2 and outside the headline band.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "release only: cargo test --release -p kestrel-app --test suite claims_held_out"
)]
fn paper_000_improvement_is_outlier_protection() {
    let base = by_name("000").expect("built-in");
    let improved = base.filters[2];
    let mut s = variant("000", "biased patch, GNSS 10 Hz");
    let [ict, gate] = kestrel_app::scenario::PROTECTED_000;
    s.filters = vec![base.filters[0], ict, gate, improved];
    let r = runs(&s);
    let kf = ratio("000 KF horizontal", &r, 0, 3, 0);
    within("000 KF horizontal", &kf, 13.03, 1.73);
    within(
        "000 KF velocity",
        &ratio("000 KF velocity", &r, 0, 3, 2),
        6.14,
        1.15,
    );
    let q = ratio("000 ICT-EREKF horizontal", &r, 1, 3, 0);
    within("000 ICT-EREKF horizontal", &q, 1.00, 0.09);
    assert_eq!(Comparison::of(&q), Comparison::NoDifference);
    let q = ratio("000 χ² gate horizontal", &r, 2, 3, 0);
    within("000 χ² gate horizontal", &q, 1.96, 0.63);
    assert_eq!(Comparison::of(&q), Comparison::Better);
    // The null case: no patch.
    let mut none = variant("000", "no patch, GNSS 10 Hz");
    none.filters = vec![base.filters[0], improved];
    let q = ratio("000 no patch horizontal", &runs(&none), 0, 1, 0);
    let (lo, hi) = band(13.03, 1.73);
    assert!(!(lo..=hi).contains(&q.median), "{q:?}");
    // The baseline is consistent on the fault-free flight.
    let kf_nees = nees(&base, &base.filters[0], TEST_SEEDS_FROM);
    assert!((2.0..4.5).contains(&kf_nees), "KF NEES {kf_nees}");
}

/// Paper 002: the ICT-EREKF beats the EKF on urban multipath (study:
/// horizontal 1.43×, IQR 0.24; velocity 2.30×, IQR 0.36; vertical better),
/// and the EKF's error has the paper's size (3-D 8.66 m, 0.164 m/s) within
/// 25 %. Null case: a true ratio of 1.10 ([`each_band_rejects_its_null_case`]).
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "release only: cargo test --release -p kestrel-app --test suite claims_held_out"
)]
fn paper_002_robust_filter_beats_the_ekf_on_held_out_multipath() {
    let sc = by_name("002").expect("built-in");
    assert!(matches!(sc.filters[1], FilterKind::IctErekf { .. }));
    let r = runs(&sc);
    within(
        "002 horizontal",
        &ratio("002 horizontal", &r, 0, 1, 0),
        1.43,
        0.24,
    );
    within(
        "002 velocity",
        &ratio("002 velocity", &r, 0, 1, 2),
        2.30,
        0.36,
    );
    let v = ratio("002 vertical", &r, 0, 1, 1);
    assert_eq!(Comparison::of(&v), Comparison::Better);
    for e in &r[..2] {
        let e = e[0];
        let position = (e[0].powi(2) + e[1].powi(2)).sqrt();
        assert!((position / 8.66 - 1.0).abs() < 0.25, "{e:?}");
        assert!((e[2] / 0.164 - 1.0).abs() < 0.25, "{e:?}");
    }
}

/// Paper 003: the fuzzy filter beats the scenario's 1 m/s max-threshold
/// baseline (study: 5.44×, IQR 2.21; a bimodal ratio, 1.2 to 1000 per
/// seed) and the tuned 0.3 m/s threshold with fixed R (1.13×, IQR 0.37),
/// but not the tuned threshold given the same windowed R (1.00×, IQR
/// 0.07), the comparison its verdict rests on. Finding: that comparison
/// reads no difference on the study seeds (1.00 [0.96, 1.03]) but worse
/// on these (0.98 [0.965, 0.998]), so "partly reproduced" and "not
/// reproduced against a competent baseline" are decided by the seeds;
/// what holds on both, and is asserted, is that the fuzzy filter is not
/// better than the windowed-R baseline.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "release only: cargo test --release -p kestrel-app --test suite claims_held_out"
)]
fn paper_003_fuzzy_beats_the_papers_baseline_but_not_one_with_windowed_r() {
    let mut s = by_name("003").expect("built-in");
    let fuzzy = *s.filters.last().expect("filters");
    let tuned = |r_window| FilterKind::MaxThreshold {
        threshold: TUNED_003_THRESHOLD,
        r_window,
    };
    s.filters = vec![s.filters[1], tuned(None), tuned(Some(20)), fuzzy];
    let r = runs(&s);
    within(
        "003 1 m/s horizontal",
        &ratio("003 1 m/s horizontal", &r, 0, 3, 0),
        5.44,
        2.21,
    );
    within(
        "003 tuned horizontal",
        &ratio("003 tuned horizontal", &r, 1, 3, 0),
        1.13,
        0.37,
    );
    let q = ratio("003 tuned windowed-R horizontal", &r, 2, 3, 0);
    within("003 tuned windowed-R horizontal", &q, 1.00, 0.07);
    assert_ne!(Comparison::of(&q), Comparison::Better);
}

/// Paper 004: as configured in the paper the fading KF wins (study: 1.20×
/// horizontal, IQR 0.10; vertical 3.95×, IQR 0.81), but that KF is
/// over-confident; with the realistic bias model the KF is consistent and
/// wins position (0.85×, IQR 0.06, worse for the fading KF: the verdict's
/// comparison), the fading KF keeping velocity (1.23×, IQR 0.05).
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "release only: cargo test --release -p kestrel-app --test suite claims_held_out"
)]
fn paper_004_fading_wins_only_against_the_papers_overconfident_kf() {
    let sc = by_name("004").expect("built-in");
    let r = runs(&sc);
    within(
        "004 paper horizontal",
        &ratio("004 paper horizontal", &r, 0, 1, 0),
        1.20,
        0.10,
    );
    within(
        "004 paper vertical",
        &ratio("004 paper vertical", &r, 0, 1, 1),
        3.95,
        0.81,
    );
    let t = tuned("004").expect("004 has a tuned configuration");
    let r = runs(&t);
    let q = ratio("004 tuned horizontal", &r, 0, 1, 0);
    within("004 tuned horizontal", &q, 0.85, 0.06);
    assert_eq!(Comparison::of(&q), Comparison::Worse);
    within(
        "004 tuned velocity",
        &ratio("004 tuned velocity", &r, 0, 1, 2),
        1.23,
        0.05,
    );
    let (paper_nees, tuned_nees) = (
        nees(&sc, &sc.filters[0], TEST_SEEDS_FROM),
        nees(&t, &t.filters[0], TEST_SEEDS_FROM),
    );
    println!("004 KF position NEES: paper's configuration {paper_nees:.1}, tuned {tuned_nees:.1}");
    assert!(paper_nees > 20.0, "{paper_nees}");
    assert!((1.5..4.5).contains(&tuned_nees), "{tuned_nees}");
}
