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
    /// Bytes allocated minus bytes freed while armed.
    static LIVE: Cell<isize> = const { Cell::new(0) };
    /// The most `LIVE` has been while armed.
    static PEAK: Cell<isize> = const { Cell::new(0) };
    /// The most `LIVE` may become while armed: a larger request fails
    /// (the process stops with "memory allocation … failed") instead of
    /// taking the machine's memory.
    static LIMIT: Cell<isize> = const { Cell::new(isize::MAX) };
}

/// Whether a request for `bytes` more fits under the armed thread's limit.
fn fits(bytes: isize) -> bool {
    ARMED
        .try_with(|armed| {
            !armed.get() || LIVE.with(|l| l.get()).saturating_add(bytes) <= LIMIT.with(|m| m.get())
        })
        .unwrap_or(true)
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

/// One heap call of the current thread changing its live bytes by `bytes`.
fn note(bytes: isize) {
    // `try_with`: the allocator may run while thread-locals are torn down.
    let _ = ARMED.try_with(|armed| {
        if armed.get() {
            CALLS.with(|c| c.set(c.get() + 1));
            let live = LIVE.with(|l| {
                l.set(l.get() + bytes);
                l.get()
            });
            PEAK.with(|p| p.set(p.get().max(live)));
        }
    });
}

/// A size as a signed change of the live bytes.
fn signed(size: usize) -> isize {
    isize::try_from(size).unwrap_or(isize::MAX)
}

// SAFETY: every call is forwarded unchanged to `System`.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !fits(signed(layout.size())) {
            return std::ptr::null_mut();
        }
        note(signed(layout.size()));
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !fits(signed(layout.size())) {
            return std::ptr::null_mut();
        }
        note(signed(layout.size()));
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if !fits(signed(new_size) - signed(layout.size())) {
            return std::ptr::null_mut();
        }
        note(signed(new_size) - signed(layout.size()));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        note(-signed(layout.size()));
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

/// Runs `f` armed and returns its result with the most bytes the current
/// thread had allocated and not yet freed at any moment meanwhile (0
/// unless [`CountingAllocator`] is the global allocator): the memory a
/// call needs at its peak.
///
/// ```
/// #[global_allocator]
/// static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;
///
/// fn main() {
///     let ((), peak) = kestrel_testkit::heap_peak(|| {
///         let a = vec![0u8; 1000];
///         drop(a);
///         let _b = vec![0u8; 600];
///     });
///     assert_eq!(peak, 1000);
/// }
/// ```
pub fn heap_peak<R>(f: impl FnOnce() -> R) -> (R, usize) {
    heap_peak_within(usize::MAX, f)
}

/// [`heap_peak`] with the thread's live bytes capped at `limit`: a request
/// beyond it fails, which stops the process ("memory allocation of … bytes
/// failed") rather than letting a runaway call take the machine's memory.
///
/// ```
/// #[global_allocator]
/// static ALLOCATOR: kestrel_testkit::CountingAllocator = kestrel_testkit::CountingAllocator;
///
/// fn main() {
///     let (v, peak) = kestrel_testkit::heap_peak_within(4096, || vec![1u8; 4000]);
///     assert_eq!((v.len(), peak), (4000, 4000));
/// }
/// ```
pub fn heap_peak_within<R>(limit: usize, f: impl FnOnce() -> R) -> (R, usize) {
    LIVE.with(|l| l.set(0));
    PEAK.with(|p| p.set(0));
    LIMIT.with(|m| m.set(isize::try_from(limit).unwrap_or(isize::MAX)));
    let (out, _) = heap_calls(f);
    LIMIT.with(|m| m.set(isize::MAX));
    (out, PEAK.with(|p| usize::try_from(p.get()).unwrap_or(0)))
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
