//! The application crate's integration tests as one binary: the code the
//! files share is compiled and linked once, not once per file.

mod anees;
mod claims_held_out;
mod config;
mod experiment;
mod health;
mod mechanisation_accuracy;
mod odometer_faults;
mod odometer_run;
mod process;
mod reproduce_001_002;
mod scenario_file;
mod shared_simulation;
mod sim_scenarios;
mod sins_dr;
mod together;
