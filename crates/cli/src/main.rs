//! `kestrel`: the command-line front end of the kestrel estimation framework.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use kestrel_cli::{demo, import, process, reproduce, simulate, CliError};

/// State estimation for integrated navigation: reproduce the papers'
/// experiments, run your own scenarios, process recorded IMU/GNSS data.
#[derive(Debug, Parser)]
#[command(name = "kestrel", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Reproduce a paper's experiment on its built-in scenario as a Monte
    /// Carlo: tables next to the paper's numbers, CSV and plots.
    Reproduce(reproduce::ReproduceArgs),
    /// Run a user-defined scenario file (TOML) with the same outputs as
    /// `reproduce`.
    Run(reproduce::RunArgs),
    /// List the built-in scenarios.
    Scenarios,
    /// Process recorded IMU / GNSS (/ odometer) files in the open GINS text
    /// formats.
    Process(process::ProcessArgs),
    /// Simulate a scenario's sensors and write them in the open GINS text
    /// formats (input for `process`).
    Simulate(simulate::SimulateArgs),
    /// Convert another tool's configuration into a `process` configuration
    /// (KF-GINS YAML), every unit converted exactly.
    Import(import::ImportArgs),
    /// Track a simulated 2-D target with a range-bearing radar using the
    /// covariance-form EKF, the UKF and the square-root UKF, and print their
    /// accuracy, consistency and cost side by side.
    Demo(demo::DemoArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), CliError> = match cli.command {
        Command::Reproduce(args) => reproduce::reproduce(&args),
        Command::Run(args) => reproduce::run_file(&args),
        Command::Scenarios => reproduce::list_scenarios(),
        Command::Process(args) => process::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Import(args) => import::run(&args),
        Command::Demo(args) => demo::run(&args).map_err(CliError::Failed),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("kestrel: {error}");
            ExitCode::FAILURE
        }
    }
}
