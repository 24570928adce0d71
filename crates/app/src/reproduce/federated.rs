//! Paper 001's comparison: the federated UKF against the federated SR-UKF
//! over the same data.

use std::fmt::Write as _;

use crate::experiment::{compare_federated_precision, EpochRecord, PrecisionOptions, RunOptions};
use crate::scenario::Scenario;

use super::monte_carlo::FilterOutcome;
use super::table::TextTable;

/// The largest difference between two runs' records over the same epochs:
/// (position m, velocity m/s). `None` if the epochs differ.
///
/// ```
/// use kestrel_app::reproduce::largest_difference;
/// assert_eq!(largest_difference(&[], &[]), Some((0.0, 0.0)));
/// ```
pub fn largest_difference(a: &[EpochRecord], b: &[EpochRecord]) -> Option<(f64, f64)> {
    if a.len() != b.len() {
        return None;
    }
    let mut worst = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        if x.time != y.time {
            return None;
        }
        worst.0 = worst.0.max((x.position - y.position).amax());
        worst.1 = worst.1.max((x.velocity - y.velocity).amax());
    }
    Some(worst)
}

/// Mean and population variance of `values`.
fn mean_variance(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = values.clone().count().max(1) as f64;
    let mean = values.clone().sum::<f64>() / n;
    (mean, values.map(|v| (v - mean).powi(2)).sum::<f64>() / n)
}

/// The report section: paper 001's Table 2 quantities (mean and variance
/// over time of the east position and east velocity errors, run 0) per
/// filter, and the largest UKF/SR-UKF difference.
pub fn federated_section(outcomes: &[FilterOutcome]) -> String {
    let mut out = String::new();
    let mut t = TextTable::new(
        [
            "run 0, over time (paper's Table 2)",
            "east pos mean m",
            "east pos var m²",
            "east vel mean m/s",
            "east vel var (m/s)²",
        ]
        .map(String::from)
        .to_vec(),
    );
    for o in outcomes {
        let (pm, pv) = mean_variance(o.records.iter().map(|r| r.position.y));
        let (vm, vv) = mean_variance(o.records.iter().map(|r| r.velocity.y));
        t.row(vec![
            o.label.to_string(),
            format!("{pm:.4}"),
            format!("{pv:.4}"),
            format!("{vm:.4}"),
            format!("{vv:.4}"),
        ]);
    }
    let _ = writeln!(out, "{t}");
    let ukf = outcomes.iter().find(|o| o.label == "federated UKF");
    let sr = outcomes.iter().find(|o| o.label == "federated SR-UKF");
    if let (Some(u), Some(s)) = (ukf, sr) {
        match largest_difference(&u.records, &s.records) {
            Some((p, v)) => {
                let _ = writeln!(
                    out,
                    "federated UKF vs SR-UKF in f64, run 0: largest difference {p:.2e} m in position, {v:.2e} m/s in velocity ({})\n",
                    if p <= 1e-6 && v <= 1e-6 {
                        "equal to 1e-6, as exact arithmetic predicts"
                    } else {
                        "NOT equal to 1e-6"
                    }
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "federated UKF vs SR-UKF: run 0 did not complete for both\n"
                );
            }
        }
    }
    out
}

/// The precision study of paper 001: the federated UKF and SR-UKF in f64
/// and f32, in natural and badly scaled units, with the scenario's process
/// noise and with an over-confident one (×1/100), on the data of `seed`.
pub fn precision_section(scenario: &Scenario, seed: u64, duration: Option<f64>) -> String {
    let mut out = String::new();
    let run = RunOptions {
        duration,
        ..RunOptions::default()
    };
    let studies = [
        ("the scenario's tuning", PrecisionOptions::default()),
        (
            "IMU noise densities ×1/100 (over-confident Q)",
            PrecisionOptions::small_process_noise(),
        ),
    ];
    for (name, options) in studies {
        let options = PrecisionOptions { run, ..options };
        let _ = writeln!(out, "precision study, {name}, seed {seed}:");
        match compare_federated_precision(scenario, seed, &options) {
            Ok(report) => {
                let _ = writeln!(out, "{report}\n");
            }
            Err(e) => {
                let _ = writeln!(out, "   could not run: {e}\n");
            }
        }
    }
    out
}
