//! The accuracy the reproductions of papers 000 and 004 must show, as Monte
//! Carlo means of per-run RMS over a few seeds of the full built-in
//! scenarios (the events that matter span the whole flight).

use kestrel_nav::experiment::{run_with, EpochRecord, RunOptions};
use kestrel_nav::scenario::{by_name, FilterKind, Scenario};

/// Mean horizontal position RMS (m) and 3-D velocity RMS (m/s) of `kind`
/// over `seeds`, printing each run.
fn mean_rms(scenario: &Scenario, kind: &FilterKind, seeds: &[u64]) -> (f64, f64) {
    let options = RunOptions::default().without_records();
    let (mut pos, mut vel) = (0.0, 0.0);
    for &seed in seeds {
        let s = run_with(scenario, kind, seed, &options, |_| {}).expect("run");
        println!(
            "{} {:>18} seed {seed}: pos {:.3} {:.3} {:.3} m, vel {:.4} {:.4} {:.4} m/s",
            scenario.name,
            kind.label(),
            s.rms_position[0],
            s.rms_position[1],
            s.rms_position[2],
            s.rms_velocity[0],
            s.rms_velocity[1],
            s.rms_velocity[2],
        );
        pos += s.horizontal_rms();
        vel += s.velocity_rms();
    }
    let n = seeds.len() as f64;
    (pos / n, vel / n)
}

#[test]
fn paper_000_improved_adaptive_beats_the_standard_kf_3x_in_position_4x_in_velocity() {
    let sc = by_name("000").expect("built-in");
    let seeds = [0, 1, 2];
    let [kf, sh, improved] = [0, 1, 2].map(|i| mean_rms(&sc, &sc.filters[i], &seeds));
    assert!(matches!(sc.filters[0], FilterKind::Standard));
    assert!(matches!(sc.filters[1], FilterKind::SageHusaFading { .. }));
    assert!(matches!(sc.filters[2], FilterKind::ImprovedAdaptive { .. }));
    println!("000 means: KF {kf:?}, SH+fading {sh:?}, improved {improved:?}");
    assert!(kf.0 >= 3.0 * improved.0, "position: {kf:?} vs {improved:?}");
    assert!(kf.1 >= 4.0 * improved.1, "velocity: {kf:?} vs {improved:?}");
    assert!(improved.1 < sh.1, "velocity: {improved:?} vs {sh:?}");
}

/// Sums of squared errors of one filter over a time window.
#[derive(Default, Debug, Clone, Copy)]
struct Window {
    position: f64,
    velocity: f64,
    epochs: usize,
}

impl Window {
    fn add(&mut self, r: &EpochRecord) {
        self.position += r.position.norm_squared();
        self.velocity += r.velocity.norm_squared();
        self.epochs += 1;
    }

    /// (3-D position RMS, 3-D velocity RMS).
    fn rms(&self) -> (f64, f64) {
        let n = self.epochs as f64;
        ((self.position / n).sqrt(), (self.velocity / n).sqrt())
    }
}

/// Mean over `seeds` of the whole-run 3-D position and velocity RMS and of
/// the same in the climb-out (200–400 s) and the hard turn (1700–1800 s).
fn runs_004(scenario: &Scenario, kind: &FilterKind, seeds: &[u64]) -> [(f64, f64); 3] {
    let options = RunOptions::default().without_records();
    let mut sums = [(0.0, 0.0); 3];
    for &seed in seeds {
        let mut windows = [Window::default(); 3];
        run_with(scenario, kind, seed, &options, |r| {
            windows[0].add(r);
            if r.time > 200.0 && r.time <= 400.0 {
                windows[1].add(r);
            }
            if r.time > 1700.0 && r.time <= 1800.0 {
                windows[2].add(r);
            }
        })
        .expect("run");
        for (sum, w) in sums.iter_mut().zip(windows) {
            let (p, v) = w.rms();
            sum.0 += p / seeds.len() as f64;
            sum.1 += v / seeds.len() as f64;
        }
        let [all, climb, turn] = windows.map(|w| w.rms());
        println!(
            "004 {:>10} seed {seed}: all {all:.3?}, 200-400 s {climb:.3?}, 1700-1800 s {turn:.3?} (m, m/s)",
            kind.label()
        );
    }
    sums
}

#[test]
fn paper_004_fading_kf_beats_the_conventional_kf_where_the_model_is_wrong() {
    let sc = by_name("004").expect("built-in");
    assert!(matches!(sc.filters[0], FilterKind::Standard));
    assert!(matches!(
        sc.filters[1],
        FilterKind::StrongTrackingFading { .. }
    ));
    let seeds = [0, 1, 2];
    let kf = runs_004(&sc, &sc.filters[0], &seeds);
    let fading = runs_004(&sc, &sc.filters[1], &seeds);
    println!("004 means (all, climb-out, hard turn): KF {kf:.3?}, fading {fading:.3?}");
    // Whole flight: position and velocity RMS no worse than the KF's.
    assert!(fading[0].0 <= kf[0].0, "position: {fading:?} vs {kf:?}");
    assert!(fading[0].1 <= kf[0].1, "velocity: {fading:?} vs {kf:?}");
    // The events: the unmodelled scale factors after the take-off climb
    // and in the 5°/s turn; the fading filter halves the KF's error there.
    assert!(
        2.0 * fading[1].0 <= kf[1].0,
        "climb-out position: {fading:?} vs {kf:?}"
    );
    assert!(
        2.0 * fading[2].1 <= kf[2].1,
        "hard-turn velocity: {fading:?} vs {kf:?}"
    );
}
