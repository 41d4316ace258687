//! `mechanism simulate ROBOT.mech` of a floating-base declaration (a root link with
//! `joint = floating(..)`, e.g. from `mechanism import ROBOT.urdf --floating`): the
//! declaration interpreted ([`InterpretedFloating`]), `--set` and `--init` applied by the
//! configuration's and the velocities' names, fixed RK4 steps with the quaternion projected
//! back onto its unit norm ([`simulate_interpreted_floating`], the step `simulate_floating`
//! takes by default), then trajectory.csv (t, q by `CONFIGURATION`, v by `VELOCITIES`),
//! summary.json with the energy and momentum checks, and the figures.
//!
//! `--init` takes a configuration entry (`root_joint_qw=1`, `FL_HFE=0.3`), a velocity
//! (`root_joint_wz=2`) or a joint's rate as `der(FL_HFE)=1`; the root's quaternion after
//! them must be unit within 1e-9 (one line, exit 1, nothing written otherwise).

use std::path::Path;
use std::time::Instant;

use super::CliError;
use super::args::{
    IntegratorArg, SimulateArgs, StabilizationArg, check_repeated, split_assignment,
};
use super::budget::{derivation_budget, derivation_done};
use super::input::read_input;
use super::load::{did_you_mean, file_key, finite_constant, is_file_spec, located};
use super::physical::check_initial_value;
use super::run_dir::{At, Failure, Known, OUTPUT, RunDir, output_folder, owning_folder};
use super::stdio::print;
use super::validate::{check_csv_size, check_integrator, check_span};
use mechanism::output::summary::NamedValues;
use mechanism::output::{
    Conservation, Figures, FloatingInitialState, FloatingSummary, Outcome, SUMMARY_FILE, Unit,
    plot_overview, write_floating_summary,
};
use mechanism::{Error, InterpretedFloating, QUATERNION_NORM_TOLERANCE};

/// The step when `--step` is not given (s), as for the other fixed-step runs.
const DEFAULT_STEP: f64 = 1e-3;

/// A floating-base declaration loaded from its file.
pub struct LoadedFloating {
    robot: InterpretedFloating,
    key: String,
}

/// The floating-base declaration `spec` names, or `None` when it is a built-in name, a
/// file that does not parse (the ordinary route reports that) or a declaration without a
/// floating root.
///
/// # Errors
/// An unreadable file; a derivation error, located in the file.
pub fn load(spec: &str) -> Result<Option<LoadedFloating>, CliError> {
    if !is_file_spec(spec) {
        return Ok(None);
    }
    let source = read_input(Path::new(spec)).map_err(CliError::Mechanism)?;
    let Ok(model) = mechanism_codegen::parse_model_str_with(&source, derivation_budget()?) else {
        derivation_done();
        return Ok(None);
    };
    if model.floating_root().is_none() {
        derivation_done();
        return Ok(None);
    }
    let robot = InterpretedFloating::from_model(model);
    derivation_done();
    let robot = robot.map_err(|e| CliError::Mechanism(located(spec, &e)))?;
    Ok(Some(LoadedFloating {
        robot,
        key: file_key(Path::new(spec)),
    }))
}

/// Refuses `command` (`linearize`, `inverse`) for a floating-base declaration `spec` with
/// one line: both are written for q' = dq/dt. Anything else passes (the command's own
/// loading reports a bad file).
///
/// # Errors
/// The refusal.
pub fn refuse(spec: &str, command: &str) -> Result<(), CliError> {
    if !is_file_spec(spec) {
        return Ok(());
    }
    let Ok(source) = read_input(Path::new(spec)) else {
        return Ok(());
    };
    let Ok(model) = mechanism_codegen::parse_model_str(&source) else {
        return Ok(());
    };
    if model.floating_root().is_none() {
        return Ok(());
    }
    Err(CliError::Mechanism(format!(
        "{spec}: `{}` has a floating base (q has {} entries, v {}), which `mechanism \
         {command}` does not take (it is written for q' = dq/dt); `mechanism simulate` and \
         `mechanism equations` do",
        model.name,
        model.configuration_size(),
        model.coordinates.len()
    )))
}

/// A run checked and ready to start.
struct Prepared {
    robot: InterpretedFloating,
    key: String,
    q0: Vec<f64>,
    v0: Vec<f64>,
    h: f64,
    every: usize,
}

/// Runs `simulate` of the floating-base `loaded` with `a`: every refusal first, with the
/// output folder untouched, then the run in its claimed folder.
pub fn run(a: &SimulateArgs, loaded: LoadedFloating) -> Result<(), CliError> {
    let prepared = prepare(a, loaded)?;
    let dir = output_folder(&a.common, &prepared.key);
    let known = Known {
        mechanism: prepared.robot.name().to_string(),
        parameters: parameters(&prepared.robot),
    };
    let step = prepared.h;
    let run = |out: &mut RunDir, _: &mut Known| simulate(a, prepared, out);
    owning_folder(&dir, "trajectory.csv", known, run, |known, failure, out| {
        let summary = FloatingSummary {
            mechanism: known.mechanism,
            parameters: known.parameters,
            initial_state: FloatingInitialState::default(),
            integrator: "rk4".into(),
            step,
            steps: 0,
            rhs_evaluations: 0,
            wall_time_s: 0.0,
            conservation: Conservation::default(),
            outcome: failed(failure.stage, &failure.error, out.names()),
        };
        write_floating_summary(&out.file(SUMMARY_FILE), &summary)
    })
}

fn failed(stage: &str, error: &dyn std::fmt::Display, files: Vec<String>) -> Outcome {
    let mut outcome = Outcome {
        t_last: f64::NAN,
        files,
        ..Outcome::default()
    };
    outcome.failed_in(stage, error);
    outcome
}

fn parameters(robot: &InterpretedFloating) -> NamedValues {
    NamedValues::zip(robot.parameter_names(), robot.parameter_values()).unwrap_or_default()
}

/// Everything that refuses a run before it starts: the flags a floating base cannot take,
/// the span, `--set`, `--init` (the quaternion unit) and the output's size.
fn prepare(a: &SimulateArgs, loaded: LoadedFloating) -> Result<Prepared, CliError> {
    check_span(&a.common)?;
    check_integrator(a)?;
    if matches!(a.integrator, IntegratorArg::Dopri5 | IntegratorArg::Hht)
        || !matches!(a.stabilization, StabilizationArg::Projection)
    {
        return Err(CliError::Argument(format!(
            "`{}` has a floating base, which steps by fixed RK4 (--step, default 1e-3 s) with \
             its quaternion projected back onto unit norm: --integrator rk4 (or none) and \
             --stabilization projection (or none given)",
            loaded.robot.name()
        )));
    }
    let LoadedFloating { mut robot, key } = loaded;
    apply_sets(&mut robot, &a.common.set)?;
    let (q0, v0) = initial_state(&robot, &a.common.init)?;
    let columns = 1 + robot.nq() + robot.nv();
    check_csv_size(&a.common, "trajectory.csv", columns)?;
    let h = a.step.unwrap_or(DEFAULT_STEP).min(a.common.t_end);
    // A sample every `every` steps: the steps per sampling interval, at least one.
    let every = (1.0 / (a.common.samples_per_second * h)).round().max(1.0) as usize;
    let steps = a.common.t_end / h;
    if steps > mechanism::MAX_OUTPUT_SAMPLES as f64 * 100.0 {
        return Err(CliError::Argument(format!(
            "--step {h:e} over --t-end {} asks for {steps:e} steps: raise --step",
            a.common.t_end
        )));
    }
    Ok(Prepared {
        robot,
        key,
        q0,
        v0,
        h,
        every,
    })
}

/// Applies every `--set NAME=VALUE`; a value outside the declared range is refused.
fn apply_sets(robot: &mut InterpretedFloating, sets: &[String]) -> Result<(), CliError> {
    check_repeated("--set", sets)?;
    for s in sets {
        let (name, value) = split_assignment(s)
            .ok_or_else(|| CliError::Argument(format!("--set takes PARAM=VALUE, got `{s}`")))?;
        let names = robot.parameter_names();
        let index = names.iter().position(|p| p == name).ok_or_else(|| {
            CliError::Argument(format!(
                "--set: unknown parameter `{name}`{}; parameters: {}",
                did_you_mean(name, names),
                names.join(", ")
            ))
        })?;
        let v =
            finite_constant(value).map_err(|e| CliError::Argument(format!("--set {name}: {e}")))?;
        let range = robot.parameter_ranges()[index];
        robot.set_parameter(index, v).map_err(|_| {
            CliError::Argument(format!(
                "--set {name}={value}: `{name}` must be {} (its declaration says `{}`), got {v}",
                range.describe(),
                range.keyword()
            ))
        })?;
    }
    Ok(())
}

/// q0 (the neutral configuration) and v0 (zero) after every `--init`, the quaternion
/// checked unit within [`QUATERNION_NORM_TOLERANCE`].
fn initial_state(
    robot: &InterpretedFloating,
    init: &[String],
) -> Result<(Vec<f64>, Vec<f64>), CliError> {
    check_repeated("--init", init)?;
    let mut q = robot.neutral();
    let mut v = vec![0.0; robot.nv()];
    let (configuration, velocities) = (robot.configuration(), robot.velocities());
    for s in init {
        let (lhs, value) = split_assignment(s).ok_or_else(|| {
            CliError::Argument(format!(
                "--init takes NAME=VALUE or der(JOINT)=VALUE, got `{s}`"
            ))
        })?;
        let rate = lhs.strip_prefix("der(").and_then(|r| r.strip_suffix(')'));
        let target = match rate {
            // A joint's rate: its velocity entry (the root's rates are its velocities).
            Some(joint) => {
                (velocities.iter().skip(6).position(|n| n == joint.trim())).map(|k| (&mut v, k + 6))
            }
            None => match configuration.iter().position(|n| n == lhs) {
                Some(k) => Some((&mut q, k)),
                None => velocities
                    .iter()
                    .position(|n| n == lhs)
                    .map(|k| (&mut v, k)),
            },
        };
        let Some((values, k)) = target else {
            let names: Vec<String> = configuration.iter().chain(velocities).cloned().collect();
            let joints = &velocities[6..];
            return Err(CliError::Argument(format!(
                "--init: unknown entry `{lhs}`{}; q: {}; v: {}{}",
                did_you_mean(rate.unwrap_or(lhs).trim(), &names),
                configuration.join(", "),
                velocities.join(", "),
                match joints.first() {
                    Some(j) => format!(" (or der(JOINT), e.g. der({j}))"),
                    None => String::new(),
                }
            )));
        };
        let x =
            finite_constant(value).map_err(|e| CliError::Argument(format!("--init {lhs}: {e}")))?;
        check_initial_value(lhs, x, values.len() == robot.nv())?;
        values[k] = x;
    }
    let norm = (3..7).map(|k| q[k] * q[k]).sum::<f64>().sqrt();
    if (norm - 1.0).abs().is_nan() || (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        let error = Error::QuaternionNotUnit {
            quaternion: [q[3], q[4], q[5], q[6]],
            norm,
        };
        return Err(CliError::Argument(format!(
            "--init: {error} ({})",
            configuration[3..7].join(", ")
        )));
    }
    Ok((q, v))
}

/// The samples of a run and the conservation checks over them.
struct Record {
    t: Vec<f64>,
    rows: Vec<f64>,
    conservation: Conservation,
    start: Option<([f64; 3], [f64; 3])>,
    weight: [f64; 3],
    mass: Vec<f64>,
}

impl Record {
    fn sample(&mut self, robot: &InterpretedFloating, t: f64, q: &[f64], v: &[f64]) {
        self.t.push(t);
        self.rows.push(t);
        self.rows.extend_from_slice(q);
        self.rows.extend_from_slice(v);
        let energy = robot.kinetic_energy(q, v) + robot.potential_energy(q);
        let m = robot.momentum(q, v, &mut self.mass);
        let c = &mut self.conservation;
        let (p0, l0) = *self.start.get_or_insert((m.linear, m.angular));
        if self.t.len() == 1 {
            c.energy_initial = energy;
        }
        let dist = |a: [f64; 3], b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>();
        let p_expected = [0, 1, 2].map(|i| p0[i] + self.weight[i] * t);
        let unit = (3..7).map(|k| q[k] * q[k]).sum::<f64>().sqrt();
        c.max_energy_error = c.max_energy_error.max((energy - c.energy_initial).abs());
        c.max_linear_momentum_error =
            (c.max_linear_momentum_error).max(dist(m.linear, p_expected).sqrt());
        c.max_angular_momentum_error =
            (c.max_angular_momentum_error).max(dist(m.angular, l0).sqrt());
        c.max_quaternion_norm_error = c.max_quaternion_norm_error.max((unit - 1.0).abs());
    }
}

/// The run itself: integrate, then write.
fn simulate(a: &SimulateArgs, p: Prepared, out: &mut RunDir) -> Result<(), Failure> {
    let Prepared {
        robot,
        q0,
        v0,
        h,
        every,
        ..
    } = p;
    let (nq, nv) = (robot.nq(), robot.nv());
    let mut tau = vec![0.0; nv];
    robot.generalized_forces(0.0, &q0, &v0, &mut tau);
    let mut record = Record {
        t: Vec::new(),
        rows: Vec::new(),
        conservation: Conservation {
            efforts_declared: tau.iter().any(|x| *x != 0.0),
            ..Conservation::default()
        },
        start: None,
        weight: robot.weight(&q0),
        mass: vec![0.0; nv * nv],
    };
    let started = Instant::now();
    let result = mechanism::simulate_interpreted_floating(
        &robot,
        (&q0, &v0),
        (a.common.t_end, h, every),
        |t, q, v| record.sample(&robot, t, q, v),
    );
    let wall = started.elapsed().as_secs_f64();
    let t_last = record.t.last().copied().unwrap_or(f64::NAN);
    let steps = (t_last / h).round() as usize;
    let mut header = vec!["t".to_string()];
    header.extend(robot.configuration().iter().cloned());
    header.extend(robot.velocities().iter().cloned());
    write_data(a, &robot, &record, &header, out).at(OUTPUT)?;
    let first = record.rows.get(1..1 + nq + nv).unwrap_or_default();
    let mut outcome = Outcome::completed(t_last);
    if let Err(e) = &result {
        outcome.failed_in("integration", e);
    }
    outcome.files = out.names();
    let summary = FloatingSummary {
        mechanism: robot.name().to_string(),
        parameters: parameters(&robot),
        initial_state: FloatingInitialState {
            q: NamedValues::zip(robot.configuration(), first.get(..nq).unwrap_or_default())
                .unwrap_or_default(),
            v: NamedValues::zip(robot.velocities(), first.get(nq..).unwrap_or_default())
                .unwrap_or_default(),
        },
        integrator: "rk4".into(),
        step: h,
        steps,
        rhs_evaluations: 4 * steps,
        wall_time_s: wall,
        conservation: record.conservation.clone(),
        outcome,
    };
    write_floating_summary(&out.file(SUMMARY_FILE), &summary).at(OUTPUT)?;
    let c = &summary.conservation;
    let text = format!(
        "{}: floating base, rk4 with the quaternion projected, step {h} s, {steps} steps to t = {t_last} s\n\
         energy T + Pi = {:.9e} J, largest change {:.3e} J; momentum: p - m g t {:.3e} kg m/s, \
         L about the centre of mass {:.3e} kg m^2/s; |quaternion| - 1 at most {:.1e}\n{}\n",
        robot.name(),
        c.energy_initial,
        c.max_energy_error,
        c.max_linear_momentum_error,
        c.max_angular_momentum_error,
        c.max_quaternion_norm_error,
        out.wrote()
    );
    let summarized = |stage, error| Failure {
        stage,
        error,
        summarized: true,
    };
    print(&text).map_err(|e| summarized(OUTPUT, Box::new(e)))?;
    match result {
        Ok(()) => Ok(()),
        Err(error) => Err(summarized(
            "integration",
            Box::new(CliError::Stopped {
                t: t_last,
                dir: out.dir().display().to_string(),
                error,
            }),
        )),
    }
}

/// trajectory.csv and, with two samples or more, the overview figures of q and of v.
fn write_data(
    a: &SimulateArgs,
    robot: &InterpretedFloating,
    record: &Record,
    header: &[String],
    out: &mut RunDir,
) -> Result<(), mechanism::output::OutputError> {
    let csv = out.file("trajectory.csv");
    let width = header.len();
    mechanism::output::csv::write_table(&csv, header, record.rows.chunks_exact(width))?;
    out.wrote_data(csv);
    let figures = a.common.figures.resolve(robot.nv());
    if record.t.len() < 2 || figures == Figures::None {
        return Ok(());
    }
    let (nq, nv) = (robot.nq(), robot.nv());
    let series = |range: std::ops::Range<usize>| -> Vec<Vec<f64>> {
        range
            .map(|k| record.rows.chunks_exact(width).map(|r| r[1 + k]).collect())
            .collect()
    };
    // Positions and linear velocities in m and m/s, the quaternion without unit, the
    // angular velocities in rad/s, the joints by their names.
    let units = |names: &[String], middle: std::ops::Range<usize>, unit: Unit| -> Vec<Unit> {
        (names.iter().enumerate())
            .map(|(k, n)| match k {
                k if k < 3 => Unit::Length,
                k if middle.contains(&k) => unit,
                _ => Unit::guess(n),
            })
            .collect()
    };
    let mut written = Vec::new();
    let configuration = robot.configuration();
    written.extend(plot_overview(
        &out.staging().join("configuration"),
        configuration,
        &units(configuration, 3..7, Unit::Unknown),
        &record.t,
        &series(0..nq),
    )?);
    let velocities = robot.velocities();
    written.extend(plot_overview(
        &out.staging().join("velocities"),
        velocities,
        &units(velocities, 3..6, Unit::Angle),
        &record.t,
        &series(nq..nq + nv),
    )?);
    out.wrote_figures(written);
    Ok(())
}
