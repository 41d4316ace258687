//! The derivation's work grows as n^2 on the closed N-bar chain, the size of M: doubling N
//! at most quadruples the constructor calls and the graph's size.
//!
//! Every stage is built to cost what its output holds (M and Khang's C have n^2 entries,
//! dM/dq 2 n^2 nonzeros, C q' n rows of O(n) terms); a stage that walks (entry,
//! coordinate) pairs or differentiates each momentum by every rate adds an n^3 term, and
//! then the ratio exceeds 4 and keeps growing. The counts are the arena's own
//! (`Arena::effort`), exact and independent of the machine, so the bound is exact: for
//! work a n^2 + b n + c with b, c >= 0 the ratio w(2n) / w(n) is at most 4 (the chain's
//! ratios are 3.83 to 3.95 from N = 16 to 128, rising towards 4 as the lower-order terms
//! fade). Wall time is in BENCHMARKS.md, not here.

use mechanism_codegen::fixtures::closed_chain_model;
use mechanism_codegen::{Effort, derive};

/// The work and size the derivation of the N-bar chain adds to its parsed model.
fn derivation_effort(n: usize) -> Effort {
    let mut model = closed_chain_model(n);
    let parsed = model.arena.effort();
    derive(&mut model).expect("the chain derives");
    let derived = model.arena.effort();
    Effort {
        work: derived.work - parsed.work,
        size: derived.size - parsed.size,
    }
}

#[test]
fn doubling_the_chain_at_most_quadruples_the_derivation() {
    let efforts: Vec<(usize, Effort)> = [16, 32, 64]
        .into_iter()
        .map(|n| (n, derivation_effort(n)))
        .collect();
    for pair in efforts.windows(2) {
        let ((n, a), (_, b)) = (pair[0], pair[1]);
        let work = b.work as f64 / a.work as f64;
        let size = b.size as f64 / a.size as f64;
        assert!(
            work <= 4.0 && size <= 4.0,
            "N = {n} -> {}: work x{work:.3}, size x{size:.3} ({a:?} -> {b:?})",
            2 * n
        );
        // Not linear either: the chain's M is dense, so the work must grow faster than n
        // (a ratio near 2 would mean entries went missing).
        assert!(work > 3.5 && size > 3.5, "N = {n}: x{work:.3}, x{size:.3}");
    }
}
