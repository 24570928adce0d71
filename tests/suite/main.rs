//! The umbrella crate's integration tests as one binary: the code the files
//! share is compiled and linked once, not once per file.

#[macro_use]
mod support;
mod common;

// The allocation tests count the heap calls of their own thread only, so
// one counting allocator serves every module.
#[global_allocator]
static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;

mod adapters;
mod compositions;
mod consistency;
mod contract_proptest;
mod errors;
mod fade_states;
mod forms_proptest;
mod hand_computed;
mod hostile_f32;
mod jacobians;
mod no_alloc;
mod quiet_epochs;
mod report_detail;
mod sequential;
mod smoother;
mod state_space;
mod unadapted;
