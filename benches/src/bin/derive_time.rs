//! `derive_time FILE.mech [runs]`: the wall time of everything `mechanism!` does at build
//! time for one declaration (`mechanism_bench::macro_pipeline`: parse, derive, the tangent,
//! the routines of `mechanism_codegen::compile`, emission, the equations text), the median
//! of `runs` (default 5) in this process.

use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: derive_time FILE.mech [runs]");
        std::process::exit(2);
    };
    let runs: usize = args.get(1).and_then(|r| r.parse().ok()).unwrap_or(5).max(1);
    let source = match std::fs::read_to_string(path) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("derive_time: {path}: {e}");
            std::process::exit(1);
        }
    };
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs {
        let start = Instant::now();
        if let Err(e) = mechanism_bench::macro_pipeline(&source) {
            eprintln!("derive_time: {path}: {e}");
            std::process::exit(1);
        }
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!("{path}: {:.3} s (median of {runs})", times[runs / 2]);
}
