//! The runs of a model, each as the command-line tool runs it: `simulate` (assembly from
//! the independent coordinates, then the integrator), `inverse` (a prescribed motion's
//! driving forces) and `linearize` (about an equilibrium or a steady motion), and `sweep`
//! (many simulations with other parameters, in parallel). Each runs without the GIL and
//! answers with a result object of `mechanism._results` holding numpy arrays.

use std::collections::HashMap;

use mechanism::{
    AssemblyOptions, Independent, InitialState, IntegratorOptions, Interpreted, Kinematic, Method,
    SimulationOptions, Simulator, Stabilization, SteadyOptions, System, assemble_from,
    inverse_dynamics_from, linearize_steady, parse_drive, sample_times,
};
use numpy::IntoPyArray;
use numpy::ndarray::Array1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::batch::matrix;
use crate::errors::{did_you_mean, input, solver};
use crate::model::Model;

/// Largest t_end (s), as the command-line tool's `--t-end`.
const MAX_T_END: f64 = 1e9;
/// Largest |value| of an initial position or rate, as `--init`'s.
const MAX_INITIAL_VALUE: f64 = 1e9;
/// HHT's and RK4's step when none is given (s), as the command-line tool's.
const DEFAULT_STEP: f64 = 1e-3;
/// Baumgarte's gains alpha = beta (1/s), as `--stabilization baumgarte`.
const BAUMGARTE_GAIN: f64 = 10.0;

/// How a simulation integrates: `Model.simulate`'s keywords.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub t_end: f64,
    pub samples_per_second: f64,
    pub integrator: String,
    pub rtol: f64,
    pub atol: f64,
    pub step: Option<f64>,
    pub stabilization: String,
}

impl RunOptions {
    /// The library's options, the options checked as the command-line tool checks them.
    fn settings(&self) -> PyResult<(IntegratorOptions, Stabilization)> {
        let ranges = [
            (
                "t_end",
                self.t_end,
                "> 0 s and at most 1e9 s",
                self.t_end > 0.0 && self.t_end <= MAX_T_END,
            ),
            (
                "samples_per_second",
                self.samples_per_second,
                "> 0 and finite",
                self.samples_per_second > 0.0 && self.samples_per_second.is_finite(),
            ),
            (
                "rtol",
                self.rtol,
                "finite, at least 1e-15 and below 1",
                self.rtol >= 1e-15 && self.rtol < 1.0,
            ),
            (
                "atol",
                self.atol,
                "finite and > 0",
                self.atol > 0.0 && self.atol.is_finite(),
            ),
        ];
        for (name, value, allowed, ok) in ranges {
            if !ok {
                return Err(input(format!("{name} must be {allowed}, got {value}")));
            }
        }
        if let Some(h) = self.step
            && !(h > 0.0 && h <= self.t_end)
        {
            return Err(input(format!(
                "step must be > 0 s and at most t_end, got {h}"
            )));
        }
        let h = self.step.unwrap_or(DEFAULT_STEP);
        let (method, adaptive) = match self.integrator.as_str() {
            "rk4" => (Method::Rk4 { h }, false),
            "dopri5" => (Method::Dopri5, true),
            "dop853" => (Method::Dop853, true),
            "hht" => (Method::Hht { h, alpha: -0.05 }, false),
            other => {
                return Err(input(format!(
                    "integrator `{other}`: use one of rk4, dopri5, dop853, hht"
                )));
            }
        };
        let stabilization = match self.stabilization.as_str() {
            "projection" => Stabilization::Projection,
            "baumgarte" => Stabilization::Baumgarte {
                alpha: BAUMGARTE_GAIN,
                beta: BAUMGARTE_GAIN,
            },
            "none" => Stabilization::None,
            other => {
                return Err(input(format!(
                    "stabilization `{other}`: use one of projection, baumgarte, none"
                )));
            }
        };
        let integrator = IntegratorOptions {
            method,
            rtol: self.rtol,
            atol: self.atol,
            h_initial: if adaptive { self.step } else { None },
            ..IntegratorOptions::default()
        };
        Ok((integrator, stabilization))
    }

    /// Whether the integrator reads the residual's tangent.
    fn implicit(&self) -> bool {
        self.integrator == "hht"
    }
}

/// The independent coordinates and the guesses with `init` in place: `"x": v` sets a
/// position (an independent one's value, or a dependent one's guess, which picks the
/// assembly branch), `"der(x)": v` an independent coordinate's rate.
pub fn initial_values(
    system: &dyn Kinematic,
    init: &[(String, f64)],
) -> PyResult<(Vec<Independent>, Vec<f64>)> {
    let info = system.info();
    let mut independent = info.independent.clone();
    let mut guess = info.initial_guess.clone();
    for (lhs, v) in init {
        let (name, rate) = match lhs.strip_prefix("der(").and_then(|r| r.strip_suffix(')')) {
            Some(inner) => (inner.trim(), true),
            None => (lhs.as_str(), false),
        };
        let k = info.coordinate_index(name).ok_or_else(|| {
            input(format!(
                "init: unknown coordinate `{name}`{}; coordinates: {}",
                did_you_mean(name, &info.coordinates),
                info.coordinates.join(", ")
            ))
        })?;
        if !v.is_finite() || v.abs() > MAX_INITIAL_VALUE {
            return Err(input(format!(
                "init {lhs}: the value must be finite with |value| at most 1e9, got {v}"
            )));
        }
        match (independent.iter_mut().find(|i| i.coordinate == k), rate) {
            (Some(ind), false) => ind.position = *v,
            (Some(ind), true) => ind.velocity = *v,
            (None, false) => guess[k] = *v,
            (None, true) => {
                let names: Vec<&str> = independent
                    .iter()
                    .map(|i| info.coordinates[i.coordinate].as_str())
                    .collect();
                return Err(input(format!(
                    "init: der({name}) follows from the constraints; rates can be set for the \
                     independent coordinates ({})",
                    names.join(", ")
                )));
            }
        }
    }
    Ok((independent, guess))
}

/// A finished simulation's samples, row-major.
pub struct Run {
    n: usize,
    m: usize,
    t: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    lambda: Vec<f64>,
    kinetic: Vec<f64>,
    potential: Vec<f64>,
    work: Vec<f64>,
    constraint_error: Vec<f64>,
    velocity_constraint_error: Vec<f64>,
    q0: Vec<f64>,
    qd0: Vec<f64>,
    stats: mechanism::SolverStats,
    passages: usize,
}

/// Assembles `system` from its independent coordinates (with `init`) and integrates it as
/// `options` say: the command-line tool's `simulate`, without its files.
pub fn simulate_system(
    system: &Interpreted,
    options: &RunOptions,
    init: &[(String, f64)],
) -> PyResult<Run> {
    let (integrator, stabilization) = options.settings()?;
    let (independent, guess) = initial_values(system, init)?;
    let assembly = AssemblyOptions::default();
    let start = assemble_from(system, 0.0, &independent, &guess, &assembly).map_err(solver)?;
    let sim_options = SimulationOptions {
        t_end: options.t_end,
        output_rate: options.samples_per_second,
        integrator,
        stabilization,
        initial: InitialState::Consistent {
            q: start.q.clone(),
            qd: start.qd.clone(),
        },
        assembly,
        ..SimulationOptions::default()
    };
    let mut sim = Simulator::new(system, &sim_options).map_err(solver)?;
    loop {
        match sim.step() {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                let t = sim.time();
                return Err(crate::errors::kind(&e)(format!(
                    "{e} (the run stopped at t = {t} s)"
                )));
            }
        }
    }
    let trajectory = sim.finish(None).trajectory;
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    let mut run = Run {
        n,
        m,
        t: Vec::new(),
        q: Vec::new(),
        qd: Vec::new(),
        qdd: Vec::new(),
        lambda: Vec::new(),
        kinetic: Vec::new(),
        potential: Vec::new(),
        work: Vec::new(),
        constraint_error: Vec::new(),
        velocity_constraint_error: Vec::new(),
        q0: start.q,
        qd0: start.qd,
        stats: trajectory.stats,
        passages: trajectory.singular_passages.len(),
    };
    for s in trajectory.samples() {
        run.t.push(s.t);
        run.q.extend_from_slice(s.q);
        run.qd.extend_from_slice(s.qd);
        run.qdd.extend_from_slice(s.qdd);
        run.lambda.extend_from_slice(s.lambda);
        run.kinetic.push(s.kinetic);
        run.potential.push(s.potential);
        run.work.push(s.work);
        run.constraint_error.push(s.constraint_error);
        run.velocity_constraint_error
            .push(s.velocity_constraint_error);
    }
    Ok(run)
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |a, x| {
        if x.is_nan() || a.is_nan() {
            f64::NAN
        } else {
            a.max(x.abs())
        }
    })
}

fn vector(py: Python<'_>, v: Vec<f64>) -> Py<PyAny> {
    Array1::from(v).into_pyarray(py).into_any().unbind()
}

/// The `mechanism._results` object `class` made from `fields`.
fn result(py: Python<'_>, class: &str, fields: Bound<'_, PyDict>) -> PyResult<Py<PyAny>> {
    let class = py.import("mechanism._results")?.getattr(class)?;
    Ok(class.call((), Some(&fields))?.unbind())
}

/// `run` of `model` with the parameter values `parameters` as a `Trajectory`.
pub fn trajectory(
    py: Python<'_>,
    model: &Model,
    parameters: &[f64],
    run: Run,
) -> PyResult<Py<PyAny>> {
    let info = model.system.info();
    let d = PyDict::new(py);
    let rows = run.t.len();
    let energy: Vec<f64> = (0..rows)
        .map(|i| run.kinetic[i] + run.potential[i] - run.work[i])
        .collect();
    let drift = energy
        .iter()
        .map(|e| e - energy.first().copied().unwrap_or(0.0))
        .collect::<Vec<_>>();
    d.set_item("mechanism", &info.name)?;
    d.set_item("coordinates", info.coordinates.clone())?;
    let named: HashMap<&str, f64> = info
        .parameters
        .iter()
        .map(String::as_str)
        .zip(parameters.iter().copied())
        .collect();
    d.set_item("parameters", named)?;
    d.set_item("max_constraint_error", max_abs(&run.constraint_error))?;
    d.set_item(
        "max_velocity_constraint_error",
        max_abs(&run.velocity_constraint_error),
    )?;
    d.set_item("max_energy_balance_error", max_abs(&drift))?;
    d.set_item("energy_depends_on_time", info.energy_depends_on_time)?;
    d.set_item("steps", run.stats.steps)?;
    d.set_item("rejected_steps", run.stats.rejected_steps)?;
    d.set_item("rhs_evaluations", run.stats.rhs_evaluations)?;
    d.set_item("wall_time_s", run.stats.wall_time_s)?;
    d.set_item("singular_passages", run.passages)?;
    d.set_item("q0", vector(py, run.q0))?;
    d.set_item("qd0", vector(py, run.qd0))?;
    d.set_item("t", vector(py, run.t))?;
    d.set_item("q", matrix(py, rows, run.n, run.q)?)?;
    d.set_item("qd", matrix(py, rows, run.n, run.qd)?)?;
    d.set_item("qdd", matrix(py, rows, run.n, run.qdd)?)?;
    d.set_item("multipliers", matrix(py, rows, run.m, run.lambda)?)?;
    d.set_item("kinetic", vector(py, run.kinetic))?;
    d.set_item("potential", vector(py, run.potential))?;
    d.set_item("work", vector(py, run.work))?;
    d.set_item("constraint_error", vector(py, run.constraint_error))?;
    d.set_item(
        "velocity_constraint_error",
        vector(py, run.velocity_constraint_error),
    )?;
    result(py, "Trajectory", d)
}

/// `Model.simulate`.
pub fn simulate(
    py: Python<'_>,
    model: &Model,
    options: RunOptions,
    set: &[(String, f64)],
    init: &[(String, f64)],
) -> PyResult<Py<PyAny>> {
    let (run, values) = py.detach(|| {
        let system = model.system_for(options.implicit(), set)?;
        let mut values = vec![0.0; system.info().parameters.len()];
        system.parameter_values(&mut values);
        simulate_system(&system, &options, init).map(|r| (r, values))
    })?;
    trajectory(py, model, &values, run)
}

/// `mechanism.sweep`: one simulation per parameter set, in parallel; the results in the
/// order of `sets`.
pub fn sweep(
    py: Python<'_>,
    model: &Model,
    sets: Vec<Vec<(String, f64)>>,
    options: RunOptions,
    init: &[(String, f64)],
    threads: Option<usize>,
) -> PyResult<Vec<Py<PyAny>>> {
    options.settings()?;
    let runs: Vec<PyResult<(Run, Vec<f64>)>> = py.detach(|| {
        let one = |set: &Vec<(String, f64)>| {
            let system = model.system_for(options.implicit(), set)?;
            let mut values = vec![0.0; system.info().parameters.len()];
            system.parameter_values(&mut values);
            simulate_system(&system, &options, init).map(|r| (r, values))
        };
        match threads {
            Some(k) => match rayon::ThreadPoolBuilder::new()
                .num_threads(k.max(1))
                .build()
            {
                Ok(pool) => pool.install(|| sets.par_iter().map(one).collect()),
                Err(e) => vec![Err(input(format!("threads: {e}")))],
            },
            None => sets.par_iter().map(one).collect(),
        }
    });
    let mut out = Vec::with_capacity(runs.len());
    for (i, r) in runs.into_iter().enumerate() {
        match r {
            Ok((run, values)) => out.push(trajectory(py, model, &values, run)?),
            Err(e) => {
                let message = format!("parameter set {i}: {}", e.value(py));
                return Err(PyErr::from_type(e.get_type(py), message));
            }
        }
    }
    Ok(out)
}

/// `Model.inverse`: the driving forces along the prescribed motions `drives`.
pub fn inverse(
    py: Python<'_>,
    model: &Model,
    drives: Vec<String>,
    t_end: f64,
    samples_per_second: f64,
    set: &[(String, f64)],
    init: &[(String, f64)],
) -> PyResult<Py<PyAny>> {
    let span = RunOptions {
        t_end,
        samples_per_second,
        integrator: "dop853".into(),
        rtol: 1e-10,
        atol: 1e-10,
        step: None,
        stabilization: "projection".into(),
    };
    span.settings()?;
    let solved = py.detach(|| {
        let system = model.system_for(false, set)?;
        let info = system.info();
        let mut parsed = Vec::with_capacity(drives.len());
        for text in &drives {
            parsed.push(parse_drive(&system, text).map_err(|e| input(format!("drive: {e}")))?);
        }
        if let Some((lhs, _)) = init.iter().find(|(l, _)| l.starts_with("der(")) {
            return Err(input(format!(
                "init {lhs}: in inverse the rates follow from the drives; init gives guesses of \
                 positions"
            )));
        }
        let (independent, mut guess) = initial_values(&system, init)?;
        for i in independent {
            guess[i.coordinate] = i.position;
        }
        let times = sample_times(0.0, t_end, samples_per_second);
        let r = inverse_dynamics_from(&system, parsed, &guess, &times, &AssemblyOptions::default())
            .map_err(solver)?;
        let driven: Vec<String> = r
            .driven
            .iter()
            .map(|&k| info.coordinates[k].clone())
            .collect();
        Ok((r, driven, info.n(), info.m()))
    })?;
    let (r, driven, n, m) = solved;
    let rows = r.samples.len();
    let d = PyDict::new(py);
    let flat = |f: &dyn Fn(&mechanism::InverseSample) -> &[f64]| -> Vec<f64> {
        r.samples
            .iter()
            .flat_map(|s| f(s).iter().copied())
            .collect()
    };
    d.set_item("coordinates", model.system.info().coordinates.clone())?;
    d.set_item("driven", driven.clone())?;
    d.set_item("t", vector(py, r.samples.iter().map(|s| s.t).collect()))?;
    d.set_item("q", matrix(py, rows, n, flat(&|s| &s.q))?)?;
    d.set_item("qd", matrix(py, rows, n, flat(&|s| &s.qd))?)?;
    d.set_item("qdd", matrix(py, rows, n, flat(&|s| &s.qdd))?)?;
    d.set_item(
        "driving",
        matrix(py, rows, driven.len(), flat(&|s| &s.driving))?,
    )?;
    d.set_item("multipliers", matrix(py, rows, m, flat(&|s| &s.lambda))?)?;
    result(py, "InverseResult", d)
}

/// `Model.linearize`: the declaration built again at the parameter values (so that
/// declared independent values that depend on them follow), with the constraint rows'
/// tangents, assembled and linearised about its steady motion.
pub fn linearize(
    py: Python<'_>,
    model: &Model,
    set: &[(String, f64)],
    init: &[(String, f64)],
) -> PyResult<Py<PyAny>> {
    let named = model.named_values(set)?;
    let (lin, variables) = py.detach(|| {
        let values: Vec<(&str, f64)> = named.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        let parsed = mechanism_codegen::parse_model_str_at(&model.source, &values)
            .map_err(|e| crate::errors::declaration(&model.shown, &e))?;
        let system = Interpreted::for_linearization(parsed)
            .map_err(|e| crate::errors::declaration(&model.shown, &e))?;
        let (independent, guess) = initial_values(&system, init)?;
        let state = assemble_from(
            &system,
            0.0,
            &independent,
            &guess,
            &AssemblyOptions::default(),
        )
        .map_err(solver)?;
        let lin = linearize_steady(&system, 0.0, &state.q, &state.qd, &SteadyOptions::default())
            .map_err(solver)?;
        let variables = lin.variables.clone();
        Ok::<_, PyErr>((lin, variables))
    })?;
    let numpy = py.import("numpy")?;
    let complex = |values: &[nalgebra::Complex<f64>]| -> PyResult<Py<PyAny>> {
        let list: Vec<Bound<'_, PyAny>> = values
            .iter()
            .map(|c| pyo3::types::PyComplex::from_doubles(py, c.re, c.im).into_any())
            .collect();
        Ok(numpy.call_method1("array", (list, "complex128"))?.unbind())
    };
    let k = lin.state.nrows();
    let state: Vec<f64> = (0..k)
        .flat_map(|i| (0..k).map(move |j| (i, j)))
        .map(|(i, j)| lin.state[(i, j)])
        .collect();
    let d = PyDict::new(py);
    d.set_item("variables", variables.clone())?;
    d.set_item("state_matrix", matrix(py, k, k, state)?)?;
    d.set_item("eigenvalues", complex(&lin.eigenvalues)?)?;
    d.set_item(
        "structural_zeros",
        lin.structural
            .iter()
            .map(|&i| variables[i].clone())
            .collect::<Vec<_>>(),
    )?;
    d.set_item("reduced_eigenvalues", complex(&lin.reduced)?)?;
    d.set_item("parameters", named.into_iter().collect::<HashMap<_, _>>())?;
    result(py, "Linearization", d)
}
