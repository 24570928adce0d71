//! The compile errors of common mistakes, pinned: each names the cause in
//! the user's terms (the adapter's measurement size and `update_with`, the
//! valid state sizes of a model, both sizes of a `Stack`). A missing
//! Jacobian is not pinned: rustc lists every implementor of the trait in
//! that message, so the pin would break with each new model.
//! The expected messages are in `tests/compile_fail/*.stderr`; regenerate
//! them with `TRYBUILD=overwrite cargo test -p kestrel-compile-fail` after a
//! deliberate change, and read the diff.

#[test]
fn mistakes_give_messages_that_name_the_cause() {
    trybuild::TestCases::new().compile_fail("tests/compile_fail/*.rs");
}
