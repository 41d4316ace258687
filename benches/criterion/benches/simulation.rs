//! Whole simulations (issue 6, item 3).
//!
//! 1. The seed crank-slider for 10 s with each integrator: wall time, steps, RHS
//!    evaluations, error at 10 s against DOP853 at 1e-13, max |Phi|.
//! 2. The planar four-bar for 10 s at an error of 1e-7 rad: the loosest tolerance that
//!    reaches it, and simulated seconds per wall second.
//! 3. |Phi| with projection, Baumgarte and no stabilisation (seed and four-bar).
//!
//! The tables are printed to stderr and written to `bench-results/simulation.md` (and the key
//! numbers to `simulation.json`) in cargo's target directory (`CARGO_TARGET_DIR` when set).
//! Each run is timed by `measure` itself; the seed's DOP853 run is also timed against scipy
//! in `benches/run.py`'s interleaved rounds.

use std::fmt::Write as _;

use mechanism::{Method, Stabilization, System};
use mechanism_bench::simulation::{
    HEADER, RunReport, T_END, measure, options, reference, row, seed_methods, stabilizations,
};

/// `bench-results/` in cargo's target directory: `CARGO_TARGET_DIR` (relative to the
/// workspace root, as cargo reads it) when set, else the workspace's `target/`.
fn results_dir() -> std::path::PathBuf {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), |t| root.join(t));
    let dir = target.join("bench-results");
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// The loosest tolerance (of 1e-5 .. 1e-12) at which `method` is within `target` of the
/// reference at 10 s.
fn at_accuracy(
    name: &str,
    system: &dyn System,
    method: Method,
    target: f64,
    reference: &[f64],
) -> Option<(f64, RunReport)> {
    for k in 5..=12 {
        let tol = 10f64.powi(-k);
        let r = measure(
            &format!("{name}, rtol = atol = 1e-{k}"),
            system,
            &options(method, tol, Stabilization::Projection),
            reference,
            5,
        );
        if r.error <= target {
            return Some((tol, r));
        }
    }
    None
}

fn tables() -> (String, String) {
    let seed = mechanism::builtin::builtin("spatial_crank_slider").expect("seed");
    let four = mechanism::builtin::builtin("planar_four_bar").expect("four-bar");
    let mut md = String::new();
    let mut json = String::from("{\n");

    let seed_ref = reference(seed.as_ref());
    let _ = writeln!(json, "  \"seed_reference_q\": {:?},", seed_ref);
    let _ = writeln!(
        md,
        "### Seed crank-slider, 10 s (projection; reference DOP853 at 1e-13)\n\n{HEADER}"
    );
    for (label, method, tol) in seed_methods() {
        let repeats = if matches!(method, Method::Rk4 { h } | Method::Hht { h, .. } if h < 5e-4) {
            3
        } else {
            7
        };
        let r = measure(
            label,
            seed.as_ref(),
            &options(method, tol, Stabilization::Projection),
            &seed_ref,
            repeats,
        );
        let _ = writeln!(md, "{}", row(&r));
        let key = label
            .split(',')
            .next()
            .unwrap_or(label)
            .split(' ')
            .next()
            .unwrap_or(label);
        let _ = writeln!(
            json,
            "  \"seed {label}\": {{\"method\": \"{key}\", \"wall_s\": {:e}, \"steps\": {}, \"rhs\": {}, \"error\": {:e}, \"max_phi\": {:e}}},",
            r.wall_s, r.steps, r.rhs, r.error, r.max_phi
        );
    }

    let four_ref = reference(four.as_ref());
    let _ = writeln!(
        md,
        "\n### Planar four-bar, 10 s at an error of 1e-7 rad (loosest tolerance that reaches it)\n\n\
         | run | wall (ms) | steps | rejected | RHS evals | error at 10 s | max abs(Phi) | simulated s / wall s |\n\
         |---|---|---|---|---|---|---|---|"
    );
    let mut lines = Vec::new();
    for (name, method) in [("dopri5", Method::Dopri5), ("dop853", Method::Dop853)] {
        match at_accuracy(name, four.as_ref(), method, 1e-7, &four_ref) {
            Some((tol, r)) => {
                let speed = T_END / r.wall_s;
                lines.push(format!("{} {:.0} |", row(&r), speed));
                let _ = writeln!(
                    json,
                    "  \"four_bar {name}\": {{\"tol\": {tol:e}, \"wall_s\": {:e}, \"error\": {:e}, \"sim_per_wall\": {speed:e}}},",
                    r.wall_s, r.error
                );
            }
            None => lines.push(format!(
                "| {name} | did not reach 1e-7 rad down to 1e-12 | | | | | | |"
            )),
        }
    }
    for l in lines {
        let _ = writeln!(md, "{l}");
    }

    let _ = writeln!(
        md,
        "\n### Loop closure: max abs(Phi) over 10 s, DOP853 at 1e-10\n\n| model | stabilisation | max abs(Phi) | error at 10 s | wall (ms) |\n|---|---|---|---|---|"
    );
    for (model, system, r) in [
        ("seed", seed.as_ref(), &seed_ref),
        ("four-bar", four.as_ref(), &four_ref),
    ] {
        for (label, stab) in stabilizations() {
            let rep = measure(label, system, &options(Method::Dop853, 1e-10, stab), r, 3);
            let _ = writeln!(
                md,
                "| {model} | {label} | {:.1e} | {:.1e} | {:.3} |",
                rep.max_phi,
                rep.error,
                rep.wall_s * 1e3
            );
            let _ = writeln!(
                json,
                "  \"phi {model} {label}\": {{\"max_phi\": {:e}, \"error\": {:e}}},",
                rep.max_phi, rep.error
            );
        }
    }
    json.push_str("  \"t_end\": 10.0\n}\n");
    (md, json)
}

fn main() {
    let (md, json) = tables();
    eprintln!("{md}");
    let dir = results_dir();
    let _ = std::fs::write(dir.join("simulation.md"), &md);
    let _ = std::fs::write(dir.join("simulation.json"), &json);
}
