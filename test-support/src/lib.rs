//! Helpers shared by the workspace's test binaries and benchmarks.
//!
//! [`Counting`] is a global allocator that counts allocations on the calling thread only,
//! so tests running in parallel threads cannot disturb a measurement. A test binary installs
//! it with
//!
//! ```ignore
//! #[global_allocator]
//! static ALLOCATOR: mechanism_test_support::Counting = mechanism_test_support::Counting;
//! ```
//!
//! and reads [`allocations`] before and after the code that must not allocate.
//!
//! [`a02`] is the exact branch of the IFToMM A02 chain; [`rounding`] the first-order
//! rounding-error bound that compares two evaluation orders of one expression.

pub mod a02;
pub mod rounding;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The counting allocator (forwards to the system allocator).
pub struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: every call forwards to `System` with the same arguments; counting touches only a
// thread-local cell.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // try_with: the thread-local may already be gone while a thread shuts down.
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Allocations (and reallocations) made so far on this thread while [`Counting`] is the
/// global allocator.
pub fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}
