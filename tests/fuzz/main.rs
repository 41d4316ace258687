//! Fuzzing with generated inputs: declarations (valid and broken) through the whole
//! interpreter route (parse, checks, derivation, compilation, a short simulation), and
//! command lines through the binary. The properties: no panic, no abort, a typed error or a
//! result, finite numbers in every result, and bounded time.
//!
//! A quick subset runs with `cargo test` (a few hundred cases); the full campaign is
//! ignored: `cargo test --release --test fuzz -- --ignored --nocapture` (10^5 declarations,
//! 10^4 command lines), or set `MECHANISM_FUZZ_CASES`. RELIABILITY.md records its results.

mod cli;
mod declarations;

/// Cases for a run: `MECHANISM_FUZZ_CASES`, or `quick` (the CI subset).
pub fn cases(quick: u32) -> u32 {
    std::env::var("MECHANISM_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(quick)
}
