//! The navigation crate's integration tests as one binary: the code the files
//! share is compiled and linked once, not once per file.

mod aiding;
mod common_ins;

// The allocation tests count the heap calls of their own thread only, so
// one counting allocator serves every module.
#[global_allocator]
static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;

mod attitude;
mod coning_sculling;
mod earth;
mod engine;
mod engine_no_alloc;
mod error_model;
mod ins_gnss;
mod measurement_jacobians;
mod schuler;
mod stationary;
