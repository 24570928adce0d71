//! Helpers of the tests that simulate a scenario file and process it: a
//! fresh folder, the simulation, the arguments of a run with three 60 s
//! outages, the drift per outage.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use kestrel_app::process::{ProcessReport, WindowKind};
use kestrel_app::simulate::{simulate, SimulateOptions};
use kestrel_cli::process::ProcessArgs;

/// A fresh folder in the temporary directory, unique to this process.
pub fn tmp_dir(prefix: &str, name: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("kestrel-{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).unwrap();
    p
}

/// `scenarios/FILE` simulated with `seed` (for `duration` s, or all) into
/// `dir`.
pub fn simulate_file(file: &str, seed: u64, duration: Option<f64>, dir: &Path) {
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(file);
    simulate(&SimulateOptions {
        scenario: scenario.to_string_lossy().into_owned(),
        seed: Some(seed),
        duration,
        imu_rate: None,
        out: dir.to_path_buf(),
        force: false,
    })
    .unwrap();
}

/// The outage windows of the drives' checks: 60 s at 300, 600 and 900 s.
pub const OUTAGES: [&str; 3] = ["300:360", "600:660", "900:960"];

/// A run of the simulated files in `dir` with `config`, writing `dir/out`,
/// with the truth, the given outages, no plots.
pub fn run_args(dir: &Path, config: &str, out: &str, outages: &[&str]) -> ProcessArgs {
    ProcessArgs {
        imu: dir.join("imu.txt"),
        gnss: Some(dir.join("gnss.txt")),
        odo: false,
        odometer: None,
        truth: Some(dir.join("truth.nav")),
        config: dir.join(config),
        out: dir.join(out),
        outages: outages.iter().map(|w| w.parse().unwrap()).collect(),
        no_plots: true,
        smooth: false,
        force: false,
        stop_on_divergence: false,
    }
}

/// The maximum horizontal error in each `--outage` window, in order.
pub fn max_drift(drift: &[kestrel_app::process::WindowDrift]) -> Vec<f64> {
    drift
        .iter()
        .filter(|w| w.kind == WindowKind::Outage)
        .map(|w| w.horizontal.unwrap().1)
        .collect()
}

/// [`max_drift`] of a report's forward solution.
pub fn forward_drift(r: &ProcessReport) -> Vec<f64> {
    max_drift(&r.drift)
}
