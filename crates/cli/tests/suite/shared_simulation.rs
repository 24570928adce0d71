//! The reproduction's Monte Carlo and consistency check run the filters of
//! a seed on one shared simulation: their results must be exactly what one
//! filter at a time gives, run by run and in the same order of summation.

use kestrel::nav::experiment::{run_with, RunOptions};
use kestrel::nav::scenario::{by_name, fault_free};
use kestrel_cli::plot::chi2_quantile;
use kestrel_cli::reproduce::{nees_rows, run_monte_carlo, MonteCarloPlan, Window, WindowProbe};

#[test]
fn the_monte_carlo_equals_one_filter_at_a_time() {
    let s = by_name("000").unwrap();
    let plan = MonteCarloPlan {
        runs: 3,
        seed: 40,
        threads: 2,
        duration: Some(30.0),
        progress: false,
    };
    let windows = [Window {
        start: 5.0,
        end: 20.0,
    }];
    let outcomes = run_monte_carlo(&s, &plan, &windows).unwrap();
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
    let rows = nees_rows(&[("", &s), (" (again)", &s)], 5..8, 2, Some(duration)).unwrap();
    assert_eq!(rows.len(), 2 * s.filters.len());
    let (lo, hi) = (
        chi2_quantile(3, 0.025).unwrap(),
        chi2_quantile(3, 0.975).unwrap(),
    );
    let clean = fault_free(&s);
    let options = RunOptions::default()
        .with_duration(duration)
        .without_records();
    let start = duration * 0.1;
    for (kind, row) in s.filters.iter().cycle().zip(&rows) {
        // The definition: per run, the sum over its epochs after the
        // settling share; then over the runs in seed order.
        let (mut sum, mut inside, mut epochs) = (0.0, 0usize, 0usize);
        for seed in 5..8 {
            let (mut rs, mut ri, mut re) = (0.0, 0usize, 0usize);
            run_with(&clean, kind, seed, &options, |r| {
                if let (true, Some(v)) = (r.time >= start, r.position_nees) {
                    rs += v;
                    re += 1;
                    ri += usize::from(v >= lo && v <= hi);
                }
            })
            .unwrap();
            (sum, inside, epochs) = (sum + rs, inside + ri, epochs + re);
        }
        assert!(row.label.starts_with(kind.label()), "{}", row.label);
        assert!(epochs > 0);
        assert_eq!(row.epochs, epochs, "{}", row.label);
        assert_eq!(row.mean, Some(sum / epochs as f64), "{}", row.label);
        assert_eq!(
            row.inside,
            Some(inside as f64 / epochs as f64),
            "{}",
            row.label
        );
        assert_eq!(row.failed, 0);
    }
}
