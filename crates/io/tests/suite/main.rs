//! The I/O crate's integration tests, one binary: one link, and the shared
//! filter code instantiated once instead of once per file.

mod config;
mod gins;
mod process;
