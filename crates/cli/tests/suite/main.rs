//! The command-line tool's integration tests, one binary: one link, and the shared
//! filter code instantiated once instead of once per file.

#[macro_use]
mod support;

mod alignment;
mod constraints;
mod plots;
mod process_cli;
mod real_logs;
mod reproduce;
mod scale_factors;
mod scenario_file;
mod smooth;
