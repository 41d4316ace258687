//! The cost of one right-hand side (`Dynamics::solve`, then the minimum-norm multipliers a
//! sample records) for a point mass on the line x = 1 declared K times: K constraint rows of
//! rank 1 (issue 28: a redundant set should cost what its rank costs).
//!
//! ```text
//! cargo run --release -p mechanism-bench --bin redundant_rows [-- K ...]
//! ```
//!
//! Default K = 10 100 1000 10000; each solve timed as the median of 21 (wall time), then
//! the growth exponent of the solve's time in K fitted on log-log (1 for a cost linear in
//! the rows).

use std::fmt::Write as _;
use std::time::Instant;

use mechanism::{Dynamics, Interpreted, Kinematic};

fn source(k: usize) -> String {
    let mut s = String::from(
        "pub struct Redundant;\n\
         coordinates { x = 1.0; y = 0.0; }\n\
         independent { y = 0.0; der(y) = 1.0; }\n\
         kinetic = (der(x)^2 + der(y)^2)/2;\n\
         potential = 9.81*y;\n\
         constraints {\n",
    );
    for _ in 0..k {
        let _ = writeln!(s, "    x - 1;");
    }
    s.push_str("}\n");
    s
}

fn main() {
    let mut sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    if sizes.is_empty() {
        sizes = vec![10, 100, 1000, 10000];
    }
    println!("| copies of one row | solve (µs) | solve + minimum-norm multipliers (µs) |");
    println!("|---|---|---|");
    let mut points = Vec::new();
    for k in sizes {
        let system = match Interpreted::from_source(&source(k)) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("redundant_rows: K = {k}: {e}");
                std::process::exit(1);
            }
        };
        let mut d = Dynamics::new(system.info());
        let (q, qd) = ([1.0, 0.0], [0.0, 1.0]);
        let mut time = |with_multipliers: bool| {
            let mut t: Vec<f64> = (0..21)
                .map(|_| {
                    let start = Instant::now();
                    d.solve(&system, 0.0, &q, &qd).expect("a determined motion");
                    if with_multipliers {
                        std::hint::black_box(d.min_norm_multipliers());
                    }
                    start.elapsed().as_secs_f64() * 1e6
                })
                .collect();
            t.sort_by(f64::total_cmp);
            t[10]
        };
        let (solve, both) = (time(false), time(true));
        // y'' = -9.81 whatever the rows: the check that the redundant solve is right.
        assert!((d.accelerations()[1] + 9.81).abs() < 1e-9 && d.accelerations()[0].abs() < 1e-9);
        println!("| {k} | {solve:.1} | {both:.1} |");
        points.push(((k as f64).ln(), solve.ln()));
    }
    if points.len() >= 2 {
        // Least-squares slope of ln(time) against ln(K).
        let count = points.len() as f64;
        let mx = points.iter().map(|p| p.0).sum::<f64>() / count;
        let my = points.iter().map(|p| p.1).sum::<f64>() / count;
        let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = points.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
        println!();
        println!(
            "Fitted growth of the solve in the copies K: K^{:.2}",
            sxy / sxx
        );
    }
}
