//! The command-line tool's integration tests as one binary: the code the files
//! share is compiled and linked once, not once per file.

mod support;

mod alignment;
mod constraints;
mod integrity;
mod plots;
mod process_cli;
mod real_logs;
mod reproduce;
mod scale_factors;
mod smooth;
