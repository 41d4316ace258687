//! A02, the N four-bar chain, as N grows (issue 28): the cost of one right-hand side on the
//! compiled route (N = 10..80, `mechanism_bench::a02::system`) and on the interpreter route
//! (any N, derived here from `n_four_bar_source`), each over the benchmark's 20 s at one
//! tolerance, started from the exact consistent state (no assembly), with B0 checked
//! against the exact branch; then the growth exponent fitted to µs per RHS against N and the
//! interpreter/compiled ratio.
//!
//! ```text
//! cargo run --release -p mechanism-bench --bin a02_scale [-- [--tol R] [--repeats K] [N ...]]
//! cargo run --release -p mechanism-bench --bin a02_scale -- --mech N > a02_N.mech
//! ```
//!
//! (`--mech N` prints the declaration of one N and exits.)
//!
//! Defaults: R = 3e-7 (the loosest that keeps B0 within 1e-3 m for N = 10..80 in
//! BENCHMARKS.md's A02 tables), K = 3 timed runs per route (median), N = 10 20 40 80 160 320.

use mechanism_bench::thread_cpu;
use std::time::Instant;

use mechanism::{InitialState, Interpreted, Kinematic, SimulationOptions, System, simulate};
use mechanism_bench::a02::{self, B0_TOLERANCE, exact_crossings};
use mechanism_bench::n_four_bar::n_four_bar_source;

struct Args {
    sizes: Vec<usize>,
    tol: f64,
    repeats: usize,
}

fn args() -> Args {
    let mut out = Args {
        sizes: Vec::new(),
        tol: 3e-7,
        repeats: 3,
    };
    let mut it = std::env::args().skip(1);
    let fail = |m: &str| -> ! {
        eprintln!("a02_scale: {m}");
        std::process::exit(1)
    };
    while let Some(a) = it.next() {
        match a.as_str() {
            "--tol" => {
                out.tol = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .filter(|v: &f64| *v > 0.0)
                    .unwrap_or_else(|| fail("--tol needs a positive number"));
            }
            "--mech" => {
                // The declaration of one N, for the command-line tool (`mechanism simulate`).
                let n = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .filter(|&v: &usize| v > 0)
                    .unwrap_or_else(|| fail("--mech needs a positive integer"));
                print!("{}", n_four_bar_source(n));
                std::process::exit(0);
            }
            "--repeats" => {
                out.repeats = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .filter(|&v| v > 0)
                    .unwrap_or_else(|| fail("--repeats needs a positive integer"));
            }
            n => match n.parse() {
                Ok(n) if n >= 1 => out.sizes.push(n),
                _ => fail(&format!("unknown argument `{n}`")),
            },
        }
    }
    if out.sizes.is_empty() {
        out.sizes = vec![10, 20, 40, 80, 160, 320];
    }
    out
}

/// The options of one run: [`a02::options`] from the exact initial state of the chain with
/// `n` couplers (x_i = i, y_i = 1, x_i' = 1 m/s, y_i' = 0).
fn options(n: usize, tol: f64) -> SimulationOptions {
    let rockers = n + 1;
    let mut q = vec![0.0; 2 * rockers];
    let mut qd = vec![0.0; 2 * rockers];
    for i in 0..rockers {
        q[2 * i] = i as f64;
        q[2 * i + 1] = 1.0;
        qd[2 * i] = 1.0;
    }
    SimulationOptions {
        initial: InitialState::Consistent { q, qd },
        ..a02::options(tol)
    }
}

/// One route at one N: median time (s) of `repeats` runs (the thread's CPU time where the
/// system reports it, else the wall time), RHS per run, B0 error.
struct Measured {
    wall: f64,
    rhs: usize,
    b0: f64,
}

impl Measured {
    fn us_per_rhs(&self) -> f64 {
        self.wall / self.rhs as f64 * 1e6
    }
}

fn measure(n: usize, system: &dyn System, tol: f64, repeats: usize) -> Result<Measured, String> {
    let opts = options(n, tol);
    let crossings = exact_crossings(n);
    let mut walls = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats {
        let (start, cpu) = (Instant::now(), thread_cpu());
        let tr = simulate(system, &opts).map_err(|e| e.to_string())?;
        let wall = start.elapsed().as_secs_f64();
        walls.push(match (cpu, thread_cpu()) {
            (Some(a), Some(b)) => b - a,
            _ => wall,
        });
        last = Some(tr);
    }
    walls.sort_by(f64::total_cmp);
    let tr = last.ok_or("no run")?;
    let acc = a02::accuracy(n, &tr, &crossings);
    Ok(Measured {
        wall: walls[walls.len() / 2],
        rhs: acc.rhs,
        b0: acc.b0_error,
    })
}

/// The least-squares slope of ln y against ln x.
fn exponent(points: &[(f64, f64)]) -> f64 {
    let k = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / k, ly.iter().sum::<f64>() / k);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn main() {
    let args = args();
    let started = Instant::now();
    println!(
        "A02 per right-hand side: {} s, DOP853 at rtol = atol = {:.0e}, projection, from the exact state; median of {} runs; {} time; load at start {}",
        a02::T_END,
        args.tol,
        args.repeats,
        if thread_cpu().is_some() {
            "CPU"
        } else {
            "wall"
        },
        a02::load_average()
    );
    println!();
    println!(
        "| N | n | m | derivation, interpreter (s) | RHS | compiled: run (ms) | compiled: µs/RHS | interpreter: run (ms) | interpreter: µs/RHS | interpreter / compiled | max B0 error (m) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let (mut compiled_points, mut interpreted_points) = (Vec::new(), Vec::new());
    for &n in &args.sizes {
        let start = Instant::now();
        let interpreted = match Interpreted::from_source(&n_four_bar_source(n)) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("N = {n}: derivation failed: {e}");
                continue;
            }
        };
        let derivation = start.elapsed().as_secs_f64();
        eprintln!("N = {n}: derived in {derivation:.2} s");
        let compiled = a02::system(n).map(|s| measure(n, s.as_ref(), args.tol, args.repeats));
        let interp = measure(n, &interpreted, args.tol, args.repeats);
        let (c, i) = match (compiled.transpose(), interp) {
            (Ok(c), Ok(i)) => (c, i),
            (Err(e), _) | (_, Err(e)) => {
                eprintln!("N = {n}: a run failed: {e}");
                continue;
            }
        };
        let b0 = c.as_ref().map_or(i.b0, |c| c.b0.max(i.b0));
        if b0 > B0_TOLERANCE {
            eprintln!("N = {n}: B0 error {b0:.1e} m above {B0_TOLERANCE} m at this tolerance");
        }
        let dash = || "-".to_string();
        println!(
            "| {n} | {} | {} | {derivation:.2} | {} | {} | {} | {:.1} | {:.2} | {} | {b0:.1e} |",
            interpreted.info().n(),
            interpreted.info().m(),
            i.rhs,
            c.as_ref()
                .map_or_else(dash, |c| format!("{:.1}", c.wall * 1e3)),
            c.as_ref()
                .map_or_else(dash, |c| format!("{:.2}", c.us_per_rhs())),
            i.wall * 1e3,
            i.us_per_rhs(),
            c.as_ref()
                .map_or_else(dash, |c| format!("{:.2}", i.us_per_rhs() / c.us_per_rhs())),
        );
        if let Some(c) = &c {
            compiled_points.push((n as f64, c.us_per_rhs()));
        }
        interpreted_points.push((n as f64, i.us_per_rhs()));
    }
    println!();
    for (route, points) in [
        ("compiled", &compiled_points),
        ("interpreter", &interpreted_points),
    ] {
        if points.len() >= 2 {
            let (lo, hi) = (points[0].0, points[points.len() - 1].0);
            println!(
                "Fitted growth of µs per RHS, {route}, N = {lo}..{hi}: N^{:.2}",
                exponent(points)
            );
        }
    }
    println!(
        "Total {:.1} s; load at the end {}",
        started.elapsed().as_secs_f64(),
        a02::load_average()
    );
}
