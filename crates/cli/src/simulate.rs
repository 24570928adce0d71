//! `kestrel simulate`: a scenario's truth and sensor data in the open GINS
//! text formats, with a matching `kestrel process` configuration
//! ([`kestrel_app::simulate`]).

use std::path::PathBuf;

use clap::Args;
use kestrel_app::simulate::{simulate_with, SimulateOptions};

use crate::CliError;

/// Arguments of `kestrel simulate`.
#[derive(Clone, Debug, Args)]
pub struct SimulateArgs {
    /// A built-in scenario (000, 001, 002, 003, 004) or a scenario file
    /// (.toml).
    #[arg(value_name = "SCENARIO")]
    pub scenario: String,
    /// Random seed of the sensor noise (default: the scenario's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Simulate only the first SECONDS of the trajectory.
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// IMU rate in Hz (default: the scenario's).
    #[arg(long, value_name = "HZ")]
    pub imu_rate: Option<f64>,
    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Also replace an imu.txt, gnss.txt, truth.nav or process.toml that
    /// no earlier kestrel run into the folder wrote (without it they are
    /// refused; an earlier run's files are always replaced, exactly the set
    /// its manifest lists).
    #[arg(long)]
    pub force: bool,
}

impl SimulateArgs {
    /// The library's options.
    pub fn options(&self) -> SimulateOptions {
        SimulateOptions {
            scenario: self.scenario.clone(),
            seed: self.seed,
            duration: self.duration,
            imu_rate: self.imu_rate,
            out: self.out.clone(),
            force: self.force,
        }
    }
}

/// Runs `kestrel simulate` and prints what it wrote.
///
/// # Errors
/// [`CliError`] with a one-line cause.
pub fn run(args: &SimulateArgs, ctx: &crate::Context) -> Result<(), CliError> {
    let r = simulate_with(&args.options(), &ctx.cancel, &ctx.command)?;
    crate::outln!(
        "{} IMU samples{}, {} GNSS fixes",
        r.samples,
        if r.odometer {
            " with odometer speed"
        } else {
            ""
        },
        r.fixes
    )?;
    for f in &r.files {
        crate::outln!("wrote {}", f.display())?;
    }
    crate::outln!("process with: {}", process_command(&args.out, r.odometer))?;
    Ok(())
}

/// The `kestrel process` command for the files simulated into `out`,
/// quoted for a POSIX shell.
fn process_command(out: &std::path::Path, odometer: bool) -> String {
    let file = |name: &str| out.join(name).to_string_lossy().into_owned();
    let (imu, gnss, truth, config, result) = (
        file("imu.txt"),
        file("gnss.txt"),
        file("truth.nav"),
        file("process.toml"),
        file("result"),
    );
    let mut words = vec![
        "kestrel", "process", "--imu", &imu, "--gnss", &gnss, "--truth", &truth, "--config",
        &config,
    ];
    if odometer {
        words.push("--odo");
    }
    words.extend(["--out", &result]);
    // A path with a NUL byte cannot be quoted (nor exist): shown as is.
    shlex::try_join(words.iter().copied()).unwrap_or_else(|_| words.join(" "))
}
