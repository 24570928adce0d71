//! # kestrel-testkit
//!
//! Test support shared by the workspace's allocation tests: a global
//! allocator that counts the heap calls the current thread makes while
//! armed, the armed run, and the positive control every such test binary
//! runs to show that the allocator is installed and counting.
//!
//! The flag and the counter are thread-local, so the test harness's own
//! threads (output capture, other tests) cannot disturb a count.
//!
//! ```
//! use kestrel_testkit::{heap_calls, CountingAllocator};
//!
//! #[global_allocator]
//! static ALLOCATOR: CountingAllocator = CountingAllocator;
//!
//! fn main() {
//!     kestrel_testkit::positive_control();
//!     let (sum, calls) = heap_calls(|| [1.0f64, 2.0].iter().sum::<f64>());
//!     assert_eq!((sum, calls), (3.0, 0));
//! }
//! ```
#![deny(missing_docs)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;

thread_local! {
    static ARMED: Cell<bool> = const { Cell::new(false) };
    static CALLS: Cell<usize> = const { Cell::new(0) };
}

/// The system allocator, counting every allocation, zeroed allocation,
/// reallocation and deallocation of a thread armed by [`heap_calls`].
///
/// Install it in a test binary with `#[global_allocator]`:
///
/// ```
/// #[global_allocator]
/// static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;
///
/// fn main() {
///     let (v, calls) = kestrel_testkit::heap_calls(|| vec![0u8; 16]);
///     assert_eq!(calls, 1);
///     assert_eq!(v.len(), 16);
/// }
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct CountingAllocator;

fn note() {
    // `try_with`: the allocator may run while thread-locals are torn down.
    let _ = ARMED.try_with(|armed| {
        if armed.get() {
            CALLS.with(|c| c.set(c.get() + 1));
        }
    });
}

// SAFETY: every call is forwarded unchanged to `System`.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        note();
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Runs `f` armed and returns its result with the number of heap calls the
/// current thread made meanwhile (always 0 unless [`CountingAllocator`] is
/// the global allocator).
///
/// ```
/// #[global_allocator]
/// static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;
///
/// fn main() {
///     let v = vec![1u8, 2, 3];
///     // Made before arming, dropped after: nothing counted.
///     let (len, calls) = kestrel_testkit::heap_calls(|| v.len());
///     assert_eq!((len, calls), (3, 0));
/// }
/// ```
pub fn heap_calls<R>(f: impl FnOnce() -> R) -> (R, usize) {
    CALLS.with(|c| c.set(0));
    ARMED.with(|a| a.set(true));
    let out = f();
    ARMED.with(|a| a.set(false));
    (out, CALLS.with(Cell::get))
}

/// The positive control of an allocation test: panics unless a box made
/// and dropped while armed counts one allocation and one deallocation, a
/// vector with capacity counts one allocation, and plain arithmetic counts
/// none — so a zero count elsewhere in the binary means no heap calls, not
/// a missing allocator.
///
/// ```should_panic
/// // Without `#[global_allocator]`, nothing is counted.
/// kestrel_testkit::positive_control();
/// ```
pub fn positive_control() {
    let (_, calls) = heap_calls(|| drop(black_box(Box::new(black_box(7u64)))));
    assert_eq!(calls, 2, "one allocation and one deallocation");
    let (v, calls) = heap_calls(|| black_box(Vec::<u8>::with_capacity(64)));
    assert_eq!(calls, 1, "one allocation");
    drop(v);
    let (_, calls) = heap_calls(|| black_box(1 + 1));
    assert_eq!(calls, 0, "no allocation");
}
