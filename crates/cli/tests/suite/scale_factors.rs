//! The 21-state model (`error_model = "ins21"`) on the simulated drive of
//! `scenarios/scale-factor-drive.toml` (gyro scale factors 300 / −200 /
//! 400 ppm, accelerometer 200 / 300 / −250 ppm), seed 2001, with three 60 s
//! outages, against the 15-state model on the same files.
//!
//! The documented finding (`docs/processing.md`, seeds 2001–2005): on this
//! drive the scale factors end within 3σ of their true values except where
//! the model's accelerometer bias is too confident, the gyro scale factors
//! are barely observable (σ 500 → 420–500 ppm: few turns), the vertical
//! accelerometer scale factor is (σ 500 → 92 ppm, through gravity, tied to
//! the vertical bias), and the outage drift is the same as the 15-state
//! model's within a few per cent — the scale states do not lower it here.
//! Nothing was tuned on seed 2001 (the scenario was written before any
//! run); the bounds are two-sided around its documented values.

use crate::support;
use kestrel_cli::Context;

use std::path::Path;

use kestrel_app::process::ProcessReport;
use kestrel_cli::process::process;
use support::{forward_drift as max_drift, run_args, simulate_file, tmp_dir, OUTAGES};

fn run(dir: &Path, config: &Path, out: &str) -> ProcessReport {
    let name = config.file_name().unwrap().to_str().unwrap();
    process(&run_args(dir, name, out, &OUTAGES), &Context::default()).unwrap()
}

/// The last row of a CSV file, as numbers.
fn last_row(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect()
}

#[test]
fn scale_factors_are_estimated_and_reported() {
    let dir = tmp_dir("sf", "main");
    simulate_file("scale-factor-drive.toml", 2001, None, &dir);
    let c21 = dir.join("process.toml");
    let text = std::fs::read_to_string(&c21).unwrap();
    assert!(text.contains("error_model = \"ins21\""));
    // The same configuration without the scale states.
    let c15 = dir.join("process15.toml");
    let text15: String = text
        .replace("error_model = \"ins21\"", "error_model = \"ins15\"")
        .lines()
        .filter(|l| !l.starts_with("gyro_scale = ") && !l.starts_with("accel_scale = "))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&c15, text15).unwrap();
    let r21 = run(&dir, &c21, "r21");
    let r15 = run(&dir, &c15, "r15");

    // Final estimates (ppm) against the truth, within 3σ.
    let est = last_row(&dir.join("r21/result_imu_errors.csv"));
    let std = last_row(&dir.join("r21/result_std.csv"));
    let truth = [300.0, -200.0, 400.0, 200.0, 300.0, -250.0];
    for k in 0..6 {
        let (e, s) = (est[7 + k], std[16 + k]);
        assert!(
            (e - truth[k]).abs() <= 3.0 * s,
            "scale {k}: {e} ppm, σ {s}, truth {}",
            truth[k]
        );
    }
    // Observability: the gyro scale factors stay near their initial 500 ppm
    // σ, the vertical accelerometer one is learnt (documented 92 ppm).
    for k in 0..3 {
        assert!(
            (400.0..=500.0).contains(&std[16 + k]),
            "gyro σ {}",
            std[16 + k]
        );
    }
    assert!((80.0..=110.0).contains(&std[21]), "accel z σ {}", std[21]);
    // The same drift as the 15-state model, outage by outage (documented
    // ratios 0.99, 1.00, 1.00).
    for (a, b) in max_drift(&r21).iter().zip(max_drift(&r15)) {
        let ratio = a / b;
        assert!((0.95..=1.05).contains(&ratio), "21 / 15 drift {a} / {b}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
