//! `mechanism simulate` (and the default command): assemble, integrate, write
//! trajectory.csv, summary.json and the figures, print a summary.

use std::path::{Path, PathBuf};

use super::CliError;
use super::args::{CommonArgs, IntegratorArg, SimulateArgs, StabilizationArg};
use super::load::{apply_sets, initial_values, load};
use super::progress::Progress;
use super::report::summary_text;
use super::validate::{check_csv_size, check_span};
use mechanism::Stabilization;
use mechanism::System;
use mechanism::Trajectory;
use mechanism::integrators::{IntegratorOptions, Method};
use mechanism::output::{
    RunSettings, Summary, plot_trajectory, write_summary, write_trajectory_csv,
};
use mechanism::{AssemblyOptions, assemble_from};
use mechanism::{InitialState, SimulationOptions, Simulator};

/// Default fixed step for rk4 and hht when `--step` is not given (s).
const DEFAULT_STEP: f64 = 1e-3;
/// Baumgarte gains alpha = beta (1/s) for `--stabilization baumgarte`.
const BAUMGARTE_GAIN: f64 = 10.0;

/// What `mechanism` with no arguments runs: the seed for 10 s with DOP853 at 1e-10.
pub fn default_args() -> SimulateArgs {
    SimulateArgs {
        common: CommonArgs {
            mechanism: "spatial_crank_slider".into(),
            t_end: 10.0,
            samples_per_second: 100.0,
            set: vec![],
            init: vec![],
            out: None,
        },
        integrator: IntegratorArg::Dop853,
        rtol: 1e-10,
        atol: 1e-10,
        step: None,
        stabilization: StabilizationArg::Projection,
    }
}

/// The integrator options the flags ask for.
fn integrator(a: &SimulateArgs) -> Result<(IntegratorOptions, String), CliError> {
    if let Some(h) = a.step.filter(|h| !(h.is_finite() && *h > 0.0)) {
        return Err(CliError::Argument(format!(
            "--step must be a positive number of seconds, got {h}"
        )));
    }
    if !(a.rtol > 0.0 && a.atol > 0.0) {
        return Err(CliError::Argument(
            "--rtol and --atol must be positive".into(),
        ));
    }
    let h = a.step.unwrap_or(DEFAULT_STEP);
    let (method, name) = match a.integrator {
        IntegratorArg::Rk4 => (Method::Rk4 { h }, "rk4"),
        IntegratorArg::Dopri5 => (Method::Dopri5, "dopri5"),
        IntegratorArg::Dop853 => (Method::Dop853, "dop853"),
        IntegratorArg::Hht => (Method::Hht { h, alpha: -0.05 }, "hht"),
    };
    let adaptive = matches!(a.integrator, IntegratorArg::Dopri5 | IntegratorArg::Dop853);
    let options = IntegratorOptions {
        method,
        rtol: a.rtol,
        atol: a.atol,
        h_initial: if adaptive { a.step } else { None },
        ..IntegratorOptions::default()
    };
    Ok((options, name.to_string()))
}

/// The output folder: `--out`, or `out/<key>`.
pub fn out_dir(common: &CommonArgs, key: &str) -> PathBuf {
    common
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(key))
}

/// Per-row constraint residuals |Phi_i| at every sample (for the constraint-error figure).
fn residuals(system: &dyn System, trajectory: &Trajectory) -> Vec<Vec<f64>> {
    let m = system.info().m();
    let mut rows = vec![Vec::with_capacity(trajectory.len()); m];
    let mut phi = vec![0.0; m];
    for s in trajectory.samples() {
        system.constraints(s.t, s.q, &mut phi);
        for (r, v) in rows.iter_mut().zip(&phi) {
            r.push(v.abs());
        }
    }
    rows
}

/// Runs `simulate` with `a`.
pub fn run(a: &SimulateArgs) -> Result<(), CliError> {
    check_span(&a.common)?;
    let mut loaded = load(&a.common.mechanism)?;
    apply_sets(loaded.system.as_mut(), &a.common.set)?;
    let system = loaded.system.as_ref();
    let columns = 1 + 3 * system.info().n() + system.info().m() + 5;
    check_csv_size(&a.common, "trajectory.csv", columns)?;
    let (independent, guess) = initial_values(system, &a.common)?;
    let assembly = AssemblyOptions::default();
    let start = assemble_from(system, 0.0, &independent, &guess, &assembly)?;
    let (integrator_options, integrator_name) = integrator(a)?;
    let (stabilization, stab_name) = match a.stabilization {
        StabilizationArg::Projection => (Stabilization::Projection, "projection"),
        StabilizationArg::Baumgarte => (
            Stabilization::Baumgarte {
                alpha: BAUMGARTE_GAIN,
                beta: BAUMGARTE_GAIN,
            },
            "baumgarte",
        ),
        StabilizationArg::None => (Stabilization::None, "none"),
    };
    let options = SimulationOptions {
        t_end: a.common.t_end,
        output_rate: a.common.samples_per_second,
        integrator: integrator_options,
        stabilization,
        initial: InitialState::Consistent {
            q: start.q.clone(),
            qd: start.qd.clone(),
        },
        assembly,
        ..SimulationOptions::default()
    };
    let mut sim = Simulator::new(system, &options)?;
    let mut progress = Progress::new(a.common.t_end);
    let failure = loop {
        match sim.step() {
            Ok(true) => progress.set(sim.time()),
            Ok(false) => break None,
            Err(e) => break Some(e),
        }
    };
    progress.finish();
    let trajectory = sim.finish(None).trajectory;

    let dir = out_dir(&a.common, &loaded.key);
    let mut files = Vec::new();
    write_trajectory_csv(&dir.join("trajectory.csv"), &trajectory)?;
    files.push(dir.join("trajectory.csv"));
    let mut params = vec![0.0; system.info().parameters.len()];
    system.parameter_values(&mut params);
    let adaptive = matches!(a.integrator, IntegratorArg::Dopri5 | IntegratorArg::Dop853);
    let settings = RunSettings {
        integrator: integrator_name,
        rtol: adaptive.then_some(a.rtol),
        atol: adaptive.then_some(a.atol),
        stabilization: stab_name.to_string(),
    };
    let mut summary = Summary::new(&trajectory, &params, &settings)?;
    if let Some(e) = &failure {
        summary.failed(e);
    }
    write_summary(&dir.join("summary.json"), &summary)?;
    files.push(dir.join("summary.json"));
    if trajectory.len() >= 2 {
        let res = residuals(system, &trajectory);
        files.extend(plot_trajectory(&dir, &trajectory, None, Some(&res))?);
    }
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    print!("{}", summary_text(&loaded.key, system, &summary, &names));
    loaded.source.clear();
    match failure {
        // The samples up to the failure are written; the run still failed.
        Some(e) => Err(CliError::Stopped {
            t: summary.t_last,
            dir: dir.display().to_string(),
            error: e,
        }),
        None => Ok(()),
    }
}
