//! `kestrel`: the command-line front end of the kestrel estimation framework.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use kestrel_cli::signals::Signals;
use kestrel_cli::{demo, import, out, process, reproduce, simulate, CliError, Context};

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
    let signals = Signals::install();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage(&e),
    };
    let ctx = Context {
        cancel: signals.cancel().clone(),
        command: std::env::args().collect(),
    };
    let result: Result<(), CliError> = match cli.command {
        Command::Reproduce(args) => reproduce::reproduce(&args, &ctx),
        Command::Run(args) => reproduce::run_file(&args, &ctx),
        Command::Scenarios => reproduce::list_scenarios(),
        Command::Process(args) => process::run(&args, &ctx),
        Command::Simulate(args) => simulate::run(&args, &ctx),
        Command::Import(args) => import::run(&args),
        Command::Demo(args) => demo::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of our output went away (`kestrel … | head`): a quiet
        // end, with the status of a process a closed pipe stops.
        Err(e) if out::is_closed_pipe(&e) => ExitCode::from(141),
        Err(CliError::Cancelled) => {
            let _ = out::warn("kestrel: stopped by a signal; nothing was written");
            ExitCode::from(signals.exit_status().unwrap_or(130))
        }
        Err(error) => {
            // If standard error is gone too, the status still says it.
            let _ = out::warn(&format!("kestrel: {error}"));
            ExitCode::FAILURE
        }
    }
}

/// What clap has to say instead of a command (help, the version, a usage
/// error), written through [`out`] so a full or closed stream is an error
/// status, never a silent success.
fn usage(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind::{DisplayHelp, DisplayVersion};
    let text = e.render().to_string();
    let informational = matches!(e.kind(), DisplayHelp | DisplayVersion);
    let written = if informational {
        out::print(&text)
    } else {
        out::warn(text.trim_end())
    };
    match written {
        Err(e) if out::is_closed_pipe(&e) => ExitCode::from(141),
        Err(error) => {
            let _ = out::warn(&format!("kestrel: {error}"));
            ExitCode::FAILURE
        }
        Ok(()) if informational => ExitCode::SUCCESS,
        Ok(()) => ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2)),
    }
}
