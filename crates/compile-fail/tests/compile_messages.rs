//! The compile errors of common mistakes, pinned: each names the cause in
//! the user's terms (the adapter's measurement size and `update_with`, the
//! valid state sizes of a model, both sizes of a `Stack`). A missing
//! Jacobian is not pinned: rustc lists every implementor of the trait in
//! that message, so the pin would break with each new model.
//! The expected messages are in `tests/compile_fail/*.stderr`; regenerate
//! them with `TRYBUILD=overwrite cargo test -p kestrel-compile-fail` after a
//! deliberate change, and read the diff.
//!
//! This test runs without the libtest harness (`harness = false`), in
//! `main`, so that it can set the environment before any thread exists.

use std::env;

/// The flags trybuild gives rustc when it checks the cases (version 1.0.122,
/// as locked; compare them with its `rustflags.rs` after an update: a flag
/// left out here is left out of the check, and a message that changes with
/// it fails the test).
const CASE_FLAGS: [&str; 6] = [
    "--cfg",
    "trybuild",
    "--verbose",
    "-A",
    "dead_code",
    "--diagnostic-width=140",
];

fn main() {
    // trybuild checks the dependencies first without `--diagnostic-width`
    // and then the cases with it. Cargo keeps the flags in each unit's
    // fingerprint, so the second pass checks the whole dependency graph
    // again (about 30 s on two cores). `CARGO_ENCODED_RUSTFLAGS` takes
    // precedence over the configuration trybuild passes, so with the cases'
    // flags there both passes agree and the graph is checked once. A caller
    // with flags of their own (a coverage run) is left to trybuild.
    if env::var_os("RUSTFLAGS").is_none() && env::var_os("CARGO_ENCODED_RUSTFLAGS").is_none() {
        // SAFETY: single-threaded: `main` of a test without the harness,
        // before trybuild starts anything.
        unsafe { env::set_var("CARGO_ENCODED_RUSTFLAGS", CASE_FLAGS.join("\u{1f}")) };
    }
    trybuild::TestCases::new().compile_fail("tests/compile_fail/*.rs");
}
