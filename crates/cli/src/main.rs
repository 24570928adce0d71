//! `kestrel`: the command-line front end of the kestrel estimation framework.

mod demo;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// State estimation for integrated navigation.
#[derive(Debug, Parser)]
#[command(name = "kestrel", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Track a simulated 2-D target with a range-bearing radar using the
    /// covariance-form EKF, the UKF and the square-root UKF, and print their
    /// accuracy, consistency and cost side by side.
    Demo(demo::DemoArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(args) => demo::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("kestrel: {message}");
            ExitCode::FAILURE
        }
    }
}
