//! `kestrel reproduce` / `run` / `scenarios` end to end (the Monte Carlo
//! machinery: `kestrel-app`'s `shared_simulation` tests; the papers' claims:
//! its `claims_held_out` tests).

use std::path::PathBuf;
use std::process::Command;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kestrel-reproduce-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn kestrel(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_kestrel"))
        .args(args)
        .output()
        .expect("the binary runs")
}

#[test]
fn scenarios_lists_the_five_papers() {
    let out = kestrel(&["scenarios"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let names: Vec<&str> = text.lines().map(|l| &l[..3]).collect();
    assert_eq!(names, ["000", "001", "002", "003", "004"]);
    assert!(text.lines().all(|l| l.len() > 20), "each has a description");
}

#[test]
fn reproduce_writes_tables_csv_and_figures() {
    let dir = temp_dir("002");
    let out = kestrel(&[
        "reproduce",
        "002",
        "--runs",
        "2",
        "--duration",
        "30",
        "--study-runs",
        "2",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("== Scenario 002"));
    assert!(stdout.contains("paper 002, Table 1"), "{stdout}");
    assert!(
        stdout.contains("(2.245)"),
        "the paper's EKF east position RMS"
    );
    let d = dir.join("002");
    for f in [
        "report.txt",
        "summary.csv",
        "epochs_kf.csv",
        "epochs_ict-erekf.csv",
    ] {
        assert!(d.join(f).is_file(), "{f}");
    }
    let summary = std::fs::read_to_string(d.join("summary.csv")).unwrap();
    let mut lines = summary.lines();
    assert_eq!(
        lines.next(),
        Some("scenario,filter,metric,mean,std,median,runs_ok,runs_failed,paper,runs_with_epochs")
    );
    assert_eq!(lines.clone().count(), 2 * 11);
    assert!(summary.contains("002,KF,pos_east_m,"));
    assert!(summary.contains(",2,0,2.245"));
    // The consistency check, the study and the verdict are in the report.
    assert!(stdout.contains("position ANEES"), "{stdout}");
    assert!(stdout.contains("health monitor"), "{stdout}");
    assert!(stdout.contains("sensitivity:"), "{stdout}");
    // The verdict is computed from the study and names its seeds.
    assert!(
        stdout.contains("verdict (computed from the sensitivity study, seeds 2000–2001): "),
        "{stdout}"
    );
    assert!(
        stdout.contains("bursts capped (±15, 15, 25 m) vs the paper's baseline KF (2)"),
        "{stdout}"
    );
    // The study's disclosure is computed: three variants, two filters, two seeds.
    assert!(
        stdout.contains(
            "disclosure: study, seeds 2000–2001 (computed): 0 failed of 12 runs compared"
        ),
        "{stdout}"
    );
    let study = std::fs::read_to_string(dir.join("sensitivity.csv")).unwrap();
    // Three variants × three metrics, two seeds each.
    assert_eq!(study.lines().count(), 1 + 3 * 3, "{study}");
    assert!(
        study.lines().skip(1).all(|l| l.contains(",2,2,0,0")),
        "{study}"
    );
    assert!(dir.join("sensitivity.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without the study the verdict says it rests on the headline runs only.
#[test]
fn without_the_study_the_verdict_rests_on_the_headline_runs() {
    let dir = temp_dir("002-no-study");
    let out = kestrel(&[
        "reproduce",
        "002",
        "--runs",
        "2",
        "--seed",
        "3000",
        "--duration",
        "30",
        "--study-runs",
        "0",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains(
            "verdict (computed from the headline runs only, seeds 3000–3001 (the study was skipped)): "
        ),
        "{stdout}"
    );
    assert!(!stdout.contains("sensitivity study, seeds"), "{stdout}");
    assert!(!stdout.contains("headline seeds 2–21 include"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_fail_with_one_line() {
    for args in [
        &["reproduce", "007"][..],
        &["reproduce", "000", "--runs", "0", "--no-plots"],
        &["reproduce", "000", "--duration", "-1"],
        &["reproduce", "000", "--runs", "many"],
    ] {
        let out = kestrel(args);
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.trim().is_empty(), "{args:?}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    let out = kestrel(&["reproduce", "000", "--runs", "0", "--no-plots"]);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        "error: invalid value '0' for '--runs <N>': 0 is not in 1..=10000\n\n\
         For more information, try '--help'."
    );
}

#[test]
fn run_takes_a_scenario_file_and_reports_its_errors() {
    let dir = temp_dir("run");
    let paper = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/paper-004.toml"
    );
    let out = kestrel(&[
        "run",
        paper,
        "--runs",
        "1",
        "--duration",
        "5",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("== Scenario 004"), "{stdout}");
    assert!(
        !stdout.contains("paper 004"),
        "no paper columns for a user file"
    );
    assert!(dir.join("004").join("runs.csv").is_file());

    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[scenario]\nname = \"x\"\nbogus = 1\n").unwrap();
    let out = kestrel(&["run", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("bad.toml:3:1: key `scenario.bogus`: unknown key `bogus`"),
        "{err}"
    );
    let missing = dir.join("missing.toml");
    let out = kestrel(&["run", missing.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.toml"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run too short for any aiding epoch has no RMS: the tables print —,
/// never 0.000 ± 0.000 nor a NaN× ratio, and the report says why.
#[test]
fn runs_without_an_aiding_epoch_print_no_statistic() {
    let dir = temp_dir("no-epochs");
    let out = kestrel(&[
        "reproduce",
        "002",
        "--runs",
        "2",
        "--duration",
        "0.5",
        "--study-runs",
        "0",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!text.contains("0.000 ± 0.000"), "{text}");
    assert!(!text.contains("NaN"), "{text}");
    assert!(
        text.contains("KF: 2 of 2 run(s) had no aiding epoch counted in the RMS"),
        "{text}"
    );
    // The metrics' cells (between `failure` and `health_alarms`) are empty.
    let runs = std::fs::read_to_string(dir.join("002/runs.csv")).unwrap();
    let header: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let (from, to) = (
        header.iter().position(|c| *c == "failure").unwrap() + 1,
        header.iter().position(|c| *c == "health_alarms").unwrap(),
    );
    assert!(to - from >= 10, "{header:?}");
    let row: Vec<&str> = runs.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[4], "ok");
    assert!(row[from..to].iter().all(|c| c.is_empty()), "{row:?}");
}
