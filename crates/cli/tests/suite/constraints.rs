//! Standstill (`[zupt]`) and non-holonomic (`[nhc]`) pseudo-measurements on
//! the simulated drive of `scenarios/smoother-drive.toml`, seed 1001, three
//! 60 s outages, against the same run without them.
//!
//! Documented (`docs/processing.md`): the standstill detector finds the
//! three stops (12 536 samples ≈ 125 s, the stops less the 1 s window), and
//! the forward filter's maximum horizontal error per outage falls from
//! 5.49 / 2.48 / 11.15 m to 1.41 / 0.54 / 2.25 m. The simulated vehicle
//! never slips sideways, so the constraint holds exactly here; on the real
//! log of the docs it helps less. The settings below were written before
//! the run; the bounds are two-sided.

use crate::support;
use kestrel_cli::Context;

use std::path::Path;

use kestrel_app::process::ProcessReport;
use kestrel_cli::process::process;
use support::{forward_drift as max_drift, run_args, simulate_file, tmp_dir, OUTAGES};

fn run(dir: &Path, config: &Path, out: &str) -> Result<ProcessReport, String> {
    let name = config.file_name().unwrap().to_str().unwrap();
    process(&run_args(dir, name, out, &OUTAGES), &Context::default()).map_err(|e| e.to_string())
}

const CONSTRAINTS: &str = "
[nhc]
rate = 10.0
std = [0.1, 0.1]

[zupt]
window = 1.0
accel_std = 0.05
gyro_std = 0.1
rate = 10.0
velocity_std = 0.01
angular_rate_std = 0.01
";

#[test]
fn standstill_and_non_holonomic_updates_cut_the_drift() {
    let dir = tmp_dir("cons", "main");
    simulate_file("smoother-drive.toml", 1001, None, &dir);
    let plain = dir.join("process.toml");
    let text = std::fs::read_to_string(&plain).unwrap();
    let constrained = dir.join("constrained.toml");
    std::fs::write(&constrained, text.clone() + CONSTRAINTS).unwrap();
    let without = run(&dir, &plain, "plain").unwrap();
    let with = run(&dir, &constrained, "constrained").unwrap();

    assert_eq!(without.constraints.zero_velocity, 0);
    let c = with.constraints;
    assert!((12_000..=13_000).contains(&c.standstill_samples), "{c:?}");
    // One update per 0.1 s standing, of each kind; NHC at 10 Hz otherwise.
    assert!((1_200..=1_300).contains(&c.zero_velocity), "{c:?}");
    assert_eq!(c.zero_angular_rate, c.zero_velocity);
    assert!((10_600..=10_900).contains(&c.non_holonomic), "{c:?}");

    let (before, after) = (max_drift(&without), max_drift(&with));
    let documented = [(1.0, 2.0), (0.3, 0.9), (1.5, 3.0)];
    for k in 0..3 {
        assert!(
            after[k] * 2.0 < before[k],
            "outage {k}: {} vs {}",
            after[k],
            before[k]
        );
        let (lo, hi) = documented[k];
        assert!((lo..=hi).contains(&after[k]), "outage {k}: {}", after[k]);
    }
    let nees = with.consistency.unwrap().inside_share().unwrap();
    assert!((0.93..=0.99).contains(&nees), "NEES share {nees}");

    // The odometer update has the constraint already: [nhc] with an
    // [odometer] table is refused, naming the table.
    let both = dir.join("both.toml");
    let odometer = "\n[odometer]\nrate = 10.0\nspeed_std = 0.1\nnhc_std = 0.1\nscale_tau = 3600.0\nscale_sigma = 0.001\n";
    std::fs::write(
        &both,
        text.replace("error_model = \"ins15\"", "error_model = \"odometer16\"")
            + CONSTRAINTS
            + odometer,
    )
    .unwrap();
    let e = run(&dir, &both, "both").unwrap_err();
    assert!(
        e.ends_with(
            "key `nhc`: the odometer update applies the non-holonomic constraint already \
             (`odometer.nhc_std`); remove the [nhc] table"
        ),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
