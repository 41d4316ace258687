//! The A02 measurement's pieces (`mechanism_bench::a02`): every size has a system, the exact
//! branch lies flat 20 times in 20 s for each, and the compiled N = 10 chain follows it
//! through all 20 singular positions. (N = 80 is left to the release program: its static
//! matrices are large for a test thread's stack in an unoptimised build.)

use mechanism_bench::a02::{self, SIZES, exact_crossings};

#[test]
fn every_size_has_a_system_and_twenty_flat_positions() {
    for n in SIZES {
        let sys = a02::system(n).unwrap_or_else(|| panic!("N = {n}: no system"));
        assert_eq!(
            (sys.info().n(), sys.info().m()),
            (2 * (n + 1), 2 * n + 1),
            "N = {n}"
        );
        assert_eq!(exact_crossings(n).len(), 20, "N = {n}");
    }
    assert!(a02::system(3).is_none());
}

#[test]
fn compiled_n_10_follows_the_exact_branch_through_every_passage() {
    let n = 10;
    let sys = a02::system(n).unwrap();
    let crossings = exact_crossings(n);
    let acc = a02::run(n, sys.as_ref(), 1e-8, &crossings).expect("N = 10 runs");
    assert!(acc.tips_error < 1e-4, "{acc:?}");
    assert!(acc.max_phi < 1e-12, "{acc:?}");
    assert_eq!(acc.passages, 20, "{acc:?}");
    assert_eq!(acc.rank_drop, (n, n), "{acc:?}");
    assert!(acc.passage_time_error.unwrap() < 1e-3, "{acc:?}");
}
