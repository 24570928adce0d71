//! The papers' claims on held-out seeds.
//!
//! Every scenario's parameters were chosen on the seeds listed in
//! `TUNING_SEEDS`; these tests run seeds from `TEST_SEEDS_FROM` (1000) on,
//! which nothing was chosen on, and assert the direction of each claim and
//! two-sided bounds (±30 %) on its size around the result documented in the
//! README (the medians of the sensitivity study, seeds 2000–2009). A
//! bound that fails means the documented result does not hold on other
//! seeds, which is a finding to report, not a tolerance to widen.
//!
//! Each ratio is the baseline's RMS over the favoured filter's, per seed;
//! the assertions are on the median over the seeds (the mean of a ratio is
//! pulled by single runs).

use kestrel_app::experiment::{run_with, RunOptions, RunSummary};
use kestrel_app::scenario::{
    by_name, fault_free, tuned, variants, FilterKind, Scenario, TEST_SEEDS_FROM,
};

/// Horizontal, vertical and 3-D velocity RMS of one run.
fn figures(s: &RunSummary) -> [f64; 3] {
    [
        s.horizontal_rms(),
        s.rms_position[2].abs(),
        s.velocity_rms(),
    ]
}

/// `figures` of `kind` on `s` for each of `seeds`, two threads.
fn runs(s: &Scenario, kind: &FilterKind, seeds: &[u64]) -> Vec<[f64; 3]> {
    let options = RunOptions::default().without_records();
    std::thread::scope(|scope| {
        let handles: Vec<_> = seeds
            .chunks(seeds.len().div_ceil(2))
            .map(|chunk| {
                let options = &options;
                scope.spawn(move || {
                    chunk
                        .iter()
                        .map(|&seed| {
                            let r = run_with(s, kind, seed, options, |_| {})
                                .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", kind.label()));
                            figures(&r)
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

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// Median over `seeds` of the per-seed ratio baseline ÷ favoured (first
/// and last filter of `s`), per figure.
fn ratio(s: &Scenario, seeds: &[u64]) -> [f64; 3] {
    let base = runs(s, &s.filters[0], seeds);
    let fav = runs(s, s.filters.last().expect("filters"), seeds);
    let r =
        core::array::from_fn(|m| median(base.iter().zip(&fav).map(|(b, f)| b[m] / f[m]).collect()));
    println!(
        "{} {} vs {}: horizontal {:.2}, vertical {:.2}, velocity {:.2}",
        s.name,
        s.filters[0].label(),
        s.filters.last().expect("filters").label(),
        r[0],
        r[1],
        r[2]
    );
    r
}

/// Asserts `value` within ±30 % of `documented`.
fn near(what: &str, value: f64, documented: f64) {
    assert!(
        value >= documented / 1.3 && value <= documented * 1.3,
        "{what}: {value:.3} against the documented {documented}"
    );
}

fn seeds(n: u64) -> Vec<u64> {
    (TEST_SEEDS_FROM..TEST_SEEDS_FROM + n).collect()
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

/// Paper 000: the improved filter beats the KF under every fault shape,
/// but the size of the win is set by the biased patch the paper does not
/// describe (documented: 13.0× horizontal with it, 2.4× with a zero-mean
/// patch).
#[test]
fn paper_000_improvement_holds_in_direction_and_its_size_follows_the_patch() {
    let s = seeds(3);
    let headline = variant("000", "biased patch, GNSS 10 Hz");
    let r = ratio(&headline, &s);
    near("000 biased patch horizontal", r[0], 13.0);
    near("000 biased patch velocity", r[2], 5.8);
    let zero_mean = ratio(&variant("000", "zero-mean patch, GNSS 10 Hz"), &s);
    near("000 zero-mean patch horizontal", zero_mean[0], 2.4);
    assert!(zero_mean.iter().all(|&v| v > 1.0), "{zero_mean:?}");
    // The baseline is consistent on the fault-free flight.
    let b = by_name("000").expect("built-in");
    let kf_nees = nees(&b, &b.filters[0], TEST_SEEDS_FROM);
    assert!((2.0..4.5).contains(&kf_nees), "KF NEES {kf_nees}");
}

/// Paper 002: the ICT-EREKF beats the EKF on urban multipath (documented:
/// horizontal 1.43×, vertical 1.35×, velocity 2.33×), and the EKF's error
/// has the paper's size (3-D 8.66 m, 0.164 m/s) within 25 %.
#[test]
fn paper_002_robust_filter_beats_the_ekf_on_held_out_multipath() {
    let sc = by_name("002").expect("built-in");
    assert!(matches!(sc.filters[1], FilterKind::IctErekf { .. }));
    let s = seeds(4);
    let r = ratio(&sc, &s);
    near("002 horizontal", r[0], 1.43);
    near("002 vertical", r[1], 1.35);
    near("002 velocity", r[2], 2.33);
    let ekf = runs(&sc, &sc.filters[0], &s[..2]);
    for e in ekf {
        let position = (e[0].powi(2) + e[1].powi(2)).sqrt();
        assert!((position / 8.66 - 1.0).abs() < 0.25, "{e:?}");
        assert!((e[2] / 0.164 - 1.0).abs() < 0.25, "{e:?}");
    }
}

/// Paper 003: the fuzzy filter beats the paper's 1 m/s max-threshold
/// baseline (documented 3.7× horizontal), but not the baseline given the
/// same windowed R (documented 0.98×).
#[test]
fn paper_003_fuzzy_beats_the_papers_baseline_but_not_one_with_windowed_r() {
    let s = seeds(2);
    let paper = ratio(&variant("003", "threshold 1 m/s, R 0.1 m/s, fixed R"), &s);
    near("003 paper baseline horizontal", paper[0], 3.7);
    assert!(paper.iter().all(|&v| v > 1.0), "{paper:?}");
    let windowed = ratio(
        &variant("003", "threshold 1 m/s, R 0.1 m/s, windowed R"),
        &s,
    );
    near("003 windowed-R baseline horizontal", windowed[0], 0.98);
    // Neither is better by more than 10 %.
    assert!((windowed[0] - 1.0).abs() < 0.1, "{windowed:?}");
}

/// Paper 004: as configured in the paper the fading KF wins (documented
/// 1.17× horizontal, 4.0× vertical), but that KF is over-confident; with
/// the realistic bias model the KF is consistent and wins position
/// (documented 0.84× horizontal), the fading KF keeping velocity (1.25×).
#[test]
fn paper_004_fading_wins_only_against_the_papers_overconfident_kf() {
    let s = seeds(3);
    let sc = by_name("004").expect("built-in");
    let paper = ratio(&sc, &s);
    near("004 paper horizontal", paper[0], 1.17);
    near("004 paper vertical", paper[1], 4.0);
    let t = tuned("004").expect("004 has a tuned configuration");
    let tuned_ratio = ratio(&t, &s);
    near("004 tuned horizontal", tuned_ratio[0], 0.84);
    near("004 tuned velocity", tuned_ratio[2], 1.25);
    assert!(
        tuned_ratio[0] < 1.0 && tuned_ratio[1] < 1.0,
        "{tuned_ratio:?}"
    );
    let (paper_nees, tuned_nees) = (
        nees(&sc, &sc.filters[0], TEST_SEEDS_FROM),
        nees(&t, &t.filters[0], TEST_SEEDS_FROM),
    );
    println!("004 KF position NEES: paper's configuration {paper_nees:.1}, tuned {tuned_nees:.1}");
    assert!(paper_nees > 20.0, "{paper_nees}");
    assert!((1.5..4.5).contains(&tuned_nees), "{tuned_nees}");
}
