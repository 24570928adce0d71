//! The health monitor ([`Health`](kestrel_app::experiment::Health)) on the
//! papers' scenarios: a runaway is reported, fault-free data are not.

use kestrel_app::experiment::{run, run_together, HealthCheck, HealthEventKind, RunOptions};
use kestrel_app::reproduce::{Anees, Reading};
use kestrel_app::scenario::{by_name, fault_free, tuned, FadeBlock, FilterKind, Scenario};

/// Scenario 002's drive with the improved adaptive filter's whole-state
/// fade (γ = 1, λ ≤ 10: the defaults of a `process` configuration) runs
/// away; the monitor raises its alarm within 60 s of the onset (the first
/// update with a position error above 50 m) and the run ends diverged.
/// Seeds 1000–1004, the first 300 s.
#[test]
fn a_runaway_raises_the_alarm_within_60_s() {
    let mut s = by_name("002").unwrap();
    s.filters = vec![FilterKind::ImprovedAdaptive {
        forgetting: 0.97,
        reserve: 1.0,
        lambda_max: 10.0,
        significance: 0.05,
        fade_states: FadeBlock::All,
    }];
    let options = RunOptions::default().with_duration(300.0);
    for seed in 1000..1005 {
        let r = run(&s, &s.filters[0], seed, &options).unwrap();
        let onset = r
            .records
            .iter()
            .find(|e| e.position.norm() > 50.0)
            .map(|e| e.time)
            .expect("the filter runs away");
        let h = r.summary.health;
        let first = h.first_alarm.expect("an alarm");
        println!("seed {seed}: onset {onset} s, {first}");
        assert_eq!(first.kind, HealthEventKind::Alarm);
        assert!(
            matches!(first.check, HealthCheck::Innovations { rows: 6, .. })
                || first.check == HealthCheck::PositionNees
        );
        assert!(first.time <= onset + 60.0, "seed {seed}");
        assert!(h.diverged(), "seed {seed}");
    }
}

/// The monitor's false alarms on fault-free data (goal: none): every filter
/// of scenarios 000, 002 and 003 (and 003's tuned baselines) and both
/// tuned filters of 004 without the unmodelled scale factors, on the
/// fault-free form, seeds 4000–4039 (used for nothing else: the monitor's
/// window, run length and significance were looked at on seeds 500–519,
/// and its NEES bound was raised after one alarm in 40 runs of 000's KF on
/// seeds 1000–1039, see `kestrel_app::experiment::Health`). The innovation
/// monitor raises no alarm on any filter; the NEES monitor none on the
/// filters the consistency rule ([`Anees`]) reads consistent or
/// conservative over these 40 runs. Every count is printed.
///
/// Release only (about two minutes): `cargo test --release -p kestrel-app
/// --test suite health`.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "release only: cargo test --release -p kestrel-app --test suite health"
)]
fn no_false_alarm_on_forty_fault_free_seeds() {
    let mut no_scale = tuned("004").unwrap();
    no_scale.imu_errors.gyro_scale *= 0.0;
    no_scale.imu_errors.accel_scale *= 0.0;
    let sets: Vec<(&str, Scenario)> = vec![
        ("000", by_name("000").unwrap()),
        ("002", by_name("002").unwrap()),
        ("003", by_name("003").unwrap()),
        ("003 tuned", tuned("003").unwrap()),
        ("004 tuned, no scale factors", no_scale),
    ];
    let seeds: Vec<u64> = (4000..4040).collect();
    let options = RunOptions::default().without_records();
    for (name, s) in &sets {
        let clean = fault_free(s);
        let start = 0.1 * clean.trajectory().unwrap().duration();
        // Per seed, per filter: (innovation alarms, NEES alarms, NEES after
        // the settling share).
        let runs: Vec<Vec<(usize, usize, Vec<f64>)>> = std::thread::scope(|scope| {
            let handles: Vec<_> = seeds
                .chunks(20)
                .map(|chunk| {
                    let (clean, options) = (&clean, &options);
                    scope.spawn(move || {
                        chunk
                            .iter()
                            .map(|&seed| {
                                let mut nees = vec![Vec::new(); clean.filters.len()];
                                let done =
                                    run_together(clean, &clean.filters, seed, options, |i, r| {
                                        if r.time >= start {
                                            nees[i].push(r.position_nees.unwrap_or(f64::NAN));
                                        }
                                    })
                                    .unwrap();
                                done.into_iter()
                                    .zip(nees)
                                    .map(|(r, nees)| {
                                        let h = r.unwrap().health;
                                        if let Some(e) = h.first_alarm {
                                            println!("  {} seed {seed}: {e}", clean.name);
                                        }
                                        (h.innovation_alarms, h.nees_alarms, nees)
                                    })
                                    .collect::<Vec<_>>()
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| h.join().unwrap())
                .collect()
        });
        for (i, k) in clean.filters.iter().enumerate() {
            let innovations = runs.iter().filter(|r| r[i].0 > 0).count();
            let nees_alarms = runs.iter().filter(|r| r[i].1 > 0).count();
            let anees = Anees::of(&runs.iter().map(|r| r[i].2.clone()).collect::<Vec<_>>(), 3);
            let reading = anees.reading();
            println!(
                "{name} {}: runs with an innovation alarm {innovations} of {}, with a NEES alarm \
                 {nees_alarms}; ANEES {:.2}, {}",
                k.label(),
                seeds.len(),
                anees.mean,
                reading.word()
            );
            assert_eq!(innovations, 0, "{name} {}", k.label());
            if matches!(reading, Reading::Consistent | Reading::Conservative) {
                assert_eq!(nees_alarms, 0, "{name} {}", k.label());
            }
        }
    }
}
