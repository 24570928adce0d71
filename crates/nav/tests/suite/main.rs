//! The navigation crate's integration tests as one binary: the code the files
//! share is compiled and linked once, not once per file.

mod aiding;
mod common_ins;

// The allocation tests count the heap calls of their own thread only, so
// one counting allocator serves every module.
#[global_allocator]
static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;

mod attitude;
mod claims_held_out;
mod coning_sculling;
mod earth;
mod engine;
mod engine_no_alloc;
mod error_model;
mod experiment;
mod ins_gnss;
mod measurement_jacobians;
mod mechanisation_accuracy;
mod odometer_faults;
mod reproduce_001_002;
mod schuler;
mod sim_multipath;
mod sim_scenarios;
mod sim_sensors;
mod sim_trajectory;
mod sins_dr;
mod stationary;
mod together;
