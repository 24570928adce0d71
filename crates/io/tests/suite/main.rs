//! The I/O crate's integration tests as one binary: the code the files share is
//! compiled and linked once, not once per file.

mod config;
mod gins;
mod process;
