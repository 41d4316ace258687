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

/// The exact motion of the chain with `n` couplers: (th, th') at each of `times`
/// (`mechanism_test_support::a02::branch`).
pub fn exact_branch(n: usize, times: &[f64]) -> Vec<(f64, f64)> {
    mechanism_test_support::a02::branch(n, times)
}

/// The times in (0, [`T_END`]) where the exact branch of the chain with `n` couplers lies
/// flat: the singular positions the run must pass.
pub fn exact_crossings(n: usize) -> Vec<f64> {
    mechanism_test_support::a02::crossings(n, T_END)
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
