//! The output transaction, single reads and checked output streams, tried
//! with real processes: two runs into one folder, signals, a killed run, a
//! full disk, pipes and FIFOs as inputs, hostile names (docs/integrity.md).
//!
//! A run is held "running" by giving it a FIFO as its IMU file and writing
//! only part of the file into it: the process then waits in the middle of
//! its pass, holding its lock and its scratch folder, until the test writes
//! the rest, signals or kills it.

use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::support::tmp_dir;

fn kestrel() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kestrel"))
}

fn run(args: &[&str]) -> Output {
    kestrel().args(args).output().unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A 120 s simulated drive of scenario 002 (seed 7) in a fresh folder.
fn drive(name: &str) -> PathBuf {
    let dir = tmp_dir("integrity", name);
    let out = run(&[
        "simulate",
        "002",
        "--seed",
        "7",
        "--duration",
        "120",
        "--out",
        &dir.display().to_string(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    dir
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The names in `dir`, sorted (empty when it does not exist).
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Every file of `dir` with its bytes.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    listing(dir)
        .into_iter()
        .map(|n| {
            let b = fs::read(dir.join(&n)).unwrap_or_default();
            (n, b)
        })
        .collect()
}

fn mkfifo(p: &Path) {
    let st = Command::new("mkfifo").arg(p).status().unwrap();
    assert!(st.success());
}

/// The process arguments of a run of `dir`'s drive with IMU file `imu`
/// into `out`.
fn process_args(dir: &Path, imu: &Path, out: &Path, extra: &[&str]) -> Vec<String> {
    let mut a: Vec<String> = [
        "process",
        "--imu",
        &s(imu),
        "--gnss",
        &s(&dir.join("gnss.txt")),
        "--config",
        &s(&dir.join("process.toml")),
        "--out",
        &s(out),
        "--no-plots",
    ]
    .iter()
    .map(|x| x.to_string())
    .collect();
    a.extend(extra.iter().map(|x| x.to_string()));
    a
}

/// A `process` run of `dir`'s drive reading its IMU file from a FIFO that
/// has been given the first half of the file: it waits mid-pass with its
/// lock held. Returns the child and the FIFO's open write end with the
/// rest of the file.
struct Held {
    child: Child,
    fifo: Option<File>,
    head: Option<std::thread::JoinHandle<()>>,
    rest: Vec<u8>,
}

impl Held {
    fn start(dir: &Path, out: &Path, extra: &[&str]) -> Self {
        let fifo_path = dir.join(format!("imu-{}.fifo", listing(dir).len()));
        mkfifo(&fifo_path);
        let child = kestrel()
            .args(process_args(dir, &fifo_path, out, extra))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Read-write: the open never blocks, and the reader sees the end of
        // the file only when the test closes it.
        let fifo = OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(0)
            .open(&fifo_path)
            .unwrap();
        let imu = fs::read(dir.join("imu.txt")).unwrap();
        let half = imu[..imu.len() / 2]
            .iter()
            .rposition(|&b| b == b'\n')
            .unwrap()
            + 1;
        // Less than the pipe's 64 KiB buffer at a time, from a thread: the
        // child may still be starting.
        let head = imu[..half].to_vec();
        let mut w = fifo.try_clone().unwrap();
        let head = std::thread::spawn(move || {
            let _ = w.write_all(&head);
        });
        let held = Self {
            child,
            fifo: Some(fifo.try_clone().unwrap()),
            head: Some(head),
            rest: imu[half..].to_vec(),
        };
        held.wait_for(out, ".kestrel.lock");
        // The lock comes first, the scratch folder right after it.
        let t = Instant::now();
        while scratch_in(out).is_empty() {
            assert!(
                t.elapsed() < Duration::from_secs(60),
                "no scratch folder after 60 s"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        held
    }

    /// Waits until `out/name` exists (at most 60 s).
    fn wait_for(&self, out: &Path, name: &str) {
        let t = Instant::now();
        while !out.join(name).exists() {
            assert!(
                t.elapsed() < Duration::from_secs(60),
                "no {name} in {} after 60 s",
                out.display()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn signal(&self, sig: &str) {
        let st = Command::new("kill")
            .args([sig, &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
    }

    /// Writes the rest of the file, closes it and waits for the run.
    fn finish(mut self) -> Output {
        // The first half is read whole before the rest follows it.
        self.head.take().unwrap().join().unwrap();
        let mut f = self.fifo.take().unwrap();
        let rest = std::mem::take(&mut self.rest);
        std::thread::spawn(move || {
            let _ = f.write_all(&rest);
        });
        ended(self.child)
    }

    /// Waits for the run after a signal, without writing more.
    fn wait(self) -> Output {
        ended(self.child)
    }
}

/// The output of `child`, which must end within 60 s (killed otherwise:
/// a run waiting for a second read of a pipe would wait forever).
fn ended(mut child: Child) -> Output {
    let t = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("still running after 60 s: killed");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn scratch_in(out: &Path) -> Vec<String> {
    listing(out)
        .into_iter()
        .filter(|n| n.starts_with(".kestrel-scratch-"))
        .collect()
}

#[test]
fn a_second_run_into_a_busy_folder_is_refused_at_once() {
    let dir = drive("busy");
    let out = dir.join("out");
    let first = Held::start(&dir, &out, &[]);
    let t = Instant::now();
    let second = kestrel()
        .args(process_args(&dir, &dir.join("imu.txt"), &out, &[]))
        .output()
        .unwrap();
    assert!(t.elapsed() < Duration::from_secs(20), "{:?}", t.elapsed());
    assert_eq!(second.status.code(), Some(1), "{}", text(&second.stderr));
    let err = text(&second.stderr);
    assert!(
        err.contains(&s(&out)) && err.contains(&format!("{}", first.child.id())),
        "{err}"
    );
    // The first run is untouched by the second and publishes its own files.
    let done = first.finish();
    assert!(done.status.success(), "{}", text(&done.stderr));
    let manifest = fs::read_to_string(out.join("kestrel-manifest.json")).unwrap();
    assert!(manifest.contains("imu-"), "{manifest}");
    assert!(listing(&out).contains(&"result.nav".to_string()));
    assert!(scratch_in(&out).is_empty());
    assert!(!out.join(".kestrel.lock").exists());
}

#[test]
fn sigint_and_sigterm_leave_nothing() {
    let dir = drive("signals");
    for (sig, code, extra) in [
        ("-INT", 130, vec![]),
        ("-TERM", 143, vec!["--smooth", "--truth"]),
    ] {
        let out = dir.join(format!("out{code}"));
        let truth = s(&dir.join("truth.nav"));
        let extra: Vec<&str> = extra
            .iter()
            .copied()
            .chain((code == 143).then_some(truth.as_str()))
            .collect();
        let held = Held::start(&dir, &out, &extra);
        assert_eq!(scratch_in(&out).len(), 1, "{:?}", listing(&out));
        held.signal(sig);
        let done = held.wait();
        assert_eq!(done.status.code(), Some(code), "{}", text(&done.stderr));
        assert!(!text(&done.stderr).contains("panicked"));
        // The folder the run made is gone with its scratch and its lock.
        assert!(!out.exists(), "{sig}: {:?}", listing(&out));
    }
}

#[test]
fn a_killed_runs_scratch_is_removed_by_the_next_run() {
    let dir = drive("killed");
    let out = dir.join("out");
    let held = Held::start(&dir, &out, &[]);
    held.signal("-KILL");
    let done = held.wait();
    assert_eq!(done.status.code(), None);
    let left = scratch_in(&out);
    assert_eq!(left.len(), 1, "{:?}", listing(&out));
    let next = run(&process_args(&dir, &dir.join("imu.txt"), &out, &[])
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>());
    assert!(next.status.success(), "{}", text(&next.stderr));
    assert!(scratch_in(&out).is_empty(), "{:?}", listing(&out));
    assert!(!out.join(".kestrel.lock").exists());
}

#[test]
fn a_new_run_replaces_exactly_the_earlier_runs_files() {
    let dir = drive("replace");
    let out = dir.join("out");
    let args = |extra: &[&str]| process_args(&dir, &dir.join("imu.txt"), &out, extra);
    let truth = s(&dir.join("truth.nav"));
    let a = args(&["--smooth", "--truth", &truth]);
    let first = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(first.status.success(), "{}", text(&first.stderr));
    let smoothed = listing(&out);
    for f in ["smoothed.nav", "errors.csv", "drift.csv"] {
        assert!(smoothed.contains(&f.to_string()), "{smoothed:?}");
    }
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let b = args(&[]);
    let second = run(&b.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(second.status.success(), "{}", text(&second.stderr));
    let now = listing(&out);
    for f in ["smoothed.nav", "errors.csv", "drift.csv"] {
        assert!(!now.contains(&f.to_string()), "{f} stayed: {now:?}");
    }
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
    assert!(now.contains(&"result.nav".to_string()));
    // A file of the user's under one of the run's names is refused without
    // --force, and the folder stays as it was.
    fs::remove_file(out.join("kestrel-manifest.json")).unwrap();
    let before = contents(&out);
    let third = run(&b.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(third.status.code(), Some(1));
    assert!(
        text(&third.stderr).contains("refusing to replace"),
        "{}",
        text(&third.stderr)
    );
    assert_eq!(contents(&out), before);
}

#[test]
fn a_failed_run_leaves_the_folder_as_it_was() {
    let dir = drive("failed");
    let out = dir.join("out");
    let a = process_args(&dir, &dir.join("imu.txt"), &out, &[]);
    let first = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(first.status.success(), "{}", text(&first.stderr));
    let before = contents(&out);
    // The same drive with a damaged line three quarters in.
    let imu = fs::read_to_string(dir.join("imu.txt")).unwrap();
    let lines: Vec<&str> = imu.lines().collect();
    let k = lines.len() * 3 / 4;
    let mut bad = lines.clone();
    bad[k] = "1.0 2.0 x";
    fs::write(dir.join("bad-imu.txt"), bad.join("\n") + "\n").unwrap();
    let a = process_args(&dir, &dir.join("bad-imu.txt"), &out, &[]);
    let second = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(second.status.code(), Some(1));
    assert!(
        text(&second.stderr).contains(&format!("bad-imu.txt:{}", k + 1)),
        "{}",
        text(&second.stderr)
    );
    assert_eq!(contents(&out), before);
}

#[test]
fn inputs_named_like_kestrels_own_files_are_never_touched() {
    let dir = drive("names");
    let out = dir.join("out");
    fs::create_dir_all(&out).unwrap();
    let truth = fs::read(dir.join("truth.nav")).unwrap();
    let imu = fs::read(dir.join("imu.txt")).unwrap();
    // The scratch names of earlier versions and of this one, and the
    // lock's name, holding the user's inputs.
    for name in [
        ".errors.csv.partial",
        ".kestrel-scratch-1-1",
        ".kestrel.lock",
    ] {
        fs::write(out.join(name), &truth).unwrap();
        let t = s(&out.join(name));
        let a = process_args(&dir, &dir.join("imu.txt"), &out, &["--truth", &t]);
        let r = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(
            fs::read(out.join(name)).unwrap(),
            truth,
            "{name}: {}",
            text(&r.stderr)
        );
        if !r.status.success() {
            assert!(text(&r.stderr).contains(name), "{}", text(&r.stderr));
        }
        fs::remove_file(out.join(name)).unwrap();
    }
    fs::write(out.join(".result.nav.partial"), &imu).unwrap();
    let a = process_args(&dir, &out.join(".result.nav.partial"), &out, &[]);
    let _ = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(fs::read(out.join(".result.nav.partial")).unwrap(), imu);
    // The input under an output's name, spelt through `..`.
    fs::write(out.join("result.nav"), &truth).unwrap();
    let spelt = s(&dir.join("out/../out/result.nav"));
    let a = process_args(
        &dir,
        &dir.join("imu.txt"),
        &out,
        &["--truth", &spelt, "--force"],
    );
    let r = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(r.status.code(), Some(1));
    assert!(
        text(&r.stderr).contains("it is the --truth input"),
        "{}",
        text(&r.stderr)
    );
    assert_eq!(fs::read(out.join("result.nav")).unwrap(), truth);
}

/// The KF-GINS example's shape (see process_cli), with `extra` keys.
fn kf_gins_yaml(imupath: &str, outputpath: &str) -> String {
    format!(
        "imupath: {imupath}\ngnsspath: \"gnss.txt\"\noutputpath: {outputpath}\n\
         imudatalen: 7\nimudatarate: 200\nstarttime: 456300\nendtime: -1\n\
         initpos: [ 30.4447873701, 114.4718632047, 20.899 ]\ninitvel: [ 0.0, 0.0, 0.0 ]\n\
         initatt: [ 0.85421502, -2.03480295, 185.70235133 ]\n\
         initgyrbias: [ 0, 0, 0 ]\ninitaccbias: [ 0, 0, 0 ]\n\
         initgyrscale: [ 0, 0, 0 ]\ninitaccscale: [ 0, 0, 0 ]\n\
         initposstd: [ 0.005, 0.004, 0.008 ]\ninitvelstd: [ 0.003, 0.004, 0.004 ]\n\
         initattstd: [ 0.003, 0.003, 0.023 ]\n\
         imunoise:\n  arw: [0.003, 0.003, 0.003]\n  vrw: [0.03, 0.03, 0.03]\n  \
         gbstd: [0.027, 0.027, 0.027]\n  abstd: [15.0, 15.0, 15.0]\n  \
         gsstd: [0.0, 0.0, 0.0]\n  asstd: [0.0, 0.0, 0.0]\n  corrtime: 4.0\n\
         antlever:  [ 0.136, -0.301, -0.184 ]\n"
    )
}

#[test]
fn import_writes_whole_files_and_never_its_input() {
    let dir = tmp_dir("integrity", "import");
    let yaml = dir.join("kf.yaml");
    let good = kf_gins_yaml("\"imu.txt\"", "\"out\"");
    fs::write(&yaml, &good).unwrap();
    // Its own input, by another spelling, even with --force.
    let spelt = s(&dir
        .join("../")
        .join(dir.file_name().unwrap())
        .join("kf.yaml"));
    let r = run(&["import", "kf-gins", &s(&yaml), "--out", &spelt, "--force"]);
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert_eq!(fs::read_to_string(&yaml).unwrap(), good);
    // A link is replaced, never written through.
    let target = dir.join("target.txt");
    fs::write(&target, "keep").unwrap();
    std::os::unix::fs::symlink(&target, dir.join("link.toml")).unwrap();
    let r = run(&[
        "import",
        "kf-gins",
        &s(&yaml),
        "--out",
        &s(&dir.join("link.toml")),
        "--force",
    ]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    assert_eq!(fs::read_to_string(&target).unwrap(), "keep");
    let written = fs::read_to_string(dir.join("link.toml")).unwrap();
    assert!(written.contains("[imu]"));
    assert!(
        listing(&dir).iter().all(|n| !n.starts_with('.')),
        "{:?}",
        listing(&dir)
    );
    // A path with a line break would write a live TOML table.
    fs::write(
        &yaml,
        kf_gins_yaml("\"imu.txt\"", "\"out\\n[output]\\ninterval = 1e308\""),
    )
    .unwrap();
    let r = run(&[
        "import",
        "kf-gins",
        &s(&yaml),
        "--out",
        &s(&dir.join("nl.toml")),
    ]);
    assert_eq!(r.status.code(), Some(1));
    assert!(
        text(&r.stderr).contains("outputpath"),
        "{}",
        text(&r.stderr)
    );
    assert!(!dir.join("nl.toml").exists());
    // A name with shell syntax is printed quoted.
    fs::write(&yaml, kf_gins_yaml("\"my imu; rm -rf ~.txt\"", "\"out\"")).unwrap();
    let r = run(&["import", "kf-gins", &s(&yaml)]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    let all = text(&r.stdout) + &text(&r.stderr);
    assert!(all.contains("--imu 'my imu; rm -rf ~.txt'"), "{all}");
    // A YAML alias bomb is refused before it expands.
    let mut bomb =
        String::from("a: &a [\"x\", \"x\", \"x\", \"x\", \"x\", \"x\", \"x\", \"x\", \"x\"]\n");
    for i in 0..9u8 {
        let (p, n) = ((b'a' + i) as char, (b'b' + i) as char);
        bomb += &format!("{n}: &{n} [*{p}, *{p}, *{p}, *{p}, *{p}, *{p}, *{p}, *{p}, *{p}]\n");
    }
    fs::write(dir.join("bomb.yaml"), bomb).unwrap();
    let r = run(&["import", "kf-gins", &s(&dir.join("bomb.yaml"))]);
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert!(text(&r.stderr).contains("alias"), "{}", text(&r.stderr));
}

#[test]
fn pipes_and_fifos_are_read_once() {
    let dir = drive("fifos");
    // Alignment reads the GNSS file ahead; the pass goes on from there.
    let config = fs::read_to_string(dir.join("process.toml")).unwrap();
    let mut aligned = String::new();
    for line in config.lines() {
        let initial = !aligned.contains("[initial.std]");
        let dropped = ["position = ", "velocity = ", "attitude = "];
        if initial && dropped.iter().any(|d| line.starts_with(d)) {
            continue;
        }
        aligned += line;
        aligned += "\n";
    }
    aligned += "\n[alignment]\nstatic_time = 1.0\nyaw = \"gnss-course\"\nmin_speed = 3.0\n";
    fs::write(dir.join("aligned.toml"), aligned).unwrap();
    let go = |gnss: &Path, out: &str, extra: &[&str]| {
        let mut c = kestrel();
        c.args([
            "process",
            "--imu",
            &s(&dir.join("imu.txt")),
            "--gnss",
            &s(gnss),
            "--config",
            &s(&dir.join("aligned.toml")),
            "--out",
            &s(&dir.join(out)),
            "--no-plots",
        ])
        .args(extra);
        c
    };
    let file = go(&dir.join("gnss.txt"), "file", &[]).output().unwrap();
    assert!(file.status.success(), "{}", text(&file.stderr));
    let fifo = dir.join("gnss.fifo");
    mkfifo(&fifo);
    let child = go(&fifo, "fifo", &[])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let gnss = fs::read(dir.join("gnss.txt")).unwrap();
    let w = std::thread::spawn({
        let fifo = fifo.clone();
        move || {
            let mut f = OpenOptions::new().write(true).open(&fifo).unwrap();
            let _ = f.write_all(&gnss);
        }
    });
    let piped = ended(child);
    w.join().unwrap();
    assert!(piped.status.success(), "{}", text(&piped.stderr));
    assert_eq!(
        fs::read(dir.join("fifo/result.nav")).unwrap(),
        fs::read(dir.join("file/result.nav")).unwrap()
    );
    // The truth from a FIFO with --smooth: read once, kept for the smoother.
    let truth = dir.join("truth.fifo");
    mkfifo(&truth);
    let child = kestrel()
        .args(process_args(
            &dir,
            &dir.join("imu.txt"),
            &dir.join("smoothed"),
            &["--smooth", "--truth", &s(&truth)],
        ))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let nav = fs::read(dir.join("truth.nav")).unwrap();
    let w = std::thread::spawn(move || {
        let mut f = OpenOptions::new().write(true).open(&truth).unwrap();
        let _ = f.write_all(&nav);
    });
    let smoothed = ended(child);
    w.join().unwrap();
    assert!(smoothed.status.success(), "{}", text(&smoothed.stderr));
    let listed = listing(&dir.join("smoothed"));
    for f in ["errors.csv", "errors_smoothed.csv", "smoothed.nav"] {
        assert!(listed.contains(&f.to_string()), "{f}: {listed:?}");
    }
    // /dev/zero and /dev/urandom as inputs end in an error, bounded.
    for (flag, dev) in [
        ("--imu", "/dev/zero"),
        ("--imu", "/dev/urandom"),
        ("--config", "/dev/zero"),
    ] {
        let mut a = vec![
            "process".to_string(),
            "--imu".into(),
            s(&dir.join("imu.txt")),
            "--gnss".into(),
            s(&dir.join("gnss.txt")),
            "--config".into(),
            s(&dir.join("process.toml")),
            "--out".into(),
            s(&dir.join("dev")),
        ];
        let i = a.iter().position(|x| x == flag).unwrap();
        a[i + 1] = dev.into();
        let t = Instant::now();
        let r = kestrel().args(&a).output().unwrap();
        assert_eq!(
            r.status.code(),
            Some(1),
            "{flag} {dev}: {}",
            text(&r.stderr)
        );
        assert!(
            t.elapsed() < Duration::from_secs(30),
            "{flag} {dev}: {:?}",
            t.elapsed()
        );
        assert!(text(&r.stderr).contains(dev), "{}", text(&r.stderr));
    }
}

#[test]
fn full_and_closed_output_streams_never_panic() {
    if !Path::new("/dev/full").exists() {
        eprintln!("skipped: no /dev/full on this machine");
        return;
    }
    let full = File::create("/dev/full").unwrap();
    let r = kestrel().arg("--help").stdout(full).output().unwrap();
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert!(!text(&r.stderr).contains("panicked"), "{}", text(&r.stderr));
    // `kestrel … | head -c 1`: the pipe closes early; the run ends quietly.
    let mut child = kestrel()
        .args([
            "reproduce",
            "000",
            "--duration",
            "20",
            "--out",
            &s(&tmp_dir("integrity", "head")),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let r = child.wait_with_output().unwrap();
    assert!(
        matches!(r.status.code(), Some(0) | Some(141)),
        "{:?} {}",
        r.status,
        text(&r.stderr)
    );
    assert!(!text(&r.stderr).contains("panicked"), "{}", text(&r.stderr));
}

/// Mounts a 1 MiB tmpfs at `dir` (as root), or says why not.
fn small_tmpfs(dir: &Path) -> Result<(), String> {
    fs::create_dir_all(dir).unwrap();
    let out = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=1m", "tmpfs", &s(dir)])
        .output()
        .map_err(|e| e.to_string())?;
    if out.status.success() {
        Ok(())
    } else {
        Err(text(&out.stderr))
    }
}

#[test]
fn a_full_disk_publishes_nothing() {
    let dir = drive("full");
    let disk = dir.join("disk");
    if let Err(why) = small_tmpfs(&disk) {
        eprintln!(
            "skipped: cannot mount a 1 MiB tmpfs (needs root): {}",
            why.trim()
        );
        return;
    }
    struct Unmount(PathBuf);
    impl Drop for Unmount {
        fn drop(&mut self) {
            let _ = Command::new("umount").arg(&self.0).status();
        }
    }
    let _u = Unmount(disk.clone());
    // process: the result of a 120 s drive at the IMU rate is larger than
    // 1 MiB.
    let out = disk.join("out");
    let a = process_args(
        &dir,
        &dir.join("imu.txt"),
        &out,
        &["--truth", &s(&dir.join("truth.nav"))],
    );
    let r = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert!(
        text(&r.stderr).contains("no space left"),
        "{}",
        text(&r.stderr)
    );
    assert!(
        listing(&disk).is_empty(),
        "{:?} {:?}",
        listing(&disk),
        listing(&out)
    );
    // simulate: the IMU file alone is larger than 1 MiB.
    let sim = disk.join("sim");
    let r = run(&["simulate", "002", "--duration", "120", "--out", &s(&sim)]);
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert!(
        text(&r.stderr).contains("no space left"),
        "{}",
        text(&r.stderr)
    );
    assert!(listing(&disk).is_empty(), "{:?}", listing(&sim));
}
