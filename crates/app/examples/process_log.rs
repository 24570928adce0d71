//! Processes a recorded log and prints what `kestrel process` prints.
//!
//! ```text
//! cargo run -p kestrel-io --example process_log -- IMU CONFIG OUT [GNSS [TRUTH]]
//! ```
//!
//! Without arguments it processes `examples/data` (5 s of a simulated
//! drive, written by `kestrel simulate 002 --seed 1 --duration 5
//! --imu-rate 50`) into a temporary folder.

use std::path::PathBuf;

use kestrel_app::process::{process, summary, Inputs, Progress};

/// Prints the time reached now and then.
struct Dots;

impl Progress for Dots {
    fn reached(&mut self, t: f64) {
        eprintln!("… {t:.1} s");
    }
}

fn main() -> Result<(), kestrel_io::Error> {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let data = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data"));
    let inputs = match args.as_slice() {
        [] => Inputs {
            gnss: Some(data.join("gnss.txt")),
            truth: Some(data.join("truth.nav")),
            ..Inputs::new(
                data.join("imu.txt"),
                data.join("process.toml"),
                std::env::temp_dir().join("kestrel-process-log"),
            )
        },
        [imu, config, out, rest @ ..] if rest.len() <= 2 => Inputs {
            gnss: rest.first().cloned(),
            truth: rest.get(1).cloned(),
            ..Inputs::new(imu, config, out)
        },
        _ => {
            eprintln!("usage: process_log IMU CONFIG OUT [GNSS [TRUTH]]");
            std::process::exit(2);
        }
    };
    let run = process(&inputs, &mut Dots)?;
    print!("{}", summary(&run.report));
    Ok(())
}
