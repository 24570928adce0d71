//! `run_together`: the filters of a scenario on one shared simulation give
//! exactly what each gives alone with `run_with`: summaries, every record,
//! the same errors for kinds that cannot run, and the same failures when
//! the filters diverge.

use kestrel::nav::nalgebra::Vector3;
use kestrel_app::experiment::{
    run_together, run_with, EpochRecord, RunError, RunOptions, RunSummary,
};
use kestrel_app::scenario::{builtin, by_name, FilterKind, MeasurementNoise, Scenario};

/// `kind` alone: its summary or error, and its records.
fn alone(
    s: &Scenario,
    kind: &FilterKind,
    seed: u64,
    opts: &RunOptions,
) -> (Result<RunSummary, RunError>, Vec<EpochRecord>) {
    let mut records = Vec::new();
    let r = run_with(s, kind, seed, opts, |e| records.push(*e));
    (r, records)
}

/// `kinds` together: their summaries or errors, and their records.
fn together(
    s: &Scenario,
    kinds: &[FilterKind],
    seed: u64,
    opts: &RunOptions,
) -> Vec<(Result<RunSummary, RunError>, Vec<EpochRecord>)> {
    let mut records = vec![Vec::new(); kinds.len()];
    let results = run_together(s, kinds, seed, opts, |i, e| records[i].push(*e)).unwrap();
    assert_eq!(results.len(), kinds.len());
    results.into_iter().zip(records).collect()
}

#[test]
fn every_scenario_together_equals_each_filter_alone() {
    // A kind of another paper (refused by every scenario but 003) and one
    // with an invalid parameter ride along.
    let foreign = FilterKind::MaxThreshold {
        threshold: 1.0,
        r_window: None,
    };
    let invalid = FilterKind::IctErekf { significance: 0.5 };
    let opts = RunOptions::default().with_duration(40.0);
    for s in builtin() {
        let mut kinds = s.filters.clone();
        kinds.extend([foreign, invalid]);
        let all = together(&s, &kinds, 31, &opts);
        for (kind, (result, records)) in kinds.iter().zip(all) {
            let (expected, expected_records) = alone(&s, kind, 31, &opts);
            assert_eq!(result, expected, "{} {}", s.name, kind.label());
            assert_eq!(records, expected_records, "{} {}", s.name, kind.label());
            if s.filters.contains(kind) {
                assert!(!records.is_empty(), "{} {}", s.name, kind.label());
            }
        }
    }
}

#[test]
fn filters_that_fail_mid_run_fail_as_they_do_alone() {
    for name in ["000", "001"] {
        let mut s = by_name(name).unwrap();
        // A NaN position variance: every filter fails at its first GNSS
        // update, after the records of the samples before it.
        s.filter.r = MeasurementNoise::gnss(Vector3::repeat(f64::NAN), Vector3::repeat(0.3));
        let opts = RunOptions::default().with_duration(5.0);
        let all = together(&s, &s.filters, 2, &opts);
        for (kind, (result, records)) in s.filters.iter().zip(all) {
            let (expected, expected_records) = alone(&s, kind, 2, &opts);
            assert!(matches!(result, Err(RunError::Filter { .. })), "{result:?}");
            assert_eq!(result, expected);
            assert_eq!(records, expected_records);
        }
    }
}

#[test]
fn a_simulation_that_cannot_be_built_is_the_call_s_error() {
    let s = by_name("002").unwrap();
    let opts = RunOptions::default().with_imu_rate(1e9);
    let e = run_together(&s, &s.filters, 1, &opts, |_, _| {}).unwrap_err();
    assert!(matches!(e, RunError::TooLong { .. }));
    assert_eq!(Err(e), run_with(&s, &s.filters[0], 1, &opts, |_| {}));
    // No kinds: nothing to run, nothing returned.
    let none = run_together(
        &s,
        &[],
        1,
        &RunOptions::default().with_duration(1.0),
        |_, _| {},
    );
    assert_eq!(none.unwrap(), Vec::new());
}
