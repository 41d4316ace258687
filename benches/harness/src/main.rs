//! The like-for-like timing program behind `benches/run.py` (one command for every table of
//! BENCHMARKS.md). Each call prints one JSON object on stdout:
//!
//! ```text
//! harness state <model>                       the assembled state and the C inputs
//! harness eval <model> <what> <batches> <n>   ns per call of each batch of n calls
//! harness solve <model> <batches> <n>         ns per Dynamics::solve, each batch of n
//! harness simulate <model> <runs> <tol> [predictive]
//!                                             10 s of DOP853 at rtol = atol = tol (PI
//!                                             step control, or the predictive controller)
//! harness reference <model>                   q at 10 s from DOP853 at 1e-13
//! harness robot <rounds>                      the Panda's robotics routines (robot.rs)
//! harness floating <robot> <rounds>           Solo12's or Talos' floating-base routines
//!                                             (floating.rs)
//! harness derivatives <robot> <rounds>        the derivatives of the dynamics of the
//!                                             Panda, the UR5 or Solo12 (derivatives.rs)
//! ```
//!
//! `<what>` is `evaluate` (the combined evaluation into the caller's buffer) or `five` (M,
//! C q', g, Phi and Phi_q by the five separate functions, each called through a pointer so
//! that nothing is shared between them, like SymPy's per-routine C). Inputs: the assembled
//! state of the model (q and q' from its declared independent coordinates, the first rate
//! set to 1 rad/s for a model assembled at rest), t = 0.3, the declared parameters; q_0
//! grows by 1e-15 before every call, exactly as in the C loop. The model names are `seed`,
//! `four_bar`, `rssr`, `chain8`, `chain16` and `chain32`.

mod derivatives;
mod floating;
mod models;
mod robot;
mod simulate;
mod timing;

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize| args.get(k).map(String::as_str).unwrap_or("");
    let number = |k: usize| arg(k).parse::<f64>().ok();
    if arg(0) == "floating" {
        let rounds = number(2).map_or(11, |r| r as usize).max(1);
        return match floating::floating_json(arg(1), rounds) {
            Some(json) => {
                println!("{json}");
                ExitCode::SUCCESS
            }
            None => {
                eprintln!(
                    "harness floating: unknown robot {:?} (solo12, talos)",
                    arg(1)
                );
                ExitCode::FAILURE
            }
        };
    }
    if arg(0) == "robot" {
        let rounds = number(1).map_or(11, |r| r as usize).max(1);
        println!("{}", robot::robot_json(rounds));
        return ExitCode::SUCCESS;
    }
    if arg(0) == "derivatives" {
        let rounds = number(2).map_or(11, |r| r as usize).max(1);
        return match derivatives::derivatives_json(arg(1), rounds) {
            Some(json) => {
                println!("{json}");
                ExitCode::SUCCESS
            }
            None => {
                eprintln!("derivatives <panda|ur5|solo12> <rounds>");
                ExitCode::FAILURE
            }
        };
    }
    let result = match (arg(0), models::Model::named(arg(1))) {
        ("state", Some(m)) => Ok(m.state_json()),
        ("eval", Some(m)) => match (number(3), number(4)) {
            (Some(b), Some(n)) => m.eval_json(arg(2), b as usize, n as usize),
            _ => Err("eval <model> <evaluate|five> <batches> <calls>".to_string()),
        },
        ("solve", Some(m)) => match (number(2), number(3)) {
            (Some(b), Some(n)) => Ok(m.solve_json(b as usize, n as usize)),
            _ => Err("solve <model> <batches> <calls>".to_string()),
        },
        ("simulate", Some(m)) => match (number(2), number(3)) {
            (Some(r), Some(tol)) => Ok(m.simulate_json(r as usize, tol, arg(4) == "predictive")),
            _ => Err("simulate <model> <runs> <tol> [predictive]".to_string()),
        },
        ("reference", Some(m)) => Ok(m.reference_json()),
        (_, None) => Err(format!(
            "unknown model {:?} (one of {})",
            arg(1),
            models::NAMES.join(", ")
        )),
        (cmd, _) => Err(format!("unknown command {cmd:?}")),
    };
    match result {
        Ok(json) => {
            println!("{json}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("harness: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `[a, b, c]` with every value in Rust's shortest round-trip form.
fn json_list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(", "))
}
