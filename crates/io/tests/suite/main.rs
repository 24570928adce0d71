//! The I/O crate's integration tests.

mod gins;
