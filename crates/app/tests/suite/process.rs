//! The pipeline as a library: progress reporting and the caller's own
//! output names (the command-line tests cover the rest through `kestrel
//! process`).

use std::path::PathBuf;

use kestrel_app::process::{process, Inputs, Progress};

/// The shipped example data.
fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples/data")
        .join(name)
}

/// A fresh output folder.
fn out(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("kestrel-io-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Records every call.
#[derive(Default)]
struct Log(Vec<String>);

impl Progress for Log {
    fn begin(&mut self, start: f64, end: f64) {
        self.0.push(format!("begin {start} {end}"));
    }
    fn reached(&mut self, t: f64) {
        self.0.push(format!("at {t}"));
    }
    fn finish(&mut self) {
        self.0.push("finish".into());
    }
}

#[test]
fn progress_hears_the_span_and_the_end_of_a_run_that_succeeds_or_fails() {
    let dir = out("progress");
    let mut inputs = Inputs::new(data("imu.txt"), data("process.toml"), &dir);
    inputs.gnss = Some(data("gnss.txt"));
    let mut log = Log::default();
    let run = process(&inputs, &mut log).unwrap();
    assert_eq!(run.report.samples, 250);
    assert!(run.traces.is_none());
    // 250 samples: fewer than one report interval.
    assert_eq!(log.0, ["begin 0 5", "finish"]);
    // A run that fails after starting still finishes its report, and leaves
    // no result behind.
    let imu = dir.join("short.txt");
    let text = std::fs::read_to_string(data("imu.txt")).unwrap();
    let broken: String =
        text.lines().take(40).collect::<Vec<_>>().join("\n") + "\n0.78 x 0 0 0 0 0\n";
    std::fs::write(&imu, broken).unwrap();
    inputs.imu = imu.clone();
    inputs.out = dir.join("failed");
    let mut log = Log::default();
    let e = process(&inputs, &mut log).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}:41:2: expected a number (Δθ x, rad), found `x`",
            imu.display()
        )
    );
    // The span ends at the last line's time.
    assert_eq!(log.0, ["begin 0 0.78", "finish"]);
    assert!(!dir.join("failed/result.nav").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_callers_output_names_are_guarded_like_the_runs_own() {
    let dir = out("names");
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("plot.png");
    std::fs::copy(data("process.toml"), &config).unwrap();
    let mut inputs = Inputs::new(data("imu.txt"), &config, &dir);
    inputs.also_written = vec!["plot.png".into()];
    let e = process(&inputs, &mut kestrel_app::process::Silent)
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        format!(
            "refusing to write {}: it is the --config input {}; choose another --out",
            dir.join("plot.png").display(),
            config.display()
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_callers_output_name_must_stay_inside_the_output_folder() {
    let dir = out("escape");
    for bad in [
        "../plot.png",
        "/tmp/plot.png",
        "sub/plot.png",
        "..",
        ".",
        "",
    ] {
        let mut inputs = Inputs::new(data("imu.txt"), data("process.toml"), &dir);
        inputs.also_written = vec!["fine.png".into(), bad.into()];
        let e = process(&inputs, &mut kestrel_app::process::Silent)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!("also_written: `{bad}` is not a plain file name (no folders, `.` or `..`)")
        );
    }
    // Refused before anything is written.
    assert!(!dir.exists());
}
