//! The IFToMM benchmark A02, the N four-bar chain, for N = 10, 20, 40 and 80 (issue 12):
//! the compiled systems, the exact branch, and one measured run (`src/bin/a02.rs` prints the
//! table of BENCHMARKS.md).
//!
//! N = 40 is the built-in `n_four_bar` (`mechanisms/n_four_bar.mech`); the other sizes are
//! expanded here from `benches/mechanisms/n_four_bar_{10,20,80}.mech`, which the test
//! `benches/tests/n_four_bar_generator.rs` keeps equal to
//! [`n_four_bar_source`](crate::n_four_bar::n_four_bar_source).

use std::time::Instant;

use mechanism::{
    Compiled, Error, IntegratorOptions, Method, SimulationOptions, System, Trajectory, simulate,
};

mechanism::mechanism!(file = "mechanisms/n_four_bar_10.mech");
mechanism::mechanism!(file = "mechanisms/n_four_bar_20.mech");
mechanism::mechanism!(file = "mechanisms/n_four_bar_80.mech");

/// The chain sizes N (couplers) measured: N + 1 rockers, 2 (N + 1) coordinates, 2 N + 1
/// constraint rows.
pub const SIZES: [usize; 4] = [10, 20, 40, 80];

/// The tolerances tried (rtol = atol), loosest first; a size runs at the loosest that keeps
/// B0 within [`B0_TOLERANCE`] of the exact branch.
pub const TOLERANCES: [f64; 5] = [1e-6, 3e-7, 1e-7, 3e-8, 1e-8];

/// The accuracy asked of the first rocker's tip B0 (m), largest over the samples.
pub const B0_TOLERANCE: f64 = 1e-3;

/// Simulated time (s): the benchmark's 20 s.
pub const T_END: f64 = 20.0;

/// Output samples per second.
pub const OUTPUT_RATE: f64 = 10.0;

/// Gravity of the declarations (m/s^2).
const G: f64 = 9.81;

/// The compiled N four-bar chain with `n` couplers, for `n` in [`SIZES`].
pub fn system(n: usize) -> Option<Box<dyn System>> {
    Some(match n {
        10 => Box::new(Compiled::new(NFourBar10::default())),
        20 => Box::new(Compiled::new(NFourBar20::default())),
        40 => mechanism::builtin::builtin("n_four_bar")?,
        80 => Box::new(Compiled::new(NFourBar80::default())),
        _ => return None,
    })
}

/// The options of one run: DOP853 at rtol = atol = `tol`, [`OUTPUT_RATE`], default
/// stabilisation (projection), [`T_END`].
pub fn options(tol: f64) -> SimulationOptions {
    SimulationOptions {
        t_end: T_END,
        output_rate: OUTPUT_RATE,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: tol,
            atol: tol,
            ..IntegratorOptions::default()
        },
        ..SimulationOptions::default()
    }
}

/// The exact motion of the chain with `n` couplers: every rocker at one angle th from +x,
/// ((N+1)/3 + N) th'' = -((N+1)/2 + N) g cos th, th(0) = pi/2, th'(0) = -1 rad/s. Classical
/// RK4 at h = 1e-4 s (as `a02_branch` in tests/runtime_overconstrained.rs; global error
/// below 1e-9 rad over 20 s), returning (th, th') at each of `times` (ascending).
pub fn exact_branch(n: usize, times: &[f64]) -> Vec<(f64, f64)> {
    let (a, b) = (
        (n + 1) as f64 / 3.0 + n as f64,
        (n + 1) as f64 / 2.0 + n as f64,
    );
    let k = b * G / a;
    let f = |y: [f64; 2]| [y[1], -k * y[0].cos()];
    let (mut y, mut t) = ([std::f64::consts::FRAC_PI_2, -1.0], 0.0);
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target - 1e-12 {
            let h = (target - t).min(1e-4);
            let k1 = f(y);
            let k2 = f([y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]]);
            let k3 = f([y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]]);
            let k4 = f([y[0] + h * k3[0], y[1] + h * k3[1]]);
            for i in 0..2 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            t += h;
        }
        out.push((y[0], y[1]));
    }
    out
}

/// The times in (0, [`T_END`]) where the exact branch of the chain with `n` couplers lies
/// flat (sin th = 0, all rockers horizontal): the singular positions the run must pass,
/// located to ~1e-8 s by linear interpolation on a 1e-4 s grid.
pub fn exact_crossings(n: usize) -> Vec<f64> {
    let h = 1e-4;
    let steps = (T_END / h).round() as usize;
    let grid: Vec<f64> = (0..=steps).map(|i| i as f64 * h).collect();
    let branch = exact_branch(n, &grid);
    let mut crossings = Vec::new();
    for i in 1..grid.len() {
        let (a, b) = (branch[i - 1].0.sin(), branch[i].0.sin());
        if a * b < 0.0 {
            crossings.push(grid[i - 1] + h * a / (a - b));
        }
    }
    crossings
}

/// What one run gives against the exact branch.
#[derive(Clone, Debug)]
pub struct Accuracy {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand sides (augmented solves).
    pub rhs: usize,
    /// max over the samples of max(|x0 - cos th|, |y0 - sin th|) (m).
    pub b0_error: f64,
    /// The same over every tip, B_i = (i + cos th, sin th), i = 0..N (m): large when the
    /// chain left the branch somewhere behind B0.
    pub tips_error: f64,
    /// max |Phi|_inf over the samples (m^2).
    pub max_phi: f64,
    /// max |(T + Pi - W)(t) - (T + Pi - W)(0)| over the samples (J).
    pub energy_drift: f64,
    /// (T + Pi - W)(t_end) - (T + Pi - W)(0) (J): what stays of the drift (a sample
    /// interpolated inside a step that crosses a singular position can stand out alone).
    pub energy_final: f64,
    /// Recorded singular passages.
    pub passages: usize,
    /// Rank drops of the recorded passages, smallest and largest.
    pub rank_drop: (usize, usize),
    /// When as many passages were recorded as the exact branch has crossings: the largest
    /// |t_passage - t_crossing| (s), pairing them in order.
    pub passage_time_error: Option<f64>,
}

/// Compares `tr` (the chain with `n` couplers) with the exact branch and `crossings`.
pub fn accuracy(n: usize, tr: &Trajectory, crossings: &[f64]) -> Accuracy {
    let times: Vec<f64> = tr.samples().map(|s| s.t).collect();
    let exact = exact_branch(n, &times);
    let (mut b0_error, mut tips_error) = (0.0f64, 0.0f64);
    for (s, (th, _)) in tr.samples().zip(&exact) {
        let (c, si) = (th.cos(), th.sin());
        for i in 0..=n {
            let e = (s.q[2 * i] - (i as f64 + c))
                .abs()
                .max((s.q[2 * i + 1] - si).abs());
            if i == 0 {
                b0_error = b0_error.max(e);
            }
            tips_error = tips_error.max(e);
        }
    }
    let max_phi = tr.samples().fold(0.0f64, |a, s| a.max(s.constraint_error));
    let e0 = tr
        .samples()
        .next()
        .map_or(0.0, |s| s.kinetic + s.potential - s.work);
    let energy_drift = tr.samples().fold(0.0f64, |a, s| {
        a.max((s.kinetic + s.potential - s.work - e0).abs())
    });
    let energy_final = tr
        .last()
        .map_or(0.0, |s| s.kinetic + s.potential - s.work - e0);
    let passages = &tr.singular_passages;
    let rank_drop = passages.iter().fold((usize::MAX, 0), |(lo, hi), p| {
        (lo.min(p.rank_drop), hi.max(p.rank_drop))
    });
    let passage_time_error = (passages.len() == crossings.len()).then(|| {
        passages
            .iter()
            .zip(crossings)
            .fold(0.0f64, |a, (p, c)| a.max((p.t - c).abs()))
    });
    Accuracy {
        steps: tr.stats.steps,
        rejected: tr.stats.rejected_steps,
        rhs: tr.stats.rhs_evaluations,
        b0_error,
        tips_error,
        max_phi,
        energy_drift,
        energy_final,
        passages: passages.len(),
        rank_drop: if passages.is_empty() {
            (0, 0)
        } else {
            rank_drop
        },
        passage_time_error,
    }
}

/// Runs `system` at rtol = atol = `tol` once and compares it with the exact branch of the
/// chain with `n` couplers.
///
/// # Errors
/// When the simulation fails.
pub fn run(n: usize, system: &dyn System, tol: f64, crossings: &[f64]) -> Result<Accuracy, Error> {
    let tr = simulate(system, &options(tol))?;
    Ok(accuracy(n, &tr, crossings))
}

/// Wall times (s) of `repeats` runs at `tol`, sorted.
///
/// # Errors
/// When a simulation fails.
pub fn wall_times(system: &dyn System, tol: f64, repeats: usize) -> Result<Vec<f64>, Error> {
    let opts = options(tol);
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let start = Instant::now();
        let tr = simulate(system, &opts)?;
        times.push(start.elapsed().as_secs_f64());
        std::hint::black_box(tr);
    }
    times.sort_by(f64::total_cmp);
    Ok(times)
}

/// The 1-, 5- and 15-minute load averages (`/proc/loadavg`), or "?" off Linux.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|| "?".into())
}
