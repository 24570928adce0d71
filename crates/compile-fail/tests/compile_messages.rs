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

/// The test's name, as libtest would list it.
const NAME: &str = "mistakes_give_messages_that_name_the_cause";

/// libtest's options that take a value, given as the next argument or
/// after `=`.
const VALUED: [&str; 6] = [
    "--test-threads",
    "--skip",
    "--format",
    "--color",
    "--logfile",
    "-Z",
];

/// Whether the command line selects this test, as libtest decides for a
/// test that is not ignored: a filter runs the tests whose name contains it
/// (equals it, with `--exact`), `--skip` leaves out those that contain its
/// value, and `--ignored` runs only ignored tests. `cargo test --workspace
/// some_filter` then spends no time here.
fn selected(args: &[String]) -> bool {
    let exact = args.iter().any(|a| a == "--exact");
    let matches = |f: &str| if exact { NAME == f } else { NAME.contains(f) };
    let mut filters = Vec::new();
    let mut rest = args.iter().map(String::as_str);
    while let Some(arg) = rest.next() {
        let (option, inline) = match arg.split_once('=') {
            Some((option, value)) if option.starts_with('-') => (option, Some(value)),
            _ => (arg, None),
        };
        if option == "--ignored" {
            return false;
        }
        if VALUED.contains(&option) {
            let value = inline.or_else(|| rest.next());
            if option == "--skip" && value.is_some_and(matches) {
                return false;
            }
        } else if !option.starts_with('-') {
            filters.push(arg);
        }
    }
    filters.is_empty() || filters.into_iter().any(matches)
}

fn main() {
    let args: Vec<String> = env::args().skip(1).collect();
    if !selected(&args) {
        return;
    }
    if args.iter().any(|a| a == "--list") {
        println!("{NAME}: test");
        return;
    }
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
