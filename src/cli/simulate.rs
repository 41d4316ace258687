//! `mechanism simulate` (and the default command): assemble, integrate, write
//! trajectory.csv, summary.json and the figures, print a summary.

use super::CliError;
use super::args::{CommonArgs, FiguresArg, IntegratorArg, SimulateArgs, StabilizationArg, ViewArg};
use super::drawing::write_drawing;
use super::load::{Loaded, load};
use super::physical::check_assembled;
use super::physical::{apply_sets, initial_values};
use super::progress::Progress;
use super::report::summary_text;
use super::run_dir::{
    At, Failure, Known, OUTPUT, RunDir, left_as_it_was, output_folder, owning_folder,
};
use super::seed::figure_names;
use super::stdio::print;
use super::validate::{check_csv_size, check_integrator, check_span};
use mechanism::Stabilization;
use mechanism::System;
use mechanism::Trajectory;
use mechanism::integrators::{IntegratorOptions, Method};
use mechanism::output::{
    Figures, OutputError, RunSettings, SUMMARY_FILE, Summary, plot_run, write_summary,
    write_trajectory_csv,
};
use mechanism::{AssemblyOptions, assemble_from};
use mechanism::{Error, Independent, InitialState, SimulationOptions, Simulator};
use mechanism_codegen::Tangents;

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
            no_animation: false,
            view: ViewArg::Auto,
            strobe: 12,
            figures: FiguresArg::Auto,
        },
        integrator: IntegratorArg::Dop853,
        rtol: 1e-10,
        atol: 1e-10,
        step: None,
        stabilization: StabilizationArg::Projection,
    }
}

/// How the run integrates, from the flags.
struct Settings {
    integrator: IntegratorOptions,
    stabilization: Stabilization,
    /// What summary.json records of them.
    run: RunSettings,
}

/// The integrator and stabilisation the flags ask for.
fn settings(a: &SimulateArgs) -> Result<Settings, CliError> {
    check_integrator(a)?;
    let h = a.step.unwrap_or(DEFAULT_STEP);
    let (method, name) = match a.integrator {
        IntegratorArg::Rk4 => (Method::Rk4 { h }, "rk4"),
        IntegratorArg::Dopri5 => (Method::Dopri5, "dopri5"),
        IntegratorArg::Dop853 => (Method::Dop853, "dop853"),
        IntegratorArg::Hht => (Method::Hht { h, alpha: -0.05 }, "hht"),
    };
    let adaptive = matches!(a.integrator, IntegratorArg::Dopri5 | IntegratorArg::Dop853);
    let integrator = IntegratorOptions {
        method,
        rtol: a.rtol,
        atol: a.atol,
        h_initial: if adaptive { a.step } else { None },
        ..IntegratorOptions::default()
    };
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
    let run = RunSettings {
        integrator: name.to_string(),
        rtol: adaptive.then_some(a.rtol),
        atol: adaptive.then_some(a.atol),
        stabilization: stab_name.to_string(),
    };
    Ok(Settings {
        integrator,
        stabilization,
        run,
    })
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

/// Runs `simulate` with `a`: everything that can refuse the run is checked ([`prepare`]),
/// with the output folder untouched; then the folder is claimed ([`owning_folder`]) and the
/// run starts. A failure from the assembly on leaves a `summary.json` saying where and why.
pub fn run(a: &SimulateArgs) -> Result<(), CliError> {
    check_span(&a.common)?;
    // A floating base steps on its own route (`floating`).
    if let Some(loaded) = super::floating::load(&a.common.mechanism)? {
        return super::floating::run(a, loaded);
    }
    let settings = settings(a)?;
    let prepared = prepare(a, &settings)?;
    let dir = output_folder(&a.common, &prepared.loaded.key);
    let known = Known::of(prepared.loaded.system.as_ref());
    let run = |out: &mut RunDir, _: &mut Known| simulate(a, &settings, prepared, out);
    owning_folder(&dir, "trajectory.csv", known, run, |known, failure, out| {
        let mut summary = Summary::not_started(
            &known.mechanism,
            known.parameters,
            &settings.run,
            failure.stage,
            &failure.error,
        );
        summary.outcome.files = out.names();
        write_summary(&out.file(SUMMARY_FILE), &summary)
    })
}

/// A run checked and ready to start: the mechanism with its `--set` values, the
/// independent coordinates and guesses the assembly starts from, the run's options.
struct Prepared {
    loaded: Loaded,
    independent: Vec<Independent>,
    guess: Vec<f64>,
    options: SimulationOptions,
}

/// Everything that refuses a run before it starts, with nothing written: the mechanism
/// loaded, `--set` and `--init` applied and checked, the CSV's size, and the simulator's
/// own refusals ([`Simulator::check`]: a fixed step too small, an output too large).
fn prepare(a: &SimulateArgs, settings: &Settings) -> Result<Prepared, CliError> {
    // Only the implicit integrator reads the residual's tangent.
    let tangents = match settings.integrator.method {
        Method::Hht { .. } => Tangents::Residual,
        _ => Tangents::None,
    };
    let mut loaded = load(&a.common.mechanism, tangents)?;
    apply_sets(&mut loaded, &a.common.set)?;
    let system = loaded.system.as_ref();
    let columns = 1 + 3 * system.info().n() + system.info().m() + 5;
    check_csv_size(&a.common, "trajectory.csv", columns)?;
    let (independent, guess) = initial_values(system, &a.common)?;
    let options = SimulationOptions {
        t_end: a.common.t_end,
        output_rate: a.common.samples_per_second,
        integrator: settings.integrator,
        stabilization: settings.stabilization,
        assembly: AssemblyOptions::default(),
        ..SimulationOptions::default()
    };
    Simulator::check(system, &options)?;
    Ok(Prepared {
        loaded,
        independent,
        guess,
        options,
    })
}

/// The run itself: assemble, integrate, write.
fn simulate(
    a: &SimulateArgs,
    settings: &Settings,
    prepared: Prepared,
    out: &mut RunDir,
) -> Result<(), Failure> {
    let Prepared {
        mut loaded,
        independent,
        guess,
        options,
    } = prepared;
    let system = loaded.system.as_ref();
    let assembly = options.assembly;
    let start = assemble_from(system, 0.0, &independent, &guess, &assembly).at("assembly")?;
    check_assembled(&loaded, &start.q).at("assembly")?;
    let options = SimulationOptions {
        initial: InitialState::Consistent {
            q: start.q.clone(),
            qd: start.qd.clone(),
        },
        ..options
    };
    // Its refusals are checked already (`prepare`): what is left is the first solve at
    // the assembled state.
    let mut sim = Simulator::new(system, &options).at("integration")?;
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
    let result = write_results(
        system,
        &trajectory,
        failure,
        &settings.run,
        (out, &a.common),
        &loaded.key,
    );
    loaded.source.clear();
    result
}

/// Writes trajectory.csv, the figures and summary.json (last, listing the others) of a run
/// that stopped with `failure` (or completed), and prints the summary. Files that cannot
/// all be written are a failure in [`OUTPUT`] that replaces nothing (the previous results
/// stay: [`owning_folder`]).
fn write_results(
    system: &dyn System,
    trajectory: &Trajectory,
    failure: Option<Error>,
    settings: &RunSettings,
    (out, common): (&mut RunDir, &CommonArgs),
    key: &str,
) -> Result<(), Failure> {
    let mut params = vec![0.0; system.info().parameters.len()];
    system.parameter_values(&mut params);
    let mut summary = Summary::new(trajectory, &params, settings).at(OUTPUT)?;
    if let Err(written) = write_data(system, trajectory, out, common, key) {
        // The run's own error first, when it stopped; then why nothing was replaced.
        let error = match failure {
            Some(e) => left_as_it_was(e.into(), Some(written), out.dir()),
            None => written.into(),
        };
        return Err(Failure {
            stage: OUTPUT,
            error: Box::new(error),
            summarized: false,
        });
    }
    if let Some(e) = &failure {
        summary.outcome.failed_in("integration", e);
    }
    summary.outcome.files = out.names();
    write_summary(&out.file(SUMMARY_FILE), &summary).at(OUTPUT)?;
    let summarized = |stage, error| Failure {
        stage,
        error,
        summarized: true,
    };
    let text = summary_text(key, system, &summary, &out.wrote());
    print(&text).map_err(|e| summarized(OUTPUT, Box::new(e)))?;
    match failure {
        // The samples up to the failure are written; the run still failed.
        Some(e) => Err(summarized(
            "integration",
            Box::new(CliError::Stopped {
                t: summary.outcome.t_last,
                dir: out.dir().display().to_string(),
                error: e,
            }),
        )),
        None => Ok(()),
    }
}

/// trajectory.csv and, with two samples or more, the figures `--figures` asks for.
fn write_data(
    system: &dyn System,
    trajectory: &Trajectory,
    out: &mut RunDir,
    common: &CommonArgs,
    key: &str,
) -> Result<(), OutputError> {
    let csv = out.file("trajectory.csv");
    write_trajectory_csv(&csv, trajectory)?;
    out.wrote_data(csv);
    let figures = common.figures.resolve(system.info().n());
    if trajectory.len() >= 2 && figures != Figures::None {
        let res = residuals(system, trajectory);
        let names = figure_names(key, system);
        let written = plot_run(out.staging(), trajectory, None, Some(&res), figures, &names)?;
        out.wrote_figures(written);
    }
    let drawing = write_drawing(system, common, out.staging(), trajectory.len(), |i| {
        let s = trajectory.sample(i);
        (s.t, s.q)
    })?;
    out.wrote_figures(drawing);
    Ok(())
}
