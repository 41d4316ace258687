//! The emitted functions allocate nothing: a counting global allocator (this test binary
//! only) sees no allocation while every generated function runs.

use std::hint::black_box;

use mechanism_emit_check::generated::{MATRICES, P, SCALARS};
use nalgebra::{SMatrix, SVector};

#[global_allocator]
static ALLOCATOR: mechanism_test_support::Counting = mechanism_test_support::Counting;

#[test]
fn emitted_functions_do_not_allocate() {
    let p = P { k: 0.7 };
    let q = SVector::<f64, 2>::new(0.3, -1.1);
    let mut all = [SMatrix::<f64, 2, 3>::zeros(); MATRICES.len()];
    let mut sink = 0.0;
    let before = mechanism_test_support::allocations();
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
    let after = mechanism_test_support::allocations();
    assert_eq!(after - before, 0, "emitted code allocated");
    black_box(sink);
}
