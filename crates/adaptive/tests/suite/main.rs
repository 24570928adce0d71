//! The adapters' integration tests as one binary: the code the files share is
//! compiled and linked once, not once per file.

mod federated_common;
#[macro_use]
mod support;

// The allocation tests count the heap calls of their own thread only, so
// one counting allocator serves every module.
#[global_allocator]
static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;

mod federated_equivalence;
mod federated_fusion;
mod federated_isolation;
mod federated_no_alloc;
mod federated_sharing;
mod gated_huber;
mod monitor;
mod paper000_compression;
mod paper000_fading;
mod paper000_forms;
mod paper000_hand;
mod paper000_no_alloc;
mod paper000_sage_husa;
mod paper000_scenario;
mod paper002;
mod paper002_003_forms;
mod paper002_003_no_alloc;
mod paper003_fuzzy;
mod paper003_windowed;
mod paper003_windowed_f32_update;
mod paper004_strong_tracking;
