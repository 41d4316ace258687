//! IFToMM benchmark A02, the N four-bar chain through its singular positions, for N = 10,
//! 20, 40 and 80: 20 s with DOP853 (projection, 10 samples/s) against the exact branch.
//!
//! ```text
//! cargo run --release -p mechanism-bench --bin a02 [-- [--repeats K] [--wait-idle] [N ...]]
//! ```
//!
//! For each N it runs every tolerance of `a02::TOLERANCES` once (the error of B0 against
//! the exact branch, passages, steps), picks the loosest that keeps B0 within 1e-3 m, times
//! K runs there (default 5) and prints the markdown tables of BENCHMARKS.md, with the load
//! average next to each timing. `--wait-idle` waits (up to 15 min) before each timing until
//! the 1-minute load average is below 1.2.

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use mechanism_bench::a02::{
    self, Accuracy, B0_TOLERANCE, OUTPUT_RATE, SIZES, T_END, TOLERANCES, exact_crossings,
};

struct Args {
    sizes: Vec<usize>,
    repeats: usize,
    wait_idle: bool,
}

fn args() -> Args {
    let mut out = Args {
        sizes: Vec::new(),
        repeats: 5,
        wait_idle: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--repeats" => {
                out.repeats = it
                    .next()
                    .and_then(|k| k.parse().ok())
                    .filter(|&k| k > 0)
                    .unwrap_or_else(|| fail("--repeats needs a positive integer"));
            }
            "--wait-idle" => out.wait_idle = true,
            n => match n.parse() {
                Ok(n) if SIZES.contains(&n) => out.sizes.push(n),
                _ => fail(&format!("unknown argument `{n}` (sizes: {SIZES:?})")),
            },
        }
    }
    if out.sizes.is_empty() {
        out.sizes = SIZES.to_vec();
    }
    out
}

fn fail(message: &str) -> ! {
    eprintln!("a02: {message}");
    std::process::exit(1)
}

fn load_1min() -> f64 {
    a02::load_average()
        .split_whitespace()
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.0)
}

/// Waits until the 1-minute load average is below 1.2 (at most 15 minutes).
fn wait_idle() {
    let start = Instant::now();
    while load_1min() >= 1.2 && start.elapsed() < Duration::from_secs(900) {
        eprintln!("  load {}: waiting", a02::load_average());
        std::thread::sleep(Duration::from_secs(15));
    }
}

/// The rank drops of the recorded passages: one number when all equal, else "low-high".
fn rank_drop(a: &Accuracy) -> String {
    if a.rank_drop.0 == a.rank_drop.1 {
        a.rank_drop.0.to_string()
    } else {
        format!("{}-{}", a.rank_drop.0, a.rank_drop.1)
    }
}

fn sci(x: f64) -> String {
    format!("{x:.1e}")
}

fn ms(s: f64) -> String {
    format!("{:.1}", s * 1e3)
}

struct Row {
    n: usize,
    coordinates: usize,
    rows: usize,
    tol: f64,
    times: Vec<f64>,
    acc: Accuracy,
    crossings: usize,
    load: (String, String),
}

fn main() {
    let args = args();
    let mut sweep = String::new();
    let mut rows = Vec::new();
    let started = Instant::now();
    println!(
        "A02, the N four-bar chain: {T_END} s, DOP853 (rtol = atol = R), projection, {OUTPUT_RATE} samples/s; load at start {}",
        a02::load_average()
    );
    for &n in &args.sizes {
        let system = a02::system(n).expect("a measured size");
        let (coordinates, m) = (system.info().n(), system.info().m());
        let crossings = exact_crossings(n);
        eprintln!(
            "N = {n}: {coordinates} coordinates, {m} rows; the exact branch lies flat {} times in {T_END} s",
            crossings.len()
        );
        let mut chosen = None;
        for &tol in &TOLERANCES {
            let line = match a02::run(n, system.as_ref(), tol, &crossings) {
                Ok(acc) => {
                    let ok = acc.b0_error <= B0_TOLERANCE;
                    let line = format!(
                        "| {n} | {tol:.0e} | {} | {} | {} | {} | {} | {} of {} | {} | {} | {} | {} |",
                        sci(acc.b0_error),
                        if ok { "yes" } else { "no" },
                        sci(acc.tips_error),
                        sci(acc.energy_drift),
                        sci(acc.energy_final),
                        acc.passages,
                        crossings.len(),
                        rank_drop(&acc),
                        acc.steps,
                        acc.rhs,
                        sci(acc.max_phi),
                    );
                    if ok && chosen.is_none() {
                        chosen = Some((tol, acc));
                    }
                    line
                }
                Err(e) => {
                    format!(
                        "| {n} | {tol:.0e} | failed: {e} | no | - | - | - | - | - | - | - | - |"
                    )
                }
            };
            eprintln!("  {line}");
            let _ = writeln!(sweep, "{line}");
        }
        let Some((tol, acc)) = chosen else {
            eprintln!("  N = {n}: no tolerance keeps B0 within {B0_TOLERANCE} m; not timed");
            continue;
        };
        if args.wait_idle {
            wait_idle();
        }
        let before = a02::load_average();
        let times = a02::wall_times(system.as_ref(), tol, args.repeats)
            .unwrap_or_else(|e| fail(&format!("N = {n}: a timed run failed: {e}")));
        let after = a02::load_average();
        eprintln!(
            "  timed at R = {tol:.0e}: {:?} s (load {before} -> {after})",
            times
        );
        rows.push(Row {
            n,
            coordinates,
            rows: m,
            tol,
            times,
            acc,
            crossings: crossings.len(),
            load: (before, after),
        });
    }

    println!();
    println!(
        "Tolerance sweep (B0 error = max over the samples of max(|x0 - cos th|, |y0 - sin th|)):"
    );
    println!();
    println!(
        "| N | R | max B0 error (m) | within 1e-3 m | max error, all tips (m) | energy drift, max (J) | at 20 s (J) | passages | rank drop | steps | RHS | max abs(Phi) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    print!("{sweep}");
    println!();
    println!(
        "At the loosest R that keeps B0 within 1e-3 m; wall time of `simulate` (assembly to last sample), median [min-max] of {} runs:",
        args.repeats
    );
    println!();
    println!(
        "| N | n | m | R | wall (ms), median [min-max] | steps (rejected) | RHS | wall / RHS (us) | max B0 error (m) | max error, all tips (m) | max abs(Phi) | energy drift, max (J) | at 20 s (J) | passages (exact crossings) | rank drop | passage time error (s) | load 1/5/15 min before -> after |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let median = r.times[r.times.len() / 2];
        let (lo, hi) = (r.times[0], r.times[r.times.len() - 1]);
        let a = &r.acc;
        println!(
            "| {} | {} | {} | {:.0e} | {} [{}-{}] | {} ({}) | {} | {:.2} | {} | {} | {} | {} | {} | {} ({}) | {} | {} | {} -> {} |",
            r.n,
            r.coordinates,
            r.rows,
            r.tol,
            ms(median),
            ms(lo),
            ms(hi),
            a.steps,
            a.rejected,
            a.rhs,
            median / a.rhs as f64 * 1e6,
            sci(a.b0_error),
            sci(a.tips_error),
            sci(a.max_phi),
            sci(a.energy_drift),
            sci(a.energy_final),
            a.passages,
            r.crossings,
            rank_drop(a),
            a.passage_time_error.map_or("-".into(), sci),
            r.load.0,
            r.load.1,
        );
    }
    println!();
    println!(
        "Total {:.1} s; load at the end {}",
        started.elapsed().as_secs_f64(),
        a02::load_average()
    );
}
