//! Whole simulations: 10 s of DOP853 with the default projection, 10 samples per second
//! (scipy's `solve_ivp` peer records only its steps, so the output costs little here too).

use std::time::Instant;

use mechanism::{
    IntegratorOptions, Method, SimulationOptions, Stabilization, StepController, System, simulate,
};

/// What [`simulate_runs`] measured.
pub struct Runs {
    /// Wall time of each timed run (s).
    pub wall_s: Vec<f64>,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand sides (augmented solves).
    pub rhs: usize,
    /// q at 10 s.
    pub q_end: Vec<f64>,
    /// Largest |Phi|_inf over the samples.
    pub max_phi: f64,
    /// Whether the predictive step controller ran.
    pub predictive: bool,
}

/// 10 s of DOP853 at rtol = atol = `tol` with projection, PI step control or the predictive
/// controller.
fn options(tol: f64, predictive: bool) -> SimulationOptions {
    let controller = if predictive {
        StepController::Predictive
    } else {
        StepController::Pi
    };
    SimulationOptions {
        t_end: 10.0,
        output_rate: 10.0,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: tol,
            atol: tol,
            controller,
            ..IntegratorOptions::default()
        },
        stabilization: Stabilization::Projection,
        ..SimulationOptions::default()
    }
}

/// One untimed run, then `runs` timed ones.
pub fn simulate_runs(system: &dyn System, runs: usize, tol: f64, predictive: bool) -> Runs {
    let opts = options(tol, predictive);
    let run = || {
        simulate(system, &opts)
            .unwrap_or_else(|e| panic!("{}: simulation failed: {e}", system.info().name))
    };
    let last = run();
    let wall_s = (0..runs)
        .map(|_| {
            let start = Instant::now();
            let t = run();
            let s = start.elapsed().as_secs_f64();
            std::hint::black_box(t.len());
            s
        })
        .collect();
    Runs {
        wall_s,
        steps: last.stats.steps,
        rejected: last.stats.rejected_steps,
        rhs: last.stats.rhs_evaluations,
        q_end: last.last().map(|s| s.q.to_vec()).unwrap_or_default(),
        max_phi: last
            .samples()
            .fold(0.0, |a: f64, s| a.max(s.constraint_error)),
        predictive,
    }
}

/// q at 10 s from DOP853 at rtol = atol = 1e-13 (the error reference).
pub fn reference(system: &dyn System) -> Vec<f64> {
    let t = simulate(system, &options(1e-13, false))
        .unwrap_or_else(|e| panic!("{}: reference run failed: {e}", system.info().name));
    t.last().map(|s| s.q.to_vec()).unwrap_or_default()
}
