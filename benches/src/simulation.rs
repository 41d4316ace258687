//! Whole simulations (issue 6, item 3): the seed for 10 s with each integrator, the four-bar
//! at a prescribed accuracy, and the loop-closure residual under each stabilisation.
//!
//! Errors are measured against a run of our own at DOP853, rtol = atol = 1e-13 (projection),
//! as the largest |q_k(10 s) - q_k^ref(10 s)| over the coordinates (rad, or m for x_c).

use std::time::Instant;

use mechanism::{
    IntegratorOptions, Method, SimulationOptions, Stabilization, System, Trajectory, simulate,
};

/// End time of every whole-simulation benchmark (s).
pub const T_END: f64 = 10.0;
/// Output samples per second: low, so that the timing is the integration itself (scipy's
/// `solve_ivp` baseline records only its steps). |Phi| is the maximum over these samples.
pub const OUTPUT_RATE: f64 = 10.0;

/// Options for a 10 s run with `method` at rtol = atol = `tol`.
pub fn options(method: Method, tol: f64, stabilization: Stabilization) -> SimulationOptions {
    SimulationOptions {
        t_end: T_END,
        output_rate: OUTPUT_RATE,
        integrator: IntegratorOptions {
            method,
            rtol: tol,
            atol: tol,
            ..IntegratorOptions::default()
        },
        stabilization,
        ..SimulationOptions::default()
    }
}

/// One whole-simulation measurement.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// What was run.
    pub label: String,
    /// Wall time of the run (s), the median of `repeats` runs.
    pub wall_s: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand-side evaluations (augmented solves).
    pub rhs: usize,
    /// max_k |q_k(T) - q_k^ref(T)|.
    pub error: f64,
    /// max |Phi|_inf over the samples.
    pub max_phi: f64,
}

/// q at the last sample of `traj`.
pub fn final_q(traj: &Trajectory) -> Vec<f64> {
    traj.last().map(|s| s.q.to_vec()).unwrap_or_default()
}

/// max |Phi|_inf over the samples of `traj`.
pub fn max_phi(traj: &Trajectory) -> f64 {
    traj.samples().fold(0.0, |a, s| a.max(s.constraint_error))
}

/// The reference end state: DOP853 at rtol = atol = 1e-13 with projection.
pub fn reference(system: &dyn System) -> Vec<f64> {
    let traj = simulate(
        system,
        &options(Method::Dop853, 1e-13, Stabilization::Projection),
    )
    .unwrap_or_else(|e| panic!("{}: reference run failed: {e}", system.info().name));
    final_q(&traj)
}

/// Runs `opts` `repeats` times on `system` and reports the median wall time with the
/// statistics of the last run and its error against `reference`.
pub fn measure(
    label: &str,
    system: &dyn System,
    opts: &SimulationOptions,
    reference: &[f64],
    repeats: usize,
) -> RunReport {
    let mut times = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let traj = simulate(system, opts);
        times.push(start.elapsed().as_secs_f64());
        last = Some(traj);
    }
    times.sort_by(f64::total_cmp);
    let wall_s = times[times.len() / 2];
    match last {
        Some(Ok(traj)) => {
            let q = final_q(&traj);
            let error = q
                .iter()
                .zip(reference)
                .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
            RunReport {
                label: label.to_string(),
                wall_s,
                steps: traj.stats.steps,
                rejected: traj.stats.rejected_steps,
                rhs: traj.stats.rhs_evaluations,
                error,
                max_phi: max_phi(&traj),
            }
        }
        Some(Err(e)) => {
            eprintln!("{label}: failed: {e}");
            RunReport {
                label: label.to_string(),
                wall_s,
                steps: 0,
                rejected: 0,
                rhs: 0,
                error: f64::NAN,
                max_phi: f64::NAN,
            }
        }
        None => unreachable!("at least one run"),
    }
}

/// The seed integrator table: rk4 (fixed step), dopri5 and dop853 at 1e-10, hht.
pub fn seed_methods() -> Vec<(&'static str, Method, f64)> {
    vec![
        ("rk4, h = 1e-3", Method::Rk4 { h: 1e-3 }, 1e-10),
        ("rk4, h = 1e-4", Method::Rk4 { h: 1e-4 }, 1e-10),
        ("dopri5, rtol = atol = 1e-10", Method::Dopri5, 1e-10),
        ("dop853, rtol = atol = 1e-10", Method::Dop853, 1e-10),
        (
            "hht (alpha = -0.05), h = 1e-3",
            Method::Hht {
                h: 1e-3,
                alpha: -0.05,
            },
            1e-10,
        ),
        (
            "hht (alpha = -0.05), h = 1e-4",
            Method::Hht {
                h: 1e-4,
                alpha: -0.05,
            },
            1e-10,
        ),
    ]
}

/// The stabilisation choices compared for |Phi|.
pub fn stabilizations() -> Vec<(&'static str, Stabilization)> {
    vec![
        ("projection", Stabilization::Projection),
        (
            "baumgarte (alpha = beta = 10)",
            Stabilization::Baumgarte {
                alpha: 10.0,
                beta: 10.0,
            },
        ),
        ("none", Stabilization::None),
    ]
}

/// Formats a report as a markdown table row.
pub fn row(r: &RunReport) -> String {
    format!(
        "| {} | {:.4} | {} | {} | {} | {:.1e} | {:.1e} |",
        r.label,
        r.wall_s * 1e3,
        r.steps,
        r.rejected,
        r.rhs,
        r.error,
        r.max_phi
    )
}

/// The header matching [`row`].
pub const HEADER: &str = "| run | wall (ms) | steps | rejected | RHS evals | error at 10 s | max abs(Phi) |\n|---|---|---|---|---|---|---|";
