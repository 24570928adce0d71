//! Fuzz targets: every reader and parser of the files kestrel takes, as a
//! plain function of the bytes of one file. Each reads the whole input
//! the way the commands do and throws the result away; a target must
//! return (an error is a fine answer) for any input, never panic, hang or
//! allocate beyond the limits the readers state
//! ([`MAX_LINE_BYTES`](kestrel_io::gins::MAX_LINE_BYTES) per line,
//! [`MAX_CONFIG_BYTES`] per configuration).
//!
//! The same functions run under three drivers: `cargo test` (the
//! repository's `fuzz` test replays the seed corpora under `fuzz/corpus/`
//! and a fixed-seed mutation pass), cargo-fuzz (libFuzzer, the `fuzz/`
//! package) and AFL++ (through the `afl` crate's `fuzz!` macro around the
//! same call). `fuzz/README.md` says how to run each.
//!
//! ```
//! for (name, target) in kestrel_app::fuzz::TARGETS {
//!     target(b"");
//!     target(b"1 2 3\n\xff\n[x]\n");
//!     assert!(!name.is_empty());
//! }
//! ```

use std::io::Cursor;
use std::path::Path;

use kestrel_io::gins::{GnssReader, ImuReader, NavReader, OdometerReader, RtklibReader};

use crate::config::read::MAX_CONFIG_BYTES;

/// A fuzz target: reads the bytes of one file.
pub type Target = fn(&[u8]);

/// Every target by name (the name of its corpus folder).
pub const TARGETS: [(&str, Target); 8] = [
    ("imu", imu),
    ("gnss", gnss),
    ("rtklib", rtklib),
    ("nav", nav),
    ("odometer", odometer),
    ("process-config", process_config),
    ("scenario", scenario),
    ("kf-gins", kf_gins),
];

/// Drains a reader: every record, stopping at the first error as the
/// commands do.
fn drain<T, E>(records: impl Iterator<Item = Result<T, E>>) {
    for r in records {
        if r.is_err() {
            break;
        }
    }
}

/// An IMU file in the GINS text format ([`ImuReader`]).
pub fn imu(data: &[u8]) {
    drain(ImuReader::new(Cursor::new(data), Path::new("fuzz.imu")));
}

/// A GNSS file in the GINS text format ([`GnssReader`]).
pub fn gnss(data: &[u8]) {
    drain(GnssReader::new(Cursor::new(data), Path::new("fuzz.gnss")));
}

/// An RTKLIB `.pos` file ([`RtklibReader`], week 2000, fixes of quality 1
/// and 2).
pub fn rtklib(data: &[u8]) {
    drain(RtklibReader::new(
        Cursor::new(data),
        Path::new("fuzz.pos"),
        2000,
        &[1, 2],
    ));
}

/// A navigation (truth or result) file ([`NavReader`]).
pub fn nav(data: &[u8]) {
    drain(NavReader::new(Cursor::new(data), Path::new("fuzz.nav")));
}

/// An odometer file ([`OdometerReader`]).
pub fn odometer(data: &[u8]) {
    drain(OdometerReader::new(
        Cursor::new(data),
        Path::new("fuzz.odo"),
    ));
}

/// The text of a configuration as [`read_config`](crate::config::read::read_config)
/// gives it: at most [`MAX_CONFIG_BYTES`], UTF-8.
fn config_text(data: &[u8]) -> Option<&str> {
    if data.len() as u64 > MAX_CONFIG_BYTES {
        return None;
    }
    std::str::from_utf8(data).ok()
}

/// A `process` configuration ([`config::process::parse`](crate::config::process::parse)).
pub fn process_config(data: &[u8]) {
    if let Some(text) = config_text(data) {
        let _ = crate::config::process::parse(text, Path::new("fuzz.toml"));
    }
}

/// A scenario file ([`config::scenario::parse`](crate::config::scenario::parse)),
/// trajectory included.
pub fn scenario(data: &[u8]) {
    if let Some(text) = config_text(data) {
        let _ = crate::config::scenario::parse(text, Path::new("fuzz.toml"));
    }
}

/// A KF-GINS YAML configuration ([`import::kf_gins`](crate::import::kf_gins)).
pub fn kf_gins(data: &[u8]) {
    if let Some(text) = config_text(data) {
        let _ = crate::import::kf_gins(text, Path::new("fuzz.yaml"), None);
    }
}
