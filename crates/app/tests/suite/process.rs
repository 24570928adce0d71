//! The pipeline as a library: progress reporting and the caller's own
//! output names (the command-line tests cover the rest through `kestrel
//! process`).

use std::path::PathBuf;

use kestrel_app::process::Silent;
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
    use kestrel_app::transaction::Cancel;
    let dir = out("names");
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("plot.png");
    std::fs::copy(data("process.toml"), &config).unwrap();
    let inputs = Inputs::new(data("imu.txt"), &config, &dir);
    let mut tx = kestrel_app::process::begin(&inputs, true, &[]).unwrap();
    let run = kestrel_app::process::run(&inputs, &mut tx, &mut Silent, &Cancel::default()).unwrap();
    // A figure the caller adds under the input's name is refused at commit,
    // even with force, and nothing is published.
    std::fs::write(tx.path("plot.png").unwrap(), "figure").unwrap();
    let e = tx.commit(run.provenance).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "refusing to write {}: it is the --config input {}; choose another output folder",
            dir.join("plot.png").display(),
            config.display()
        )
    );
    assert!(!dir.join("result.nav").exists());
    assert_eq!(
        std::fs::read_to_string(&config).unwrap(),
        std::fs::read_to_string(data("process.toml")).unwrap()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_callers_output_name_must_stay_inside_the_output_folder() {
    let dir = out("escape");
    let inputs = Inputs::new(data("imu.txt"), data("process.toml"), &dir);
    let mut tx = kestrel_app::process::begin(&inputs, false, &[]).unwrap();
    for bad in [
        "../plot.png",
        "/tmp/plot.png",
        "sub/plot.png",
        "..",
        ".",
        "",
        ".kestrel.lock",
        "kestrel-manifest.json",
    ] {
        let e = tx.path(bad).unwrap_err().to_string();
        assert_eq!(
            e,
            format!("`{bad}` cannot be an output file's name (a plain name, not reserved)")
        );
    }
    drop(tx);
    // Nothing was written: the folder the run made is gone again.
    assert!(!dir.exists());
}
