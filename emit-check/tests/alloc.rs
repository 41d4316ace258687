//! The emitted functions allocate nothing: a counting global allocator (this test binary
//! only) sees no allocation while every generated function runs.

use std::alloc::{GlobalAlloc, Layout, System};
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};

use mechanism_emit_check::generated::{MATRICES, P, SCALARS};
use nalgebra::{SMatrix, SVector};

struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn emitted_functions_do_not_allocate() {
    let p = P { k: 0.7 };
    let q = SVector::<f64, 2>::new(0.3, -1.1);
    let mut all = [SMatrix::<f64, 2, 3>::zeros(); MATRICES.len()];
    let mut sink = 0.0;
    let before = ALLOCS.load(Ordering::SeqCst);
    for step in 0..10 {
        let t = 0.1 * step as f64;
        for f in SCALARS {
            sink += black_box(f(black_box(&p), black_box(&q), black_box(t)));
        }
        for f in MATRICES {
            sink += black_box(f(&p, &q, t))[(0, 1)];
        }
        p.all(black_box(&q), t, black_box(&mut all));
    }
    let after = ALLOCS.load(Ordering::SeqCst);
    assert_eq!(after - before, 0, "emitted code allocated");
    black_box(sink);
}
