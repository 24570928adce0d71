//! What real logs and real users do to `kestrel`, end to end on a simulated
//! 200 Hz drive: a dropped IMU sample is bridged and reported, a gap longer
//! than `max_gap` is an error naming the line (or coasted when configured),
//! a log that starts late after `initial.time` is refused the same way, a
//! GPS week rollover in every file changes nothing; outputs never replace
//! inputs or write through links, a failed run leaves no result file,
//! `simulate` does not overwrite without `--force`, and run counts and
//! thread counts are bounded before work starts.

use kestrel_cli::Context;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use kestrel_app::process::summary;
use kestrel_app::simulate::{simulate, SimulateOptions};
use kestrel_cli::process::{process, ProcessArgs};

use crate::support;

fn sim(seed: u64, duration: f64) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let k = N.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("kestrel-timing-{}-{k}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    simulate(&SimulateOptions {
        scenario: "002".into(),
        seed: Some(seed),
        duration: Some(duration),
        imu_rate: None,
        out: dir.clone(),
        force: false,
    })
    .unwrap();
    dir
}

/// A run of the simulated files in `dir` with their `process.toml`, no
/// outages.
fn args(dir: &Path, out: &str) -> ProcessArgs {
    support::run_args(dir, "process.toml", out, &[])
}

/// Rewrites the IMU file without the data lines whose time is in
/// `[from, to)`; returns the line number (1-based) of the first line after.
fn drop_imu(dir: &Path, from: f64, to: f64) -> usize {
    let text = std::fs::read_to_string(dir.join("imu.txt")).unwrap();
    let mut kept = Vec::new();
    let mut after = None;
    for l in text.lines() {
        let t = l
            .split(' ')
            .next()
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|_| !l.starts_with('#'));
        match t {
            Some(t) if t >= from && t < to => continue,
            Some(t) if t >= to && after.is_none() => after = Some(kept.len() + 1),
            _ => {}
        }
        kept.push(l);
    }
    std::fs::write(dir.join("imu.txt"), kept.join("\n") + "\n").unwrap();
    after.unwrap()
}

fn set_config(dir: &Path, edit: impl Fn(&str) -> String) {
    let p = dir.join("process.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, edit(&text)).unwrap();
}

#[test]
fn a_dropped_sample_is_bridged_and_reported() {
    let dir = sim(3, 30.0);
    let full = process(&args(&dir, "full"), &Context::default()).unwrap();
    assert_eq!(full.timing.gaps, 0);
    assert!((full.timing.nominal - 0.005).abs() < 1e-12);
    let line = drop_imu(&dir, 10.0, 10.004);
    let bridged = process(&args(&dir, "bridged"), &Context::default()).unwrap();
    let t = &bridged.timing;
    assert_eq!((t.gaps, t.first_gaps.len()), (1, 1));
    assert_eq!(t.first_gaps[0].line, line);
    assert!((t.first_gaps[0].seconds - 0.01).abs() < 1e-9);
    let text = summary(&bridged);
    assert!(
        text.contains(&format!(
            "warning: IMU dropout bridged: 0.0100 s before line {line}"
        )),
        "{text}"
    );
    // One lost sample bridged at the held rate costs the solution nearly
    // nothing: the position RMS moves by under a millimetre.
    let (a, b) = (full.errors.unwrap(), bridged.errors.unwrap());
    assert!((a.rms_position - b.rms_position).norm() < 1e-3);
}

#[test]
fn a_long_gap_is_an_error_naming_its_line_unless_coasting_is_configured() {
    let dir = sim(4, 30.0);
    let line = drop_imu(&dir, 10.0, 12.0);
    let e = process(&args(&dir, "r"), &Context::default())
        .unwrap_err()
        .to_string();
    let path = dir.join("imu.txt");
    assert_eq!(
        e,
        format!(
            "{}:{line}:1: gap in the IMU data: 2.005 s since line {}, longer than max_gap = 1 s \
             (the nominal interval is 0.005 s); raise [imu] max_gap or set [imu] long_gap = \
             \"coast\" to bridge it",
            path.display(),
            line - 1
        )
    );
    // The failed run leaves no result file that looks complete.
    assert!(
        !dir.join("r").join("result.nav").exists(),
        "a half-written result"
    );
    set_config(&dir, |t| {
        t.replace("[imu]\n", "[imu]\nlong_gap = \"coast\"\n")
    });
    let r = process(&args(&dir, "coast"), &Context::default()).unwrap();
    assert_eq!(r.timing.gaps, 1);
    assert!(r.timing.longest.unwrap().long);
    set_config(&dir, |t| {
        t.replace("long_gap = \"coast\"\n", "max_gap = 2.5\n")
    });
    let r = process(&args(&dir, "wide"), &Context::default()).unwrap();
    assert!(!r.timing.longest.unwrap().long);
}

#[test]
fn a_log_starting_late_after_the_initial_time_is_refused() {
    let dir = sim(5, 30.0);
    let line = drop_imu(&dir, 0.0, 3.0);
    let e = process(&args(&dir, "r"), &Context::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!(
            "imu.txt:{line}:1: gap in the IMU data: 3 s since initial.time, longer than \
             max_gap = 1 s"
        )),
        "{e}"
    );
}

#[test]
fn a_week_rollover_changes_nothing() {
    let dir = sim(6, 20.0);
    let before = process(&args(&dir, "plain"), &Context::default()).unwrap();
    // Move every time so that the run crosses the end of the week at 10 s:
    // IMU and GNSS in seconds of week, the truth in week + seconds.
    let shift = 604_800.0 - 10.0;
    let wrap = |t: f64| {
        let s = t + shift;
        if s >= 604_800.0 {
            (1, s - 604_800.0)
        } else {
            (0, s)
        }
    };
    for name in ["imu.txt", "gnss.txt"] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let out: Vec<String> = text
            .lines()
            .map(|l| {
                if l.starts_with('#') {
                    return l.to_string();
                }
                let mut f: Vec<&str> = l.split(' ').collect();
                let t = wrap(f[0].parse().unwrap()).1.to_string();
                f[0] = &t;
                f.join(" ")
            })
            .collect();
        std::fs::write(dir.join(name), out.join("\n") + "\n").unwrap();
    }
    let text = std::fs::read_to_string(dir.join("truth.nav")).unwrap();
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with('#') {
                return l.to_string();
            }
            let mut f: Vec<String> = l.split(' ').map(String::from).collect();
            let week: u32 = f[0].parse().unwrap();
            let (w, s) = wrap(f[1].parse().unwrap());
            f[0] = (week + w).to_string();
            f[1] = s.to_string();
            f.join(" ")
        })
        .collect();
    std::fs::write(dir.join("truth.nav"), out.join("\n") + "\n").unwrap();
    set_config(&dir, |t| {
        let i = t.find("time = ").unwrap();
        let end = i + t[i..].find('\n').unwrap();
        let old: f64 = t[i + 7..end]
            .split('#')
            .next()
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        format!("{}time = {}{}", &t[..i], old + shift, &t[end..])
    });
    let after = process(&args(&dir, "rolled"), &Context::default()).unwrap();
    assert_eq!(after.samples, before.samples);
    assert_eq!(after.updates, before.updates);
    let (a, b) = (before.errors.unwrap(), after.errors.unwrap());
    assert_eq!(a.epochs, b.epochs);
    // Times near 604 800 s carry 1e-10 s less precision than near 0: the
    // solutions agree to far below a millimetre.
    assert!(
        (a.rms_position - b.rms_position).norm() < 1e-4,
        "{a:?} {b:?}"
    );
    // The output continues in the next week.
    let nav = std::fs::read_to_string(dir.join("rolled").join("result.nav")).unwrap();
    let last = nav.lines().last().unwrap();
    let week: u32 = last.split(' ').next().unwrap().parse().unwrap();
    let first_week: u32 = nav
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(week, first_week + 1, "{last}");
}

/// Outputs never replace inputs: a truth file inside `--out` under a result
/// name, or a symbolic link there pointing at an input, stops the run
/// before anything is written, and the input is intact.
#[test]
fn outputs_never_replace_inputs() {
    let dir = sim(7, 5.0);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::copy(dir.join("truth.nav"), out.join("result.nav")).unwrap();
    let before = std::fs::read(out.join("result.nav")).unwrap();
    let mut a = args(&dir, "out");
    a.truth = Some(out.join("result.nav"));
    let e = process(&a, &Context::default()).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "refusing to write {}: it is the --truth input {}; choose another output folder",
            out.join("result.nav").display(),
            out.join("result.nav").display()
        )
    );
    assert_eq!(std::fs::read(out.join("result.nav")).unwrap(), before);
    // A link named result.csv pointing at the IMU file.
    let linked = dir.join("linked");
    std::fs::create_dir_all(&linked).unwrap();
    std::os::unix::fs::symlink(dir.join("imu.txt"), linked.join("result.csv")).unwrap();
    let imu = std::fs::read(dir.join("imu.txt")).unwrap();
    let e = process(&args(&dir, "linked"), &Context::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("it is the --imu input"), "{e}");
    assert_eq!(std::fs::read(dir.join("imu.txt")).unwrap(), imu);
    // A link to an unrelated file is the user's: refused, and with
    // --force replaced, never written through.
    let other = dir.join("other.txt");
    std::fs::write(&other, "keep me").unwrap();
    let replaced = dir.join("replaced");
    std::fs::create_dir_all(&replaced).unwrap();
    std::os::unix::fs::symlink(&other, replaced.join("result.nav")).unwrap();
    std::os::unix::fs::symlink(&other, replaced.join("errors.csv")).unwrap();
    let mut a = args(&dir, "replaced");
    let e = process(&a, &Context::default()).unwrap_err().to_string();
    assert!(e.starts_with("refusing to replace"), "{e}");
    a.force = true;
    process(&a, &Context::default()).unwrap();
    assert_eq!(std::fs::read_to_string(&other).unwrap(), "keep me");
    assert!(
        std::fs::read_to_string(replaced.join("errors.csv"))
            .unwrap()
            .len()
            > 100
    );
    assert!(!std::fs::symlink_metadata(replaced.join("result.nav"))
        .unwrap()
        .file_type()
        .is_symlink());
}

/// `simulate` replaces the files an earlier run into the folder wrote (its
/// manifest lists them) and never a file of the user's without `--force`.
#[test]
fn simulate_replaces_its_own_files_and_refuses_the_users() {
    let dir = sim(8, 2.0);
    let imu = std::fs::read(dir.join("imu.txt")).unwrap();
    let mut a = SimulateOptions {
        scenario: "002".into(),
        seed: Some(9),
        duration: Some(2.0),
        imu_rate: None,
        out: dir.clone(),
        force: false,
    };
    simulate(&a).unwrap();
    assert_ne!(std::fs::read(dir.join("imu.txt")).unwrap(), imu);
    // The same names in a folder no kestrel run wrote: the user's files.
    let mine = dir.join("mine");
    std::fs::create_dir_all(&mine).unwrap();
    std::fs::write(mine.join("imu.txt"), "my data\n").unwrap();
    a.out = mine.clone();
    let e = simulate(&a).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "refusing to replace {}: no earlier kestrel run into this folder wrote it (no \
             manifest lists it); move it away or pass --force",
            mine.join("imu.txt").display()
        )
    );
    assert_eq!(
        std::fs::read_to_string(mine.join("imu.txt")).unwrap(),
        "my data\n"
    );
    assert!(
        !mine.join("gnss.txt").exists(),
        "nothing published on a refusal"
    );
    a.force = true;
    simulate(&a).unwrap();
    assert_ne!(
        std::fs::read_to_string(mine.join("imu.txt")).unwrap(),
        "my data\n"
    );
}

/// `--runs` and `--threads` are checked before any work, with the limit
/// named (no capacity-overflow panic, no 20 000-thread pool).
#[test]
fn run_and_thread_counts_are_bounded() {
    let kestrel = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_kestrel"))
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, err) = kestrel(&["reproduce", "000", "--runs", "18446744073709551615"]);
    assert_eq!(code, Some(2));
    assert!(
        err.starts_with(
            "error: invalid value '18446744073709551615' for '--runs <N>': \
             18446744073709551615 is not in 1..=10000"
        ),
        "{err}"
    );
    let (code, err) = kestrel(&["reproduce", "000", "--threads", "20000"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("20000 is not in 0..=256"), "{err}");
}

/// The timing keys refuse what they cannot mean, naming the key.
#[test]
fn timing_keys_refuse_hostile_values() {
    let dir = sim(10, 2.0);
    for (line, want) in [
        (
            "max_gap = -1.0",
            "key `imu.max_gap`: expected a finite value > 0, found -1",
        ),
        (
            "max_gap = nan",
            "key `imu.max_gap`: expected a finite value > 0, found NaN",
        ),
        (
            "max_gap = 0.0",
            "key `imu.max_gap`: expected a finite value > 0, found 0",
        ),
        (
            "long_gap = \"maybe\"",
            "key `imu.long_gap`: expected `error` or `coast`, found `maybe`",
        ),
    ] {
        set_config(&dir, |t| {
            let base: String = t
                .lines()
                .filter(|l| !l.starts_with("max_gap") && !l.starts_with("long_gap"))
                .map(|l| format!("{l}\n"))
                .collect();
            base.replace("[imu]\n", &format!("[imu]\n{line}\n"))
        });
        let e = process(&args(&dir, "r"), &Context::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{line}: {e}");
    }
}

/// Rewrites the truth file with `shift` s added to every time.
fn shift_truth(dir: &Path, shift: f64) {
    let p = dir.join("truth.nav");
    let text = std::fs::read_to_string(&p).unwrap();
    let shifted: String = text
        .lines()
        .map(|l| {
            if l.starts_with('#') {
                return format!("{l}\n");
            }
            let mut f: Vec<String> = l.split(' ').map(String::from).collect();
            f[1] = (f[1].parse::<f64>().unwrap() + shift).to_string();
            f.join(" ") + "\n"
        })
        .collect();
    std::fs::write(&p, shifted).unwrap();
}

#[test]
fn errors_are_evaluated_at_every_truth_epoch_and_never_over_nothing() {
    let dir = sim(4, 10.0);
    let exact = process(&args(&dir, "exact"), &Context::default()).unwrap();
    let all = exact.errors.unwrap();
    assert_eq!(all.epochs, exact.samples);
    assert_eq!(exact.aiding_errors.unwrap().epochs, exact.fixes_used);

    // A truth 2 µs off every sample: compared at its own epochs, the
    // solution interpolated between samples; same errors to 1e-3.
    shift_truth(&dir, 2e-6);
    let off = process(&args(&dir, "off"), &Context::default()).unwrap();
    let e = off.errors.unwrap();
    assert_eq!(
        e.epochs,
        exact.samples - 1,
        "the last truth epoch is after the run"
    );
    for i in 0..3 {
        let (a, b) = (e.rms_position[i], all.rms_position[i]);
        assert!((a - b).abs() < 1e-3 * b, "{a} vs {b}");
    }
    // No truth epoch is at an aiding sample: there is no "after the update"
    // line rather than one over nothing.
    assert!(off.aiding_errors.is_none());
    assert!(
        !summary(&off).contains("aiding epochs"),
        "{}",
        summary(&off)
    );

    // A truth that starts after the run, and an empty one: errors that say
    // why, and no result files.
    shift_truth(&dir, 100.0);
    let e = process(&args(&dir, "late"), &Context::default())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        format!(
            "{}: no truth epoch to compare with: the truth starts at 100.000002 s of week, \
             after the run's last IMU sample at 10 s",
            dir.join("truth.nav").display()
        )
    );
    assert!(!dir.join("late/result.nav").exists() && !dir.join("late/errors.csv").exists());
    std::fs::write(dir.join("truth.nav"), "# nothing yet\n").unwrap();
    let e = process(&args(&dir, "empty"), &Context::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.ends_with("no truth epoch to compare with: the file has no data lines"),
        "{e}"
    );
}

#[test]
fn drift_is_reported_per_outage_and_gap_and_never_over_nothing() {
    let dir = sim(6, 10.0);
    // Without GNSS the run is compared at every epoch; no aiding line.
    let mut a = args(&dir, "ins");
    a.gnss = None;
    let ins = process(&a, &Context::default()).unwrap();
    assert_eq!(ins.errors.unwrap().epochs, 2000);
    assert!(ins.aiding_errors.is_none() && ins.drift.is_empty());
    // Every fix inside an outage; a second window after the run.
    let mut a = args(&dir, "windows");
    a.outages = vec!["0:100".parse().unwrap(), "200:300".parse().unwrap()];
    let r = process(&a, &Context::default()).unwrap();
    assert_eq!((r.fixes_used, r.fixes_in_outage), (0, 10));
    assert_eq!(r.drift[0].epochs, 2000);
    assert_eq!(r.drift[1].epochs, 0);
    assert!(r.drift[1].horizontal.is_none());
    let s = summary(&r);
    assert!(
        s.contains("  outage 200 to 300 s (100 s): no truth epoch in the window\n"),
        "{s}"
    );
    let csv = std::fs::read_to_string(dir.join("windows/drift.csv")).unwrap();
    assert_eq!(csv.lines().nth(2), Some("outage,200,300,100,0,,,,"));
    // No fix used: the whole run is one gap of the fixes.
    assert_eq!(r.drift.len(), 3);
    assert_eq!(
        (r.drift[2].start, r.drift[2].end, r.drift[2].epochs),
        (0.0, 10.0, 2000)
    );
    // The printed statistics are numbers, never NaN or inf.
    assert!(!s.contains("NaN") && !s.contains("inf"), "{s}");
}

#[test]
fn every_gnss_line_is_read_and_checked_even_after_the_imu_ends() {
    let dir = sim(8, 5.0);
    let gnss = std::fs::read_to_string(dir.join("gnss.txt")).unwrap();
    let last = gnss.lines().last().unwrap().to_owned();
    let fix_at = |t: f64| {
        let mut f: Vec<&str> = last.split(' ').collect();
        let t = t.to_string();
        f[0] = &t;
        f.join(" ")
    };
    // Good fixes after the run: read, counted, reported.
    let extra: String = (6..9).map(|t| fix_at(f64::from(t)) + "\n").collect();
    std::fs::write(dir.join("gnss.txt"), format!("{gnss}{extra}")).unwrap();
    let r = process(&args(&dir, "after"), &Context::default()).unwrap();
    assert_eq!((r.fixes_used, r.fixes_after_end), (5, 3));
    assert!(summary(&r).contains(
        "warning: 3 GNSS fixes after the last IMU sample were read and checked but not used\n"
    ));
    // A far-future fix followed by the rest of the file: the time that
    // goes back is found, not skipped by waiting for the far fix.
    let text = format!("{gnss}{}\n{}\n", fix_at(9e4), fix_at(7.0));
    std::fs::write(dir.join("gnss.txt"), &text).unwrap();
    let lines = text.lines().count();
    let e = process(&args(&dir, "far"), &Context::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{}:{lines}:1: time does not increase: 7 s after 90000 s",
            dir.join("gnss.txt").display()
        )),
        "{e}"
    );
    // A garbage line after the run is an error naming it.
    std::fs::write(dir.join("gnss.txt"), format!("{gnss}{extra}x y\n")).unwrap();
    let e = process(&args(&dir, "garbage"), &Context::default())
        .unwrap_err()
        .to_string();
    let n = gnss.lines().count() + 4;
    assert!(
        e.starts_with(&format!("{}:{n}:", dir.join("gnss.txt").display())),
        "{e}"
    );
    assert!(!dir.join("garbage/result.nav").exists());
}

#[test]
fn simulated_sizes_are_bounded_before_work_starts() {
    let dir = std::env::temp_dir().join(format!("kestrel-size-{}", std::process::id()));
    let try_sim = |duration: Option<f64>, imu_rate: Option<f64>| {
        simulate(&SimulateOptions {
            scenario: "002".into(),
            seed: Some(1),
            duration,
            imu_rate,
            out: dir.clone(),
            force: true,
        })
        .unwrap_err()
        .to_string()
    };
    let start = std::time::Instant::now();
    assert_eq!(
        try_sim(None, Some(1e9)),
        "scenario 002: 3600 s at 1000000000 Hz would be 3600000000000 IMU samples, more than \
         the limit of 20000000 (about 28 h at 200 Hz): shorten the duration or lower the IMU rate"
    );
    // A duration beyond the scenario's is cut to the scenario (1 h), so a
    // long one only fails with a rate that makes it too long.
    assert!(try_sim(Some(1e9), Some(1e4)).contains("would be 36000000 IMU samples"));
    assert!(start.elapsed().as_secs() < 5, "refused before any work");
    assert!(!dir.join("imu.txt").exists());
}

/// The simulated IMU file rewritten by `line`, which gets the time and the
/// increments (forward-right-down, rad and m/s) of each data line.
fn rewrite_imu(dir: &Path, name: &str, header: &str, line: impl Fn(f64, [f64; 6]) -> String) {
    let text = std::fs::read_to_string(dir.join("imu.txt")).unwrap();
    let mut out = String::from(header);
    for l in text.lines().filter(|l| !l.starts_with('#')) {
        let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
        out += &line(v[0], [v[1], v[2], v[3], v[4], v[5], v[6]]);
        out.push('\n');
    }
    std::fs::write(dir.join(name), out).unwrap();
}

#[test]
fn imu_files_of_other_shapes_are_read_by_configuration() {
    let dir = sim(11, 30.0);
    let gins = process(&args(&dir, "gins"), &Context::default()).unwrap();
    let base = std::fs::read_to_string(dir.join("process.toml")).unwrap();
    let with = |name: &str, table: &str| {
        std::fs::write(dir.join(format!("{name}.toml")), format!("{base}\n{table}")).unwrap();
        let mut a = args(&dir, name);
        a.imu = dir.join(format!("{name}.csv"));
        a.config = dir.join(format!("{name}.toml"));
        process(&a, &Context::default())
    };
    let g = 9.80665;
    // Increments in degrees and g·s, axes x right, y forward, z up, CSV
    // with a header, Unix time: the same data, so the same result to
    // rounding (degrees and g pass through one multiplication each).
    rewrite_imu(
        &dir,
        "increments.csv",
        "unix,dx,dy,dz,vx,vy,vz\n",
        |t, d| {
            let deg = |x: f64| x.to_degrees();
            format!(
                "{},{},{},{},{},{},{}",
                t + 315_964_800.0 - 18.0,
                deg(d[1]),
                deg(d[0]),
                -deg(d[2]),
                d[4] / g,
                d[3] / g,
                -d[5] / g
            )
        },
    );
    let r = with(
        "increments",
        "[imu_file]\ndelimiter = \",\"\nheader_lines = 1\ntime = \"unix\"\nleap_seconds = 18\n\
         gyro_unit = \"deg\"\naccel_unit = \"g*s\"\ng = 9.80665\naxes = [\"y\", \"x\", \"-z\"]\n",
    )
    .unwrap();
    let (a, b) = (r.errors.unwrap(), gins.errors.unwrap());
    assert_eq!((r.samples, r.fixes_used), (gins.samples, gins.fixes_used));
    for i in 0..3 {
        let (x, y) = (a.rms_position[i], b.rms_position[i]);
        assert!((x - y).abs() < 1e-6 * y, "{x} vs {y}");
    }
    // Rates in deg/s and g (each increment / 5 ms, so the rates are the
    // interval means): integrated by the trapezoidal rule, which smooths
    // over two samples. The position RMS differs from the increments' by
    // 0.1 mm on this 30 s drive (RMS 3.8 m); the 1 cm bound leaves room for
    // platforms' rounding and still fails a unit or axis slip, which moves
    // the errors by metres.
    rewrite_imu(
        &dir,
        "rates.csv",
        "Time  Gyro_X  Gyro_Y  Gyro_Z  Accel_X  Accel_Y  Accel_Z\n",
        |t, d| {
            let dt = 0.005;
            let r = |x: f64| x.to_degrees() / dt;
            format!(
                "{t} {} {} {} {} {} {}",
                r(d[1]),
                r(d[0]),
                -r(d[2]),
                d[4] / dt / g,
                d[3] / dt / g,
                -d[5] / dt / g
            )
        },
    );
    let r = with(
        "rates",
        "[imu_file]\nheader_lines = 1\nmeasures = \"rates\"\ngyro_unit = \"deg/s\"\n\
         accel_unit = \"g\"\ng = 9.80665\naxes = [\"y\", \"x\", \"-z\"]\n",
    )
    .unwrap();
    let a = r.errors.unwrap();
    let d = (a.rms_position - b.rms_position).norm();
    assert!(d < 0.01, "rates vs increments: {d} m");
    // The mistakes a configuration can make, each named.
    let cases = [
        ("measures = \"rates\"\n", "imu_file.gyro_unit", "rates need their unit: one of `rad/s`, `deg/s`, `deg/h`"),
        ("measures = \"rates\"\ngyro_unit = \"deg\"\n", "imu_file.gyro_unit", "rates are in `rad/s`, `deg/s`, `deg/h`, found `deg`"),
        ("accel_unit = \"g*s\"\n", "imu_file.g", "an accelerometer unit in g needs the g value it means (9.80665 for standard gravity; a datasheet may use another)"),
        ("time = \"unix\"\n", "imu_file.leap_seconds", "`unix` time needs leap_seconds, GPS − UTC (18 s since 2017-01-01)"),
        ("axes = [\"y\", \"x\", \"z\"]\n", "imu_file.axes", "these axes mirror the IMU (a left-handed frame): one sign is wrong"),
        ("axes = [\"x\", \"x\", \"z\"]\n", "imu_file.axes", "each of x, y and z must appear once"),
        ("columns = { time = 1, gyro = [2, 3, 4], accel = [5, 6, 4] }\n", "imu_file.columns.accel", "column 4 is already the gyro column"),
        ("time = \"week-seconds\"\n", "imu_file.time", "`week-seconds` needs a columns.week"),
        ("header_lines = 99999999999\n", "imu_file.header_lines", "expected at most 1000 header lines, found 99999999999"),
        ("accel_unit = \"g*s\"\ng = 1e308\n", "imu_file.g", "expected the g of the accelerometer's unit in [9.7, 9.9] m/s², found 1e308"),
    ];
    for (table, key, msg) in cases {
        let e = with("bad", &format!("[imu_file]\n{table}"))
            .unwrap_err()
            .to_string();
        // `bad.toml:LINE:COLUMN: key …`: the place, then the key and message.
        let rest = e
            .strip_prefix(&format!("{}:", dir.join("bad.toml").display()))
            .unwrap_or_else(|| panic!("{e}"));
        let mut parts = rest.splitn(3, ':');
        assert!(
            parts.next().is_some_and(|l| l.parse::<usize>().is_ok()),
            "{e}"
        );
        assert!(
            parts.next().is_some_and(|c| c.parse::<usize>().is_ok()),
            "{e}"
        );
        assert_eq!(parts.next(), Some(format!(" key `{key}`: {msg}").as_str()));
    }
    // A CSV line with a missing column names it.
    std::fs::write(dir.join("bad.csv"), "t,a\n0.005,1,2\n").unwrap();
    let e = with("bad", "[imu_file]\ndelimiter = \",\"\nheader_lines = 1\n")
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        format!(
            "{}:2:4: expected at least 4 columns (Δθ z is column 4), found 3",
            dir.join("bad.csv").display()
        )
    );
}

#[test]
fn rtklib_pos_files_are_read_with_their_quality_flags() {
    let dir = sim(12, 20.0);
    let gnss = std::fs::read_to_string(dir.join("gnss.txt")).unwrap();
    let data: Vec<Vec<String>> = gnss
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(' ').map(String::from).collect())
        .collect();
    assert_eq!(data[0].len(), 13, "fixes with velocity");
    // The same fixes as RTKLIB writes them: date and time in GPST (week 0
    // starts 1980-01-06), σ, ENU velocity; every fifth fix single (Q = 5).
    let mut pos = String::from(
        "% program   : RTKPOST ver.2.4.3\n\
         % (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp)\n\
         %  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   \
         sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio    vn(m/s)    ve(m/s)    \
         vu(m/s)      sdvn     sdve     sdvu    sdvne    sdveu    sdvun\n",
    );
    let mut kept = String::new();
    for (k, f) in data.iter().enumerate() {
        let t: f64 = f[0].parse().unwrap();
        let q = if k % 5 == 4 { 5 } else { 1 };
        let vu = -f[9].parse::<f64>().unwrap();
        pos += &format!(
            "1980/01/06 00:00:{:06.3} {} {} {} {q} 12 {} {} {} 0 0 0 0.0 99.9 {} {} {vu} {} {} {} 0 0 0\n",
            t, f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[10], f[11], f[12]
        );
        if q == 1 {
            kept += &f.join(" ");
            kept.push('\n');
        }
    }
    std::fs::write(dir.join("sol.pos"), &pos).unwrap();
    std::fs::write(dir.join("kept.txt"), &kept).unwrap();
    let base = std::fs::read_to_string(dir.join("process.toml")).unwrap();
    let config = |name: &str, table: &str| {
        let p = dir.join(format!("{name}.toml"));
        std::fs::write(&p, format!("{base}\n{table}")).unwrap();
        p
    };
    let mut a = args(&dir, "pos");
    a.gnss = Some(dir.join("sol.pos"));
    a.config = config(
        "pos",
        "[gnss_file]\nformat = \"rtklib\"\nquality = [1, 2]\n",
    );
    let r = process(&a, &Context::default()).unwrap();
    assert_eq!((r.fixes_used, r.fixes_refused_quality), (16, 4));
    assert!(summary(&r).contains("4 GNSS fixes skipped for their quality flag"));
    // Bit for bit the run on the GINS file without the single fixes.
    let mut b = args(&dir, "kept");
    b.gnss = Some(dir.join("kept.txt"));
    process(&b, &Context::default()).unwrap();
    let read = |d: &str| std::fs::read_to_string(dir.join(d).join("result.nav")).unwrap();
    assert_eq!(read("pos"), read("kept"));
    // What RTKLIB options kestrel cannot read, and a σ of 0, are named.
    let cases = [
        (pos.replace("%  GPST ", "%  UTC "), 3, 1, "time in UTC: set RTKLIB's time system to GPST (out-timesys = gpst)"),
        (pos.replace("latitude(deg) longitude(deg)  height(m)", "x-ecef(m) y-ecef(m) z-ecef(m)"), 3, 1, "positions in ECEF or ENU: set RTKLIB's solution format to lat/lon/height (out-solformat = llh) in decimal degrees"),
        (pos.replacen(" 12 ", " 12 0 ", 1).replacen(" 0 0 0 0.0 99.9", " 0 0 0.0 99.9", 1), 4, 8, "expected a standard deviation in [1e-150, 1e150] (its square must be a normal double), found 0 (RTKLIB writes 0 when it has no estimate; use [gnss] noise = \"fixed\" and drop such lines)"),
    ];
    for (text, line, column, msg) in cases {
        std::fs::write(dir.join("bad.pos"), text).unwrap();
        a.gnss = Some(dir.join("bad.pos"));
        let e = process(&a, &Context::default()).unwrap_err().to_string();
        assert_eq!(
            e,
            format!("{}:{line}:{column}: {msg}", dir.join("bad.pos").display())
        );
    }
    a.config = config("q", "[gnss_file]\nformat = \"rtklib\"\nquality = [7]\n");
    let e = process(&a, &Context::default()).unwrap_err().to_string();
    assert!(e.ends_with("key `gnss_file.quality`: expected RTKLIB's flags 1 (fix), 2 (float), 3 (SBAS), 4 (DGPS), 5 (single), 6 (PPP), found 7"), "{e}");
}

#[test]
fn the_odometer_in_its_own_file_and_with_position_only_gnss() {
    static N: AtomicUsize = AtomicUsize::new(0);
    let k = N.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("kestrel-odo-{}-{k}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    simulate(&SimulateOptions {
        scenario: "003".into(),
        seed: Some(2),
        duration: Some(20.0),
        imu_rate: None,
        out: dir.clone(),
        force: false,
    })
    .unwrap();
    let imu = std::fs::read_to_string(dir.join("imu.txt")).unwrap();
    let mut odo = String::new();
    let mut seven = String::new();
    for l in imu.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = l.split(' ').collect();
        odo += &format!("{} {}\n", f[0], f[7]);
        seven += &(f[..7].join(" ") + "\n");
    }
    std::fs::write(dir.join("odo.txt"), odo).unwrap();
    std::fs::write(dir.join("imu7.txt"), seven).unwrap();
    let mut a = args(&dir, "column");
    a.gnss = None;
    a.odo = true;
    let column = process(&a, &Context::default()).unwrap();
    let mut b = args(&dir, "file");
    b.gnss = None;
    b.imu = dir.join("imu7.txt");
    b.odometer = Some(dir.join("odo.txt"));
    let file = process(&b, &Context::default()).unwrap();
    assert_eq!(column.updates, file.updates);
    assert!(file.updates > 0);
    let read = |d: &str| std::fs::read_to_string(dir.join(d).join("result.nav")).unwrap();
    assert_eq!(
        read("column"),
        read("file"),
        "the same speeds give the same run"
    );

    // Position-only GNSS (7 columns, from the truth at 1 Hz) with the
    // odometer model: accepted, and it bounds the position error.
    let truth = std::fs::read_to_string(dir.join("truth.nav")).unwrap();
    let fixes: String = truth
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            let t: f64 = f[1].parse().ok()?;
            (t > 0.0 && t.fract() == 0.0)
                .then(|| format!("{} {} {} {} 1 1 2\n", f[1], f[2], f[3], f[4]))
        })
        .collect();
    std::fs::write(dir.join("gnss7.txt"), fixes).unwrap();
    let mut c = args(&dir, "pos-only");
    c.gnss = Some(dir.join("gnss7.txt"));
    c.odo = true;
    let aided = process(&c, &Context::default()).unwrap();
    assert_eq!(aided.fixes_used, 20);
    let (with, without) = (aided.errors.unwrap(), column.errors.unwrap());
    assert!(
        with.max_position_3d < without.max_position_3d,
        "{with:?} {without:?}"
    );
    // An empty odometer file is an error, not a run without odometer.
    std::fs::write(dir.join("odo-empty.txt"), "# nothing\n").unwrap();
    let mut e = args(&dir, "empty");
    e.gnss = None;
    e.imu = dir.join("imu7.txt");
    e.odometer = Some(dir.join("odo-empty.txt"));
    assert_eq!(
        process(&e, &Context::default()).unwrap_err().to_string(),
        format!(
            "{}: no odometer reading at or before the last IMU sample (an empty file, or times \
             that are not GPS seconds of week like the IMU's)",
            dir.join("odo-empty.txt").display()
        )
    );
    assert!(!dir.join("empty/result.nav").exists());
    // Both sources at once is refused.
    c.odometer = Some(dir.join("odo.txt"));
    let e = process(&c, &Context::default()).unwrap_err().to_string();
    assert_eq!(
        e,
        "give the odometer speeds either in the IMU file (--odo) or in their own file \
         (--odometer), not both"
    );
}

#[test]
fn a_position_only_reference_and_one_at_the_antenna() {
    let dir = sim(13, 20.0);
    // The truth as an RTKLIB .pos of a better receiver at 1 Hz, and the
    // same epochs in the navigation format.
    let truth = std::fs::read_to_string(dir.join("truth.nav")).unwrap();
    let mut pos = String::from(
        "%  GPST  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)  \
         sdne(m)  sdeu(m)  sdun(m) age(s)  ratio\n",
    );
    let mut nav = String::new();
    for l in truth.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = l.split(' ').collect();
        let t: f64 = f[1].parse().unwrap();
        if t > 0.0 && t.fract() == 0.0 {
            pos += &format!(
                "0 {} {} {} {} 1 20 0.01 0.01 0.02 0 0 0 0 0\n",
                f[1], f[2], f[3], f[4]
            );
            nav += &format!("{l}\n");
        }
    }
    std::fs::write(dir.join("truth.pos"), pos).unwrap();
    std::fs::write(dir.join("truth1hz.nav"), nav).unwrap();
    let base = std::fs::read_to_string(dir.join("process.toml")).unwrap();
    let with = |name: &str, table: &str, truth: &str| {
        std::fs::write(dir.join(format!("{name}.toml")), format!("{base}\n{table}")).unwrap();
        let mut a = args(&dir, name);
        a.truth = Some(dir.join(truth));
        a.config = dir.join(format!("{name}.toml"));
        process(&a, &Context::default()).unwrap()
    };
    let p = with("pos", "[truth_file]\nformat = \"rtklib\"\n", "truth.pos");
    let n = with("nav", "", "truth1hz.nav");
    let (pe, ne) = (p.errors.unwrap(), n.errors.unwrap());
    assert_eq!((pe.epochs, ne.epochs), (20, 20));
    assert_eq!(
        pe.rms_position, ne.rms_position,
        "the same positions, the same errors"
    );
    assert!(pe.motion.is_none() && ne.motion.is_some());
    let s = summary(&p);
    assert!(
        s.contains("(a position-only reference: no velocity or attitude errors)"),
        "{s}"
    );
    let csv = std::fs::read_to_string(dir.join("pos/errors.csv")).unwrap();
    assert!(csv.lines().nth(1).unwrap().contains(",,,,,,"), "{csv}");

    // A reference at the antenna (0.25, 0.1, -1.05 m from the IMU in this
    // scenario): the truth moved by the lever arm. Compared at the antenna
    // it gives the errors at the IMU to within the attitude error × 1.1 m
    // (millimetres); compared at the IMU it is a metre off vertically.
    let settings = kestrel_app::config::process::load(&dir.join("process.toml")).unwrap();
    let lever = settings.lever_arm;
    let mut moved = String::new();
    for r in kestrel_io::gins::NavReader::open(&dir.join("truth.nav")).unwrap() {
        let mut r = r.unwrap();
        r.state.pos = settings
            .earth
            .displace(&r.state.pos, &(r.state.att * lever));
        kestrel_io::gins::nav_line(r.week, &r.state, &mut moved);
    }
    std::fs::write(dir.join("antenna.nav"), moved).unwrap();
    let at = |name: &str, table: &str, truth: &str| with(name, table, truth).errors.unwrap();
    let imu = at("imu-pt", "", "truth.nav");
    let antenna = at("ant-pt", "[truth_file]\nat = \"antenna\"\n", "antenna.nav");
    let wrong = at("wrong-pt", "", "antenna.nav");
    let d = (antenna.rms_position - imu.rms_position).abs().max();
    assert!(d < 0.005, "{d}");
    assert_eq!(wrong.epochs, imu.epochs);
    // Compared at the wrong point, every epoch is off by the lever arm:
    // 1.05 m in height (up is the third axis in this scenario), 0.27 m
    // horizontally, to within the vehicle's tilt.
    let rows = |d: &str| -> Vec<Vec<f64>> {
        std::fs::read_to_string(dir.join(d).join("errors.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').take(4).map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    for (w, i) in rows("wrong-pt").iter().zip(rows("imu-pt")) {
        let (de, dn, du) = (w[1] - i[1], w[2] - i[2], w[3] - i[3]);
        assert!((du + 1.05).abs() < 0.02, "{du}");
        assert!(
            (de.hypot(dn) - 0.25f64.hypot(0.1)).abs() < 0.03,
            "{de} {dn}"
        );
    }
}
