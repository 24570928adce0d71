//! The reproduction's Monte Carlo and consistency check run the filters of
//! a seed on one shared simulation: their results must be exactly what one
//! filter at a time gives, run by run and in the same order of summation.

use kestrel_app::experiment::{run_with, RunOptions};
use kestrel_app::progress::Silent;
use kestrel_app::reproduce::{
    nees_rows, run_monte_carlo, Anees, MonteCarloPlan, Window, WindowProbe,
};
use kestrel_app::scenario::{by_name, fault_free};

#[test]
fn the_monte_carlo_equals_one_filter_at_a_time() {
    let s = by_name("000").unwrap();
    let plan = MonteCarloPlan {
        runs: 3,
        seed: 40,
        threads: 2,
        duration: Some(30.0),
    };
    let windows = [Window {
        start: 5.0,
        end: 20.0,
    }];
    let outcomes = run_monte_carlo(&s, &plan, &windows, &mut Silent).unwrap();
    assert_eq!(outcomes.len(), s.filters.len());
    let options = RunOptions::default().with_duration(30.0);
    for (kind, outcome) in s.filters.iter().zip(&outcomes) {
        assert_eq!(outcome.label, kind.label());
        assert_eq!(outcome.runs.len(), 3);
        for (r, run) in outcome.runs.iter().enumerate() {
            let mut probe = WindowProbe::new(&windows);
            let mut records = Vec::new();
            let summary = run_with(&s, kind, 40 + r as u64, &options, |e| {
                probe.add(e);
                records.push(*e);
            })
            .unwrap();
            let (got, errors) = run.as_ref().unwrap();
            assert_eq!(got, &summary, "{} run {r}", kind.label());
            assert_eq!(errors, &probe.finish(), "{} run {r}", kind.label());
            if r == 0 {
                assert_eq!(outcome.records, records, "{}", kind.label());
            }
        }
    }
}

#[test]
fn the_consistency_check_equals_one_filter_at_a_time() {
    let s = by_name("004").unwrap();
    let duration = 60.0;
    let rows = nees_rows(
        &[("", &s), (" (again)", &s)],
        5..8,
        2,
        Some(duration),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(rows.len(), 2 * s.filters.len());
    let clean = fault_free(&s);
    let options = RunOptions::default()
        .with_duration(duration)
        .without_records();
    let start = duration * 0.1;
    for (kind, row) in s.filters.iter().cycle().zip(&rows) {
        // The definition: per run, the NEES at its epochs after the
        // settling share; averaged over the runs epoch by epoch.
        let runs: Vec<Vec<f64>> = (5..8)
            .map(|seed| {
                let mut nees = Vec::new();
                run_with(&clean, kind, seed, &options, |r| {
                    if r.time >= start {
                        nees.push(r.position_nees.unwrap());
                    }
                })
                .unwrap();
                nees
            })
            .collect();
        assert!(row.label.starts_with(kind.label()), "{}", row.label);
        assert!(!runs[0].is_empty());
        assert_eq!(row.anees, Anees::of(&runs, 3), "{}", row.label);
        assert_eq!(row.anees.runs, 3);
        assert_eq!(row.anees.epochs, runs[0].len());
        assert_eq!((row.failed, row.completed), (0, 3));
    }
}

fn plan(runs: usize, threads: usize, duration: f64) -> MonteCarloPlan {
    MonteCarloPlan {
        runs,
        seed: 7,
        threads,
        duration: Some(duration),
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let s = by_name("002").unwrap();
    let w = [Window {
        start: 5.0,
        end: 15.0,
    }];
    let one = run_monte_carlo(&s, &plan(3, 1, 20.0), &w, &mut Silent).unwrap();
    let two = run_monte_carlo(&s, &plan(3, 2, 20.0), &w, &mut Silent).unwrap();
    assert_eq!(one.len(), s.filters.len());
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(a.label, b.label);
        assert_eq!(a.runs, b.runs);
        assert_eq!(a.records, b.records);
        assert_eq!(a.runs.len(), 3);
        assert_eq!(a.records.len(), 20, "run 0 keeps its 1 Hz records");
    }
    // Different runs see different noise.
    let s0 = one[0].runs[0].as_ref().unwrap().0;
    let s1 = one[0].runs[1].as_ref().unwrap().0;
    assert_ne!(s0.data_digest, s1.data_digest);
}
