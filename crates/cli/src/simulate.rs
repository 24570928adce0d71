//! `kestrel simulate`: a scenario's truth and sensor data in the open GINS
//! text formats, with a matching `kestrel process` configuration
//! ([`kestrel_app::simulate`]).

use std::path::PathBuf;

use clap::Args;
use kestrel_app::simulate::{simulate, SimulateOptions};

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
    /// Replace imu.txt, gnss.txt, truth.nav and process.toml if they exist
    /// (without it, existing files are never overwritten).
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
pub fn run(args: &SimulateArgs) -> Result<(), CliError> {
    let r = simulate(&args.options())?;
    println!(
        "{} IMU samples{}, {} GNSS fixes",
        r.samples,
        if r.odometer {
            " with odometer speed"
        } else {
            ""
        },
        r.fixes
    );
    for f in &r.files {
        println!("wrote {}", f.display());
    }
    let d = args.out.display();
    println!(
        "process with: kestrel process --imu {d}/imu.txt --gnss {d}/gnss.txt --truth {d}/truth.nav \
         --config {d}/process.toml{} --out {d}/result",
        if r.odometer { " --odo" } else { "" }
    );
    Ok(())
}
