//! Derivation of the closed planar N-bar chain (codegen issue, benchmark issue item 2):
//! N = 4 .. 64.
//!
//! - `model/N`: build the model through the arena API, derive M, C q', g, Phi, Phi_q and
//!   gamma, and CSE them into one program;
//! - `from_source/N`: the same from the declaration text (parser included);
//! - `macro_path/N`: everything `mechanism!` does at build time (parse, derive, one CSE'd
//!   program and emitted body per trait method plus the combined `evaluate`, equations text),
//!   in release mode, i.e. with `[profile.*.build-override] opt-level = 3`.
//!
//! The op counts after CSE are printed once per N (stderr) for BENCHMARKS.md. Flat sampling,
//! 10 samples: every sample runs the same number of iterations, so a derivation that takes
//! most of a second (N = 64) runs 10 times, not the 55 of criterion's linear sampling.

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, SamplingMode, criterion_group, criterion_main};
use mechanism_bench::{derive_and_cse, macro_pipeline};
use mechanism_codegen::fixtures::{closed_chain_model, closed_chain_source};
use mechanism_codegen::parse_model_str;

fn derivation(c: &mut Criterion) {
    let mut group = c.benchmark_group("derive_closed_chain");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(2));
    for n in [4usize, 8, 16, 32, 64] {
        match derive_and_cse(closed_chain_model(n)) {
            Ok(ops) => {
                eprintln!("closed chain N = {n}: {ops} after CSE (M, C q', g, Phi, Phi_q, gamma)")
            }
            Err(e) => eprintln!("closed chain N = {n}: derivation failed: {e}"),
        }
        group.bench_with_input(BenchmarkId::new("model", n), &n, |b, &n| {
            b.iter(|| derive_and_cse(closed_chain_model(n)))
        });
        let source = closed_chain_source(n);
        group.bench_with_input(BenchmarkId::new("from_source", n), &source, |b, s| {
            b.iter(|| parse_model_str(s).and_then(derive_and_cse))
        });
        group.bench_with_input(BenchmarkId::new("macro_path", n), &source, |b, s| {
            b.iter(|| macro_pipeline(s))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = derivation
}
criterion_main!(benches);
