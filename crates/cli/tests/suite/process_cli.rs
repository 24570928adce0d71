//! `kestrel process` and `kestrel simulate`: configuration errors, the
//! round trip simulate → open formats → process against the in-memory run,
//! outages, divergence, and the binary end to end.

use kestrel_cli::Context;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use kestrel_app::experiment::{run, RunOptions};
use kestrel_app::process::WindowKind;
use kestrel_app::scenario::{by_name, FilterKind};
use kestrel_app::simulate::{process_config, simulate, SimulateOptions};
use kestrel_cli::process::{process, ProcessArgs};

/// A fresh directory in the temporary directory, unique to this process
/// and call.
fn tmp_dir(name: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let k = N.fetch_add(1, Ordering::Relaxed);
    let p = std::env::temp_dir().join(format!("kestrel-proc-{}-{k}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).unwrap();
    p
}

fn sim(name: &str, seed: u64, duration: f64) -> PathBuf {
    let dir = tmp_dir(&format!("sim{name}"));
    simulate(&SimulateOptions {
        scenario: name.into(),
        seed: Some(seed),
        duration: Some(duration),
        imu_rate: None,
        out: dir.clone(),
        force: false,
    })
    .unwrap();
    dir
}

fn args(dir: &Path, odo: bool) -> ProcessArgs {
    ProcessArgs {
        imu: dir.join("imu.txt"),
        gnss: Some(dir.join("gnss.txt")),
        odo,
        odometer: None,
        truth: Some(dir.join("truth.nav")),
        config: dir.join("process.toml"),
        out: dir.join("result"),
        outages: Vec::new(),
        no_plots: true,
        smooth: false,
        force: false,
        stop_on_divergence: false,
    }
}

/// Runs the standard filter on `name` both ways: simulated data written
/// in the open formats and processed from the files, and the in-memory
/// experiment runner with the same seed and duration.
fn round_trip(name: &str, seed: u64, duration: f64, odo: bool) {
    round_trip_with(name, &FilterKind::Standard, seed, duration, odo);
}

/// As [`round_trip`] with the filter `kind` (its configuration written by
/// the same function `simulate` uses).
fn round_trip_with(name: &str, kind: &FilterKind, seed: u64, duration: f64, odo: bool) {
    let dir = sim(name, seed, duration);
    let sc = by_name(name).unwrap();
    let truth = sc.trajectory().unwrap().initial_state();
    let config = process_config(&sc, &sc.initial_state(&truth), kind);
    std::fs::write(dir.join("process.toml"), config).unwrap();
    let report = process(&args(&dir, odo), &Context::default()).unwrap();
    let opts = RunOptions::default().with_duration(duration);
    let mem = run(&sc, kind, seed, &opts).unwrap().summary;
    // Every IMU sample has a truth line: all are compared; the runner's
    // summary is over the aiding epochs, after the update.
    assert_eq!(report.errors.unwrap().epochs, report.samples);
    let e = report.aiding_errors.unwrap();
    assert_eq!(report.filter, kind.label());
    assert_eq!(report.rejected, mem.rejected, "{name}: same rejections");
    assert_eq!(report.updates, mem.epochs, "{name}: same aiding epochs");
    assert_eq!(
        e.epochs, mem.rms_epochs,
        "{name}: all compared with the truth"
    );
    assert_eq!(e.axes, mem.axes);
    // What differs between the two runs: latitude and longitude written in
    // degrees come back within one unit in the last place (1e-16 rad, under
    // a nanometre; about one double in ten has no exact degree
    // representation), and the initial attitude and the truth attitude pass
    // through Euler angles in degrees (a few 1e-16 rad). The runs amplify
    // these 1e-16 relative differences to at most 2.2e-9 relative here (the
    // adaptive filters most: their R estimates and fades follow the data);
    // a sample, a fix, an R or a parameter out of step changes the RMS by
    // 1e-4 relative or more. 1e-8 relative separates the two.
    let close = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-8 * b.abs(),
            "{name} {} {what}: file {a} vs memory {b}",
            kind.label()
        );
    };
    for i in 0..3 {
        close(e.rms_position[i], mem.rms_position[i], "position RMS");
        let m = e.motion.unwrap();
        close(m.rms_velocity[i], mem.rms_velocity[i], "velocity RMS");
        close(m.rms_attitude[i], mem.rms_attitude[i], "attitude RMS");
    }
    close(e.max_position_3d, mem.max_position, "max position");
    assert!(
        mem.rms_position.norm() > 0.01,
        "{name}: a real run, not a trivial one"
    );
}

#[test]
fn gnss_scenario_002_through_the_files_equals_the_in_memory_run() {
    round_trip("002", 5, 60.0, false);
}

#[test]
fn scenario_000_on_the_krasovsky_ellipsoid_equals_the_in_memory_run() {
    round_trip("000", 3, 30.0, false);
}

#[test]
fn odometer_scenario_003_through_the_eighth_column_equals_the_in_memory_run() {
    round_trip("003", 2, 30.0, true);
}

#[test]
fn the_adaptive_and_robust_filters_through_the_files_equal_the_in_memory_run() {
    // 002's ICT-EREKF, 000's Sage-Husa + fading and improved adaptive
    // filters, 003's max-threshold and fuzzy odometer processing.
    let s002 = by_name("002").unwrap();
    round_trip_with("002", &s002.filters[1], 4, 60.0, false);
    let s000 = by_name("000").unwrap();
    round_trip_with("000", &s000.filters[1], 6, 20.0, false);
    round_trip_with("000", &s000.filters[2], 6, 20.0, false);
    let s003 = by_name("003").unwrap();
    round_trip_with("003", &s003.filters[1], 8, 20.0, true);
    round_trip_with("003", &s003.filters[2], 8, 20.0, true);
}

/// The error `process` gives for the configuration text `text` (the other
/// inputs valid).
fn config_error(dir: &Path, text: &str) -> (PathBuf, String) {
    let path = dir.join(format!("bad-{}.toml", text.len()));
    std::fs::write(&path, text).unwrap();
    let mut a = args(dir, false);
    a.config = path.clone();
    (
        path,
        process(&a, &Context::default()).unwrap_err().to_string(),
    )
}

/// `e` is `FILE:LINE:COLUMN: key `key`: msg`, LINE the line of the key (or
/// of its table when the key is absent).
fn assert_at_key(e: &str, file: &Path, text: &str, key: &str, msg: &str) {
    let rest = e
        .strip_prefix(&format!("{}:", file.display()))
        .unwrap_or_else(|| panic!("{e}"));
    let mut parts = rest.splitn(3, ':');
    let line: usize = parts.next().and_then(|l| l.parse().ok()).expect(e);
    let column: Option<usize> = parts.next().and_then(|c| c.parse().ok());
    assert!(column.is_some(), "{e}");
    assert_eq!(
        parts.next(),
        Some(format!(" key `{key}`: {msg}").as_str()),
        "{e}"
    );
    let leaf = key.rsplit('.').next().unwrap().split('[').next().unwrap();
    let table = key.split('.').next().unwrap();
    let at = text.lines().nth(line - 1).unwrap_or("");
    assert!(
        at.contains(leaf) || at.contains(table),
        "{e}: line {line} is `{at}`"
    );
}

#[test]
fn configuration_errors_name_the_line_column_or_key() {
    let dir = sim("002", 1, 3.0);
    let good = std::fs::read_to_string(dir.join("process.toml")).unwrap();
    let line_of = |needle: &str| good.lines().position(|l| l.starts_with(needle)).unwrap() + 1;

    // Unknown key: line and column of the key.
    let text = good.replace("gyro_arw =", "gyro_arww =");
    let (p, e) = config_error(&dir, &text);
    let prefix = format!(
        "{}:{}:1: key `imu.gyro_arww`: unknown key `gyro_arww`, expected one of",
        p.display(),
        line_of("gyro_arw")
    );
    assert!(e.starts_with(&prefix), "{e}");

    // Wrong type: line and column of the value.
    let text = good.replace(
        "covariance_interval = 0.1",
        "covariance_interval = \"fast\"",
    );
    let (p, e) = config_error(&dir, &text);
    let prefix = format!(
        "{}:{}:23: key `filter.covariance_interval`: invalid type: string \"fast\", \
         expected a number",
        p.display(),
        line_of("covariance_interval")
    );
    assert!(e.starts_with(&prefix), "{e}");

    // An array of the wrong length: line and column of the array.
    let text = good.replacen("lever_arm = [", "lever_arm = [9.0, ", 1);
    let (p, e) = config_error(&dir, &text);
    let prefix = format!(
        "{}:{}:13: key `filter.lever_arm`: invalid length 4, expected an array of exactly 3 \
         numbers",
        p.display(),
        line_of("lever_arm")
    );
    assert!(e.starts_with(&prefix), "{e}");

    // Missing table.
    let start = good.find("[initial]").unwrap();
    let end = good.find("[imu]").unwrap();
    let text = format!("{}{}", &good[..start], &good[end..]);
    let (p, e) = config_error(&dir, &text);
    assert!(
        e.starts_with(&format!("{}:", p.display())) && e.contains("missing key `initial`"),
        "{e}"
    );

    // Out of range: the key.
    let cases = [
        ("gyro_arw = ", "gyro_arw = -0.5\n#", "imu.gyro_arw", "expected 0 (none) or a standard deviation > 0 whose square in SI units is a normal double (neither 0 nor infinite), found -0.5"),
        ("gyro_arw = ", "gyro_arw = 1e-200\n#", "imu.gyro_arw", "expected 0 (none) or a standard deviation > 0 whose square in SI units is a normal double (neither 0 nor infinite), found 1e-200"),
        ("position = [", "position = [30.0, 1e308, 0.0]\n#", "initial.position[1]", "expected a longitude in [-180, 360] deg, found 1e308"),
        ("position = [", "position = [30.0, 114.0, -1e7]\n#", "initial.position[2]", "expected a height in [-12000, 100000] m, found -10000000"),
        ("velocity = [", "velocity = [0.0, 3e3, 0.0]\n#", "initial.velocity[1]", "expected a speed in [-1000, 1000] m/s, found 3000"),
        ("attitude = [", "attitude = [0.0, 95.0, 0.0]\n#", "initial.attitude[1]", "expected a pitch in [-90, 90] deg, found 95"),
        ("gyro_arw = ", "gyro_bias = 10.0\ngyro_arw = ", "imu.gyro_bias", "not used by `process`: the filter's initial gyro bias σ is `initial.std.gyro_bias` (°/h) and a drifting bias is `imu.gyro_markov_sigma` / `imu.gyro_markov_tau`"),
        ("gyro_arw = ", "accel_scale = 100\ngyro_arw = ", "imu.accel_scale", "not used by `process`: the filter's scale-factor σ is `initial.std.gyro_scale` / `accel_scale` (ppm, error_model = `ins21`) and a known scale-factor error is `initial.gyro_scale` / `accel_scale`"),
        ("odometer_scale = ", "gyro_scale = [100.0, 100.0, 100.0]\nodometer_scale = ", "initial.std.gyro_scale", "scale-factor errors are states of error_model = `ins21` only (a known scale-factor error is `initial.gyro_scale` / `initial.accel_scale`)"),
        ("gyro_arw = ", "scale_tau = 3600.0\ngyro_arw = ", "imu.scale_tau", "scale-factor errors are states of error_model = `ins21` only (a known scale-factor error is `initial.gyro_scale` / `initial.accel_scale`)"),
        ("attitude = [", "gyro_scale = [0.0, 2e5, 0.0]\nattitude = [", "initial.gyro_scale[1]", "expected a scale-factor error in [-100000, 100000] ppm, found 200000"),
        ("attitude = [", "accel_bias = [0.0, 0.0, 3e5]\nattitude = [", "initial.accel_bias[2]", "expected an accelerometer bias in [-200000, 200000] µg, found 300000"),
        ("kind = ", "kind = \"ict-erekf\"\nsignificance = 1.5\n#", "filter.significance", "expected 0.01 ≤ significance ≤ 0.15 (the range the test is built for), found 1.5"),
        ("kind = ", "kind = \"fading\"\nrho = 1.5\n#", "filter.rho", "expected 0 ≤ ρ ≤ 1, found 1.5"),
        ("kind = ", "kind = \"sage-husa-fading\"\nlambda_max = 0.5\n#", "filter.lambda_max", "expected at least 1, found 0.5"),
        ("kind = ", "kind = \"ekf\"\nrho = 0.5\n#", "filter.rho", "does not apply to kind = \"ekf\", which takes no parameters"),
        ("kind = ", "kind = \"kalman\"\n#", "filter.kind", "unknown value `kalman`, expected one of `ekf`, `sage-husa-fading`, `improved-adaptive`, `federated-ukf`, `federated-sr-ukf`, `ict-erekf`, `chi-square-gate`, `max-threshold`, `fuzzy-adaptive`, `strong-tracking-fading`"),
        ("position = [", "position = [91.0, 0.0, 0.0]\n#", "initial.position[0]", "expected a latitude in [-89.9, 89.9] deg, found 91"),
        ("position_std = ", "position_std = [1.0, 0.0, 1.0]\n#", "gnss.position_std[1]", "expected a standard deviation > 0 whose square in SI units is a normal double (neither 0 nor infinite), found 0"),
        ("gyro_markov_tau = ", "gyro_markov_tau = -5.0\n#", "imu.gyro_markov_tau", "expected a time ≥ 0.001 s (or inf; a shorter correlation is white noise), found -5"),
    ];
    for (find, replace, key, msg) in cases {
        let text = good.replacen(find, replace, 1);
        let (p, e) = config_error(&dir, &text);
        assert_at_key(&e, &p, &text, key, msg);
    }
    // The 21-state model: a Markov σ of the scale factors needs their
    // correlation time.
    let text = good
        .replacen("error_model = \"ins15\"", "error_model = \"ins21\"", 1)
        .replacen("gyro_arw = ", "gyro_scale_sigma = 100.0\ngyro_arw = ", 1);
    let (p, e) = config_error(&dir, &text);
    assert_at_key(
        &e,
        &p,
        &text,
        "imu.gyro_scale_sigma",
        "a Markov σ needs `imu.scale_tau` (without it the scale factors are random constants)",
    );

    // --odo needs the odometer table.
    let mut a = args(&dir, true);
    a.config = dir.join("process.toml");
    assert_eq!(
        process(&a, &Context::default()).unwrap_err().to_string(),
        format!(
            "{}: key `odometer`: --odo needs an [odometer] table",
            a.config.display()
        )
    );
    // A missing configuration file.
    a.config = dir.join("absent.toml");
    let e = process(&a, &Context::default()).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("{}: cannot read the file: ", a.config.display())),
        "{e}"
    );
}

#[test]
fn outage_windows_drop_the_fixes_inside_them() {
    let dir = sim("002", 7, 60.0);
    let full = process(&args(&dir, false), &Context::default()).unwrap();
    let mut a = args(&dir, false);
    a.outages = vec!["20:40".parse().unwrap(), "50.5:52.5".parse().unwrap()];
    a.out = dir.join("coast");
    let coast = process(&a, &Context::default()).unwrap();
    // 1 Hz fixes at 1 … 60 s: the half-open windows drop 20 … 39 (20) and
    // 51, 52 (2).
    assert_eq!(full.fixes_used, 60);
    assert_eq!((coast.fixes_used, coast.fixes_in_outage), (38, 22));
    assert_eq!(coast.updates, 38);
    assert_eq!(coast.aiding_errors.unwrap().epochs, 38);
    // Every IMU sample is compared, in the outages too.
    assert_eq!(coast.errors.unwrap().epochs, 12_000);
    // The same as deleting those lines from the GNSS file, bit for bit.
    let gnss = std::fs::read_to_string(dir.join("gnss.txt")).unwrap();
    let kept: String = gnss
        .lines()
        .filter(|l| {
            let t: f64 = l.split(' ').next().unwrap().parse().unwrap_or(-1.0);
            !((20.0..40.0).contains(&t) || (50.5..52.5).contains(&t))
        })
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.join("gnss-cut.txt"), kept).unwrap();
    let mut cut = args(&dir, false);
    cut.gnss = Some(dir.join("gnss-cut.txt"));
    cut.out = dir.join("cut");
    let deleted = process(&cut, &Context::default()).unwrap();
    assert_eq!(deleted.fixes_used, 38);
    let read = |d: &str| std::fs::read_to_string(dir.join(d).join("result.nav")).unwrap();
    assert_eq!(read("cut"), read("coast"));
    // The drift table: the two windows with 200 Hz epochs, then the gaps
    // of the fixes used (1.5 s and longer): 19 … 40 s and 50 … 53 s.
    let d = &coast.drift;
    let row = |k: usize| (d[k].kind, d[k].start, d[k].end, d[k].epochs);
    assert_eq!(row(0), (WindowKind::Outage, 20.0, 40.0, 4_000));
    assert_eq!(row(1), (WindowKind::Outage, 50.5, 52.5, 400));
    assert_eq!(row(2), (WindowKind::Gap, 19.0, 40.0, 4_200));
    assert_eq!(row(3), (WindowKind::Gap, 50.0, 53.0, 600));
    assert_eq!(d.len(), 4);
    // The window's statistics are those of the errors.csv rows in it.
    let errors = std::fs::read_to_string(dir.join("coast").join("errors.csv")).unwrap();
    let (mut n, mut sum, mut max) = (0, 0.0, 0.0f64);
    for l in errors.lines().skip(1) {
        let v: Vec<f64> = l.split(',').take(4).map(|x| x.parse().unwrap()).collect();
        if (20.0..40.0).contains(&v[0]) {
            let h = v[1].hypot(v[2]);
            n += 1;
            sum += h * h;
            max = max.max(h);
        }
    }
    let (rms, largest) = d[0].horizontal.unwrap();
    assert_eq!((n, largest), (4_000, max));
    assert!((rms - (sum / 4000.0).sqrt()).abs() < 1e-12 * rms);
    assert_eq!(errors.lines().count(), 12_001);
    let drift_csv = std::fs::read_to_string(dir.join("coast").join("drift.csv")).unwrap();
    assert!(drift_csv.starts_with("kind,start_s,end_s,duration_s,epochs,"));
    assert!(drift_csv
        .lines()
        .nth(1)
        .unwrap()
        .starts_with("outage,20,40,20,4000,"));
    let summary = kestrel_app::process::summary(&coast);
    assert!(
        summary.contains("errors against the truth at 12000 epochs"),
        "{summary}"
    );
    assert!(
        summary.contains("  outage 20 to 40 s (20 s): 4000 epochs, horizontal "),
        "{summary}"
    );
    // The solutions agree bit for bit up to the first dropped fix (20 s)
    // and part there.
    let (a, b) = (read("result"), read("coast"));
    let time = |l: &str| l.split(' ').nth(1).unwrap().parse::<f64>().unwrap();
    let pairs: Vec<(&str, &str)> = a
        .lines()
        .zip(b.lines())
        .filter(|(l, _)| !l.starts_with('#'))
        .collect();
    assert_eq!(pairs.len(), 12_000);
    for (x, y) in &pairs {
        if time(x) < 20.0 {
            assert_eq!(x, y);
        }
    }
    let at_20 = pairs.iter().find(|(x, _)| time(x) == 20.0).unwrap();
    assert_ne!(at_20.0, at_20.1);
}

/// An absurd velocity increment (1e308 m/s at 0.505 s), which used to make
/// the solution non-finite mid-run ("KF diverged … no longer finite"), is
/// refused by the reader at its line and column with the rate it means.
#[test]
fn an_absurd_increment_is_refused_at_its_line() {
    let dir = sim("002", 1, 3.0);
    let imu = std::fs::read_to_string(dir.join("imu.txt")).unwrap();
    let mut lines: Vec<String> = imu.lines().map(String::from).collect();
    let k = lines.iter().position(|l| l.starts_with("0.505 ")).unwrap();
    let mut f: Vec<String> = lines[k].split(' ').map(String::from).collect();
    f[4] = "1e308".into();
    f[5] = "1e308".into();
    lines[k] = f.join(" ");
    std::fs::write(dir.join("imu.txt"), lines.join("\n")).unwrap();
    let e = process(&args(&dir, false), &Context::default())
        .unwrap_err()
        .to_string();
    let at = format!(
        "{}:{}:5: a velocity increment of 1e308 m/s in ",
        dir.join("imu.txt").display(),
        k + 1
    );
    assert!(e.starts_with(&at), "{e}");
    assert!(
        e.ends_with(
            "is inf m/s², beyond any IMU's range (at most 9806.65 m/s², 1000 g; is the \
                     column in the right unit?)"
        ),
        "{e}"
    );
}

fn kestrel(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_kestrel"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn the_binary_simulates_processes_and_refuses_bad_input() {
    let dir = tmp_dir("bin");
    let d = |f: &str| dir.join(f).display().to_string();
    let out = kestrel(&[
        "simulate",
        "002",
        "--seed",
        "9",
        "--duration",
        "20",
        "--out",
        &d(""),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("4000 IMU samples, 20 GNSS fixes\n"),
        "{stdout}"
    );

    let out = kestrel(&[
        "process",
        "--imu",
        &d("imu.txt"),
        "--gnss",
        &d("gnss.txt"),
        "--truth",
        &d("truth.nav"),
        "--config",
        &d("process.toml"),
        "--out",
        &d("result"),
        "--outage",
        "5:8",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with(
        "KF: 4000 IMU samples to 20 s of week, 17 GNSS fixes used (3 in outages), 17 updates (0 rejected)\n\
         IMU nominal interval 0.005 s, no gaps\n\
         errors against the truth at 4000 epochs (every truth epoch of the run; RMS / max |error|):\n  position  east: "
    ), "{stdout}");
    let nav = std::fs::read_to_string(dir.join("result/result.nav")).unwrap();
    assert_eq!(nav.lines().filter(|l| !l.starts_with('#')).count(), 4000);
    let csv = std::fs::read_to_string(dir.join("result/result.csv")).unwrap();
    assert_eq!(
        csv.lines().next(),
        Some(kestrel_app::process::RESULT_CSV_HEADER)
    );
    assert_eq!(csv.lines().count(), 4001);
    for f in [
        "errors.csv",
        "error_summary.csv",
        "position.png",
        "velocity.svg",
    ] {
        assert!(dir.join("result").join(f).is_file(), "{f}");
    }

    // A non-numeric field: non-zero exit, one line naming file:line:column.
    let imu = std::fs::read_to_string(dir.join("imu.txt")).unwrap();
    std::fs::write(dir.join("bad.txt"), imu.replacen("0.015 ", "0.0l5 ", 1)).unwrap();
    let out = kestrel(&[
        "process",
        "--imu",
        &d("bad.txt"),
        "--gnss",
        &d("gnss.txt"),
        "--config",
        &d("process.toml"),
        "--out",
        &d("bad"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let line = imu.lines().position(|l| l.starts_with("0.015 ")).unwrap() + 1;
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "kestrel: {}:{line}:1: expected a number (time, s of week), found `0.0l5`\n",
            d("bad.txt")
        )
    );

    // A missing file.
    let out = kestrel(&[
        "process",
        "--imu",
        &d("absent.txt"),
        "--config",
        &d("process.toml"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with(&format!(
            "kestrel: {}: cannot read the file: ",
            d("absent.txt")
        )),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
}

/// A KF-GINS configuration of the shape its example has.
const KF_GINS: &str = "# KF-GINS configuration file\n\
imupath: \"./dataset/imu.txt\"\ngnsspath: \"./dataset/gnss.txt\"\noutputpath: \"./dataset\"\n\
imudatalen: 7\nimudatarate: 200\nstarttime: 456300\nendtime: -1\n\
initpos: [ 30.4447873701, 114.4718632047, 20.899 ]\ninitvel: [ 0.0, 0.0, 0.0 ]\n\
initatt: [ 0.85421502, -2.03480295, 185.70235133 ]\n\
initgyrbias: [ 0, 0, 0 ]    # [deg/h]\ninitaccbias: [ 0, 0, 0 ]    # [mGal]\n\
initgyrscale: [ 0, 0, 0 ]\ninitaccscale: [ 0, 0, 0 ]\n\
initposstd: [ 0.005, 0.004, 0.008 ]\ninitvelstd: [ 0.003, 0.004, 0.004 ]\n\
initattstd: [ 0.003, 0.003, 0.023 ]\n\
imunoise:\n  arw: [0.003, 0.003, 0.003]\n  vrw: [0.03, 0.03, 0.03]\n  gbstd: [0.027, 0.027, 0.027]\n  \
abstd: [15.0, 15.0, 15.0]\n  gsstd: [300.0, 300.0, 300.0]\n  asstd: [300.0, 300.0, 300.0]\n  \
corrtime: 4.0\n\
antlever:  [ 0.136, -0.301, -0.184 ]\n";

#[test]
fn a_kf_gins_configuration_imports_with_every_unit_exact() {
    use kestrel_app::config::process::parse;
    use kestrel_app::import::kf_gins;
    let yaml = Path::new("kf-gins.yaml");
    let i = kf_gins(KF_GINS, yaml, None).unwrap();
    let s = parse(&i.toml, Path::new("imported.toml")).unwrap();
    // The SI values KF-GINS uses, bit for bit: 15 mGal = 1.5e-4 m/s²
    // (15.2957… µg, not 15), 0.027 deg/h, 4 h = 14 400 s.
    assert_eq!(s.imu.accel_markov_sigma, 15.0 * 1e-5);
    assert_eq!(s.p0.accel_bias.x, 15.0 * 1e-5);
    assert_eq!(
        s.imu.gyro_markov_sigma,
        0.027 * std::f64::consts::PI / 180.0 / 3600.0
    );
    assert_eq!(
        (s.imu.gyro_markov_tau, s.imu.accel_markov_tau),
        (14_400.0, 14_400.0)
    );
    assert_eq!(s.imu.gyro_arw, 0.003 * std::f64::consts::PI / 180.0 / 60.0);
    assert_eq!(s.lever_arm.y, -0.301);
    assert_eq!(s.start.time, 456_300.0);
    assert_eq!(s.covariance_interval, 0.0);
    assert_eq!(i.warnings.len(), 2, "{:?}", i.warnings);
    assert!(i
        .toml
        .contains("# NOT IMPORTED — kf-gins.yaml: imunoise.gsstd not imported"));
    assert_eq!(
        i.command,
        "kestrel process --imu ./dataset/imu.txt --gnss ./dataset/gnss.txt --config process.toml \
         --out ./dataset"
    );
    // What kestrel cannot express is refused, naming the key.
    let cases = [
        ("endtime: -1", "endtime: 457000", "endtime", "kestrel processes to the end of the IMU file: cut the file at the end time, or set endtime: -1"),
        ("initaccbias: [ 0, 0, 0 ]", "initaccbias: [ 10, 0, 0 ]", "initaccbias", "kestrel starts its bias estimates at zero and has no scale-factor states: correct the IMU data by these values first, or set them to 0"),
        ("arw: [0.003, 0.003, 0.003]", "arw: [0.003, 0.004, 0.003]", "imunoise.arw", "kestrel's IMU noise is the same on the three axes: found [0.003, 0.004, 0.003]"),
        ("imudatarate: 200", "imudatarate: 200\nodometer: true", "odometer", "not a KF-GINS key kestrel knows; remove it or convert it by hand"),
        ("antlever:  [ 0.136, -0.301, -0.184 ]", "antlever:  [ 0.136, -0.301 ]", "antlever", "expected a list of exactly 3 numbers"),
        // Hours whose seconds overflow were taken as a constant bias.
        ("corrtime: 4.0", "corrtime: 1e306", "imunoise.corrtime", "expected a time in hours ≥ 2.7778e-7 (1 ms) whose seconds are finite, found 1e306"),
        ("corrtime: 4.0", "corrtime: 1e-300", "imunoise.corrtime", "expected a time in hours ≥ 2.7778e-7 (1 ms) whose seconds are finite, found 1e-300"),
    ];
    for (from, to, key, msg) in cases {
        let e = kf_gins(&KF_GINS.replace(from, to), yaml, None)
            .unwrap_err()
            .to_string();
        assert_eq!(e, format!("kf-gins.yaml: key `{key}`: {msg}"));
    }
    // What converts outside the range `process` accepts is refused at
    // import, not written for `process` to refuse later.
    let e = kf_gins(
        &KF_GINS.replace("arw: [0.003, 0.003, 0.003]", "arw: [1e100, 1e100, 1e100]"),
        yaml,
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with(
            "kf-gins.yaml: cannot be imported: a value converts outside kestrel's range ("
        ) && e.contains("key `imu.gyro_arw`: expected at most 100 in magnitude"),
        "{e}"
    );
    let e = kf_gins("a: [1, 2\n", yaml, None).unwrap_err().to_string();
    assert!(e.starts_with("kf-gins.yaml:"), "{e}");
    // The binary writes the file and refuses to overwrite it.
    let dir = tmp_dir("import");
    std::fs::write(dir.join("kf-gins.yaml"), KF_GINS).unwrap();
    let d = |f: &str| dir.join(f).display().to_string();
    let out = kestrel(&[
        "import",
        "kf-gins",
        &d("kf-gins.yaml"),
        "--out",
        &d("p.toml"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("warning: "));
    let again = kestrel(&[
        "import",
        "kf-gins",
        &d("kf-gins.yaml"),
        "--out",
        &d("p.toml"),
    ]);
    assert_eq!(again.status.code(), Some(1));
}

/// The improved adaptive filter with the whole-state fade (γ = 1, λ ≤ 10,
/// `fade_states = "all"`, the defaults of a `process` configuration) runs
/// away on scenario 002's drive (seed 1001): hundreds of kilometres within
/// minutes. `process` used to end with status 0, "0 rejected" and no
/// warning. The health monitor reports it within 60 s of the onset (the
/// first update with a position error above 50 m, five times the
/// standard EKF's largest on these data), the summary warns that the run
/// diverged, and `--stop-on-divergence` stops it with an error and no
/// result files. The standard EKF on the same multipath data is warned
/// about too: its NEES leaves its bound (its covariance ignores the
/// multipath).
#[test]
fn a_runaway_is_reported_and_stops_the_run_when_asked() {
    use kestrel_app::experiment::HealthEventKind;
    use kestrel_app::scenario::FadeBlock;
    let (seed, duration) = (1001, 200.0);
    let dir = sim("002", seed, duration);
    let sc = by_name("002").unwrap();
    let kind = FilterKind::ImprovedAdaptive {
        forgetting: 0.97,
        reserve: 1.0,
        lambda_max: 10.0,
        significance: 0.05,
        fade_states: FadeBlock::All,
    };
    let truth = sc.trajectory().unwrap().initial_state();
    let config = process_config(&sc, &sc.initial_state(&truth), &kind);
    std::fs::write(dir.join("process.toml"), config).unwrap();
    let onset = run(
        &sc,
        &kind,
        seed,
        &RunOptions::default().with_duration(duration),
    )
    .unwrap()
    .records
    .iter()
    .find(|r| r.position.norm() > 50.0)
    .map(|r| r.time)
    .expect("the filter runs away");
    let report = process(&args(&dir, false), &Context::default()).unwrap();
    let first = report.health.first_alarm.expect("an alarm");
    println!("onset {onset} s, alarm {first}");
    assert_eq!(first.kind, HealthEventKind::Alarm);
    assert!(
        first.time >= onset - 60.0 && first.time <= onset + 60.0,
        "onset {onset} s, alarm at {} s",
        first.time
    );
    assert!(report.health.diverged());
    let text = kestrel_cli::process::summary(&report);
    assert!(
        text.contains("warning: improved adaptive diverging at"),
        "{text}"
    );
    assert!(
        text.contains("warning: improved adaptive diverged"),
        "{text}"
    );
    // Stopped when asked: an error naming the alarm, no result left.
    let mut stop = args(&dir, false);
    stop.out = dir.join("stopped");
    stop.stop_on_divergence = true;
    let e = process(&stop, &Context::default()).unwrap_err().to_string();
    assert!(
        e.contains("stopped (--stop-on-divergence)") && e.contains("diverging at"),
        "{e}"
    );
    assert!(!dir.join("stopped/result.nav").exists());
    // The standard EKF on the same data: its NEES alarm is a warning.
    let ekf = process_config(&sc, &sc.initial_state(&truth), &FilterKind::Standard);
    std::fs::write(dir.join("ekf.toml"), ekf).unwrap();
    let mut plain = args(&dir, false);
    plain.config = dir.join("ekf.toml");
    plain.out = dir.join("ekf");
    let report = process(&plain, &Context::default()).unwrap();
    let text = kestrel_cli::process::summary(&report);
    assert!(text.contains("warning: KF diverging at"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}
