//! `kestrel demo`: the radar tracking Monte Carlo of
//! [`kestrel_app::demo`], printed as a table.

use clap::Args;
use kestrel_app::demo::{radar_demo, DemoOptions, ACCEL_PSD, BEARING_SIGMA, RANGE_SIGMA};

/// Options of `kestrel demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Monte-Carlo runs.
    #[arg(long, default_value_t = 100)]
    runs: usize,
    /// Radar scans per run (one per second).
    #[arg(long, default_value_t = 200)]
    steps: usize,
    /// Seed of the random number generator (runs are reproducible).
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// Runs the demo and prints its table.
///
/// # Errors
/// A one-line message for zero runs or steps, or a failed write.
pub fn run(args: &DemoArgs) -> Result<(), crate::CliError> {
    let rows = radar_demo(&DemoOptions {
        runs: args.runs,
        steps: args.steps,
        seed: args.seed,
    })
    .map_err(crate::CliError::Failed)?;
    crate::outln!(
        "Radar tracking, constant-velocity target: {} runs × {} scans, seed {}",
        args.runs,
        args.steps,
        args.seed
    )?;
    crate::outln!(
        "range σ {RANGE_SIGMA} m, bearing σ {BEARING_SIGMA} rad, acceleration PSD {ACCEL_PSD} m²/s³\n"
    )?;
    crate::outln!(
        "{:<14}{:>14}{:>16}{:>12}{:>12}{:>10}{:>14}",
        "filter",
        "pos RMS [m]",
        "vel RMS [m/s]",
        "mean NEES",
        "mean NIS",
        "errors",
        "ns / cycle"
    )?;
    for r in &rows {
        crate::outln!(
            "{:<14}{:>14.3}{:>16.4}{:>12.3}{:>12.3}{:>10}{:>14.0}",
            r.name,
            r.position_rms,
            r.velocity_rms,
            r.mean_nees,
            r.mean_nis,
            r.errors,
            r.nanos_per_cycle,
        )?;
    }
    crate::outln!(
        "\nA consistent filter has mean NEES ≈ 4 (state size) and mean NIS ≈ 2 (measurement size)."
    )?;
    Ok(())
}
