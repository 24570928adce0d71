//! The compile errors of common mistakes with kestrel, pinned: the cases and
//! their expected messages are in `tests/compile_fail/`, run by
//! `tests/compile_messages.rs`. The package has no code of its own; it exists
//! so that trybuild checks the cases against `kestrel` alone.
