//! The fuzz targets of `kestrel_app::fuzz` under `cargo test`: every seed
//! of `fuzz/corpus/<target>/` replayed (the seeds are the test fixtures,
//! and every failure a fuzzer found, kept as a fixed case), then a
//! mutation pass from a fixed seed, so the run is the same every time.
//!
//! Each call must return — an error is a fine answer — within
//! [`MAX_SECONDS`] and with at most [`MAX_PEAK_BYTES`] allocated at its
//! peak (the readers bound a line to 4 KiB and a configuration to 1 MiB;
//! nothing may grow with what the input claims). A failing input is
//! written to `target/fuzz-failures/` to be added to the corpus.
//!
//! Wider exploration runs outside CI with cargo-fuzz or AFL++
//! (`fuzz/README.md`); what it finds becomes a seed here.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use kestrel_app::fuzz::TARGETS;
use kestrel_testkit::{heap_peak, heap_peak_within, CountingAllocator};

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// The most one call may allocate at its peak.
const MAX_PEAK_BYTES: usize = 64 << 20;

/// The longest one call may take (each takes milliseconds; this only
/// catches a hang, with room for a loaded CI machine).
const MAX_SECONDS: u64 = 5;

/// Mutated inputs per target.
const MUTATIONS: usize = 100_000;

/// The repository's corpus folder of `target`.
fn corpus_dir(target: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus")
        .join(target)
}

/// The seeds of `target`, in name order.
fn seeds(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = corpus_dir(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect()
}

/// Runs `target` on `data`, checking time and memory; on a failure the
/// input is saved and the message names it.
fn check(name: &str, target: fn(&[u8]), what: &str, data: &[u8]) {
    let started = Instant::now();
    // Past the limit an allocation fails and the process stops with
    // "memory allocation of … bytes failed": a runaway input ends the
    // test, not the machine.
    let outcome = std::panic::catch_unwind(|| heap_peak_within(MAX_PEAK_BYTES, || target(data)).1);
    let took = started.elapsed();
    let failure = match outcome {
        Err(_) => Some("panicked".to_owned()),
        Ok(peak) if peak > MAX_PEAK_BYTES => Some(format!("allocated {peak} bytes at its peak")),
        Ok(_) if took > Duration::from_secs(MAX_SECONDS) => Some(format!("took {took:?}")),
        Ok(_) => None,
    };
    if let Some(why) = failure {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/fuzz-failures");
        let _ = std::fs::create_dir_all(&dir);
        let file = dir.join(format!("{name}-{}", what.replace(['/', ' '], "_")));
        let _ = std::fs::write(&file, data);
        panic!("{name} on {what} {why}; the input is in {}", file.display());
    }
}

/// xorshift64*: a small generator whose sequence is fixed by its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Values readers must survive where a number stands.
const TOKENS: [&str; 18] = [
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-300",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "4294967295",
    "18446744073709551616",
    "-1",
    "9e15",
    "0x10",
    "\"x\"",
    "[]",
    "{}",
];

/// One mutation of `data`: a bit flip, a byte set, a range removed or
/// repeated, a number replaced by a hostile value, a line of another seed
/// spliced in, or a line break inserted.
fn mutate(rng: &mut Rng, data: &mut Vec<u8>, others: &[(String, Vec<u8>)]) {
    let len = data.len();
    match rng.below(7) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = b"\n\r\t #[]=,.-e0\"\x00\xff"[rng.below(16)];
        }
        2 if len > 0 => {
            let at = rng.below(len);
            let n = rng.below((len - at).min(64)) + 1;
            data.drain(at..at + n);
        }
        3 if len > 0 => {
            let at = rng.below(len);
            let n = (rng.below(len - at) + 1).min(256);
            let piece: Vec<u8> = data[at..at + n].to_vec();
            let times = rng.below(8) + 1;
            for _ in 0..times {
                data.splice(at..at, piece.iter().copied());
            }
        }
        4 => {
            // A number (a run of digits, `.`, `e`, `-`) replaced.
            let starts: Vec<usize> = (0..len)
                .filter(|&i| data[i].is_ascii_digit() && (i == 0 || !data[i - 1].is_ascii_digit()))
                .collect();
            if let Some(&at) = starts.get(rng.below(starts.len())) {
                let mut end = at;
                while end < len && (data[end].is_ascii_digit() || b".e-+".contains(&data[end])) {
                    end += 1;
                }
                let token = TOKENS[rng.below(TOKENS.len())].as_bytes();
                data.splice(at..end, token.iter().copied());
            }
        }
        5 if !others.is_empty() => {
            let other = &others[rng.below(others.len())].1;
            let lines: Vec<&[u8]> = other.split(|&b| b == b'\n').collect();
            let line = lines[rng.below(lines.len())];
            let at = rng.below(len + 1);
            let mut piece = line.to_vec();
            piece.push(b'\n');
            data.splice(at..at, piece);
        }
        _ => {
            let at = rng.below(len + 1);
            data.insert(at, b'\n');
        }
    }
}

/// Replays the seeds of `name`, then [`MUTATIONS`] mutated inputs from a
/// seed fixed by the target's name.
fn run(name: &str) {
    let target = TARGETS
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no fuzz target {name}"))
        .1;
    let seeds = seeds(name);
    assert!(!seeds.is_empty(), "{name}: an empty corpus");
    for (file, data) in &seeds {
        check(name, target, file, data);
    }
    let mut rng = Rng(name.bytes().fold(0x9e37_79b9_7f4a_7c15, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    }));
    for i in 0..MUTATIONS {
        let (file, base) = &seeds[rng.below(seeds.len())];
        let mut data = base.clone();
        for _ in 0..=rng.below(4) {
            mutate(&mut rng, &mut data, &seeds);
        }
        check(name, target, &format!("mutation {i} of {file}"), &data);
    }
}

#[test]
fn allocation_counting_is_on() {
    kestrel_testkit::positive_control();
    let ((), peak) = heap_peak(|| drop(std::hint::black_box(vec![0u8; 1 << 20])));
    assert_eq!(peak, 1 << 20);
}

#[test]
fn every_target_has_a_corpus_and_a_test() {
    let tested = [
        "imu",
        "gnss",
        "rtklib",
        "nav",
        "odometer",
        "process-config",
        "scenario",
        "kf-gins",
    ];
    let names: Vec<&str> = TARGETS.iter().map(|(n, _)| *n).collect();
    assert_eq!(names, tested);
    for n in names {
        assert!(corpus_dir(n).is_dir(), "{n}");
    }
}

#[test]
fn imu() {
    run("imu");
}

#[test]
fn gnss() {
    run("gnss");
}

#[test]
fn rtklib() {
    run("rtklib");
}

#[test]
fn nav() {
    run("nav");
}

#[test]
fn odometer() {
    run("odometer");
}

#[test]
fn process_config() {
    run("process-config");
}

#[test]
fn scenario() {
    run("scenario");
}

#[test]
fn kf_gins() {
    run("kf-gins");
}
