//! Forward dynamics: the simulation driver.
//!
//! Integrates the index-3 DAE M q'' + C q' + g + Phi_q^T lambda = tau, Phi(q, t) = 0 as the
//! ODE y' = [q', q'', tau . q'] in y = [q, q', W] (q'' and lambda from the augmented system,
//! [`crate::Dynamics`]; W the work of tau, so that T + Pi - W is constant), with the chosen
//! [`Stabilization`], and records samples at a fixed output rate from the integrator's dense
//! output. Each sample holds q, q', q'', lambda, |Phi|_inf, |Phi_q q' + Phi_t|_inf, T, Pi, W.
//!
//! The step loop ([`Simulator::step`]) allocates nothing: every buffer is created in
//! [`Simulator::new`], and the output trajectory is reserved for all samples up front.

// Comparisons are written `!(x > 0.0)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::fmt;
use std::sync::Arc;
use std::time::Instant;

use crate::algorithms::dynamics::{DEFAULT_CONDITION_LIMIT, Dynamics};
use crate::algorithms::kinematics::{AssemblyOptions, assemble, assemble_from};
use crate::algorithms::mobility::mobility;
use crate::algorithms::stabilization::{Projector, Stabilization};
use crate::error::Error;
use crate::integrators::{
    Dense, Hht, IntegratorOptions, Method, OdeRhs, RungeKutta, Tolerance, explicit_stepper,
    initial_step,
};
use crate::simulation::singular::SingularWatch;
use crate::simulation::trajectory::Trajectory;
use crate::system::{Independent, System};

/// Most output samples one run records (each is a row of 3n + m + 6 numbers).
pub const MAX_OUTPUT_SAMPLES: usize = 10_000_000;
/// Output samples whose storage is reserved before the first step.
const RESERVED_SAMPLES: usize = 1_000_000;

/// Where the simulation starts.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum InitialState {
    /// Assemble from the declared independent coordinates and guesses.
    #[default]
    Declared,
    /// Assemble from these independent coordinates (declared guesses for the rest).
    Independent(Vec<Independent>),
    /// A state the user asserts is consistent (checked: |Phi| and |Phi_q q' + Phi_t| below
    /// 1e-8, then projected when the stabilisation is projection).
    Consistent {
        /// Positions q(t0).
        q: Vec<f64>,
        /// Rates q'(t0).
        qd: Vec<f64>,
    },
}

/// What to do when an event function changes sign.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventAction {
    /// Record the crossing and end the simulation there (last sample at the crossing).
    Stop,
    /// Record the crossing and continue.
    Record,
}

/// An event function g(t, q, q').
pub type EventFn = Arc<dyn Fn(f64, &[f64], &[f64]) -> f64 + Send + Sync>;

/// A user function g(t, q, q') whose sign changes are located to round-off on the dense
/// output of the step in which they occur.
#[derive(Clone)]
pub struct Event {
    /// Name for reports.
    pub name: String,
    /// g(t, q, q'); should not allocate.
    pub g: EventFn,
    /// Stop or record.
    pub action: EventAction,
}

impl Event {
    /// An event called `name` with function `g` and `action`.
    pub fn new(
        name: &str,
        action: EventAction,
        g: impl Fn(f64, &[f64], &[f64]) -> f64 + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.to_string(),
            g: Arc::new(g),
            action,
        }
    }
}

impl fmt::Debug for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Event")
            .field("name", &self.name)
            .field("action", &self.action)
            .finish_non_exhaustive()
    }
}

/// One located sign change of an event function.
#[derive(Clone, Debug, PartialEq)]
pub struct EventHit {
    /// Index of the event in [`SimulationOptions::events`].
    pub event: usize,
    /// Time of the crossing (s).
    pub t: f64,
    /// q at the crossing.
    pub q: Vec<f64>,
    /// q' at the crossing.
    pub qd: Vec<f64>,
}

/// Everything a forward simulation needs besides the system.
#[derive(Clone, Debug)]
pub struct SimulationOptions {
    /// Start time (s).
    pub t_start: f64,
    /// End time (s).
    pub t_end: f64,
    /// Output samples per second (default 100); the end time is always a sample.
    pub output_rate: f64,
    /// Method and step-size control.
    pub integrator: IntegratorOptions,
    /// Constraint stabilisation (default projection).
    pub stabilization: Stabilization,
    /// Initial state.
    pub initial: InitialState,
    /// Newton options for the assembly.
    pub assembly: AssemblyOptions,
    /// Event functions.
    pub events: Vec<Event>,
    /// Condition-estimate limit of the augmented matrix ([`Error::SingularConfiguration`]).
    pub condition_limit: f64,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            t_start: 0.0,
            t_end: 10.0,
            output_rate: 100.0,
            integrator: IntegratorOptions::default(),
            stabilization: Stabilization::default(),
            initial: InitialState::default(),
            assembly: AssemblyOptions::default(),
            events: Vec::new(),
            condition_limit: DEFAULT_CONDITION_LIMIT,
        }
    }
}

/// The result of [`simulate_with_events`].
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The recorded samples and run statistics.
    pub trajectory: Trajectory,
    /// Located event crossings, in time order.
    pub events: Vec<EventHit>,
    /// Index of the event that stopped the run, if any.
    pub stopped_by: Option<usize>,
    /// Why the run stopped before the end time, if it did (the trajectory then holds the
    /// samples up to the failure).
    pub failure: Option<Error>,
}

/// Simulates `system` and returns the recorded trajectory (see the module documentation).
pub fn simulate(system: &dyn System, options: &SimulationOptions) -> Result<Trajectory, Error> {
    Ok(simulate_with_events(system, options)?.trajectory)
}

/// Simulates `system` and returns the trajectory with the located events; any failure is
/// an error (the samples recorded before it are dropped: see [`simulate_recording`]).
pub fn simulate_with_events(
    system: &dyn System,
    options: &SimulationOptions,
) -> Result<Simulation, Error> {
    let simulation = simulate_recording(system, options)?;
    match simulation.failure {
        Some(e) => Err(e),
        None => Ok(simulation),
    }
}

/// Simulates `system`, keeping what was computed when the run stops early: an error is
/// returned only when the run cannot start (assembly, invalid options); a failure during the
/// integration ends the trajectory at the last recorded sample, with the error in
/// [`Simulation::failure`].
pub fn simulate_recording(
    system: &dyn System,
    options: &SimulationOptions,
) -> Result<Simulation, Error> {
    Ok(Simulator::new(system, options)?.run_recording())
}

/// y' = [q', q'', tau . q'] through the augmented system.
struct Rhs<'s> {
    system: &'s dyn System,
    dynamics: &'s mut Dynamics,
    n: usize,
}

impl OdeRhs for Rhs<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let n = self.n;
        let (q, rest) = y.split_at(n);
        let qd = &rest[..n];
        self.dynamics.solve(self.system, t, q, qd)?;
        dy[..n].copy_from_slice(qd);
        dy[n..2 * n].copy_from_slice(self.dynamics.accelerations());
        dy[2 * n] = self.dynamics.power(qd);
        Ok(())
    }
}

enum Stepper {
    Explicit(Box<dyn RungeKutta>),
    Hht {
        hht: Box<Hht>,
        hermite: Dense,
        f0: Vec<f64>,
        f1: Vec<f64>,
        power: f64,
    },
}

/// The forward-dynamics driver, one accepted step at a time ([`Simulator::step`]) or to the
/// end ([`Simulator::run`]).
pub struct Simulator<'a> {
    system: &'a dyn System,
    options: &'a SimulationOptions,
    n: usize,
    t: f64,
    h: f64,
    y: Vec<f64>,
    y_new: Vec<f64>,
    y_dense: Vec<f64>,
    scratch: Vec<f64>,
    g_old: Vec<f64>,
    roots: Vec<f64>,
    h_step: f64,
    stepper: Stepper,
    dense_ready: bool,
    dynamics: Dynamics,
    projector: Projector,
    next_output: usize,
    outputs: usize,
    errold: f64,
    rejected_last: bool,
    finished: bool,
    trajectory: Trajectory,
    events: Vec<EventHit>,
    stopped_by: Option<usize>,
    /// Taken out while it searches a step (it calls back into the dense output).
    watch: Option<SingularWatch>,
    started: Instant,
}

impl<'a> Simulator<'a> {
    /// Checks the inputs, builds the consistent initial state, records the first sample and
    /// allocates every buffer the step loop needs.
    pub fn new(system: &'a dyn System, options: &'a SimulationOptions) -> Result<Self, Error> {
        let started = Instant::now();
        let info = system.info();
        let (n, m) = (info.n(), info.m());
        let t0 = options.t_start;
        let mut params = vec![0.0; info.parameters.len()];
        system.parameter_values(&mut params);
        Error::check_finite(&params, "parameter", &info.parameters, t0)?;
        let io = &options.integrator;
        if !(options.t_end > t0)
            || !(options.output_rate > 0.0)
            || !(io.rtol > 0.0)
            || !(io.atol >= 0.0)
        {
            return Err(Error::InvalidInput(format!(
                "need t_end > t_start, output_rate > 0, rtol > 0, atol >= 0 (got t = [{t0}, {}], rate {}, rtol {}, atol {})",
                options.t_end, options.output_rate, io.rtol, io.atol
            )));
        }
        let (q, qd) = match &options.initial {
            InitialState::Declared => {
                let s = assemble(system, t0, &options.assembly)?;
                (s.q, s.qd)
            }
            InitialState::Independent(ind) => {
                let s = assemble_from(system, t0, ind, &info.initial_guess, &options.assembly)?;
                (s.q, s.qd)
            }
            InitialState::Consistent { q, qd } => {
                if q.len() != n || qd.len() != n {
                    return Err(Error::InvalidInput(format!(
                        "initial q and q' need {n} entries"
                    )));
                }
                (q.clone(), qd.clone())
            }
        };
        Error::check_finite(&q, "initial position", &info.coordinates, t0)?;
        Error::check_finite(&qd, "initial rate", &info.coordinates, t0)?;
        let mut dynamics = Dynamics::new(info);
        dynamics.condition_limit = options.condition_limit;
        if let Stabilization::Baumgarte { alpha, beta } = options.stabilization {
            dynamics.baumgarte = Some((alpha, beta));
        }
        let mut projector = Projector::new(info);
        let dim = 2 * n + 1;
        let mut y = vec![0.0; dim];
        y[..n].copy_from_slice(&q);
        y[n..2 * n].copy_from_slice(&qd);
        if options.stabilization == Stabilization::Projection {
            let (yq, yv) = y.split_at_mut(n);
            projector.project(system, t0, yq, &mut yv[..n])?;
        }
        dynamics.solve(system, t0, &y[..n], &y[n..2 * n])?;
        if let InitialState::Consistent { .. } = options.initial {
            let (e, ev) = (
                dynamics.constraint_error(),
                dynamics.velocity_constraint_error(&y[n..2 * n]),
            );
            if e > 1e-8 || ev > 1e-8 {
                return Err(Error::InvalidInput(format!(
                    "the given initial state is not consistent: |Phi| = {e:e}, |Phi_q q' + Phi_t| = {ev:e}"
                )));
            }
        }
        let watch = Some(SingularWatch::new(system, t0, &y[..n]));
        let mobility = mobility(system, t0, &y[..n])?;
        let span = options.t_end - t0;
        let outputs = ((span * options.output_rate) - 1e-9).ceil().max(1.0);
        // t_end > t0 and rate > 0 were checked above, so outputs is not NaN.
        if outputs > MAX_OUTPUT_SAMPLES as f64 {
            return Err(Error::InvalidInput(format!(
                "{} s at {} samples per second would record {outputs:e} samples, more than the {MAX_OUTPUT_SAMPLES:e} this run allows: shorten the time span or lower the output rate",
                span, options.output_rate
            )));
        }
        // Reserve the whole output up front (the step loop then never grows it) unless it is
        // very long; beyond that the buffer grows as it fills.
        let outputs = outputs as usize;
        let reserve = (outputs + 1 + 64).min(RESERVED_SAMPLES);
        let mut trajectory = Trajectory::with_capacity(info.clone(), reserve);
        trajectory.mobility = Some(mobility);
        let stepper = match io.method {
            Method::Hht { alpha, .. } => {
                let mut hht = Box::new(Hht::new(info, alpha)?);
                hht.start(
                    system,
                    t0,
                    &y[..n],
                    &y[n..2 * n],
                    dynamics.accelerations(),
                    dynamics.multipliers(),
                );
                Stepper::Hht {
                    hht,
                    hermite: Dense::new(dim, 4),
                    f0: vec![0.0; dim],
                    f1: vec![0.0; dim],
                    power: dynamics.power(&y[n..2 * n]),
                }
            }
            method => Stepper::Explicit(
                explicit_stepper(method, dim)
                    .ok_or_else(|| Error::InvalidInput("no stepper".into()))?,
            ),
        };
        let mut sim = Self {
            system,
            options,
            n,
            t: t0,
            h: 0.0,
            y_new: y.clone(),
            y_dense: y.clone(),
            scratch: vec![0.0; 2 * dim],
            g_old: vec![0.0; options.events.len()],
            roots: vec![f64::NAN; options.events.len()],
            h_step: 0.0,
            y,
            stepper,
            dense_ready: false,
            dynamics,
            projector,
            next_output: 1,
            outputs,
            errold: 1e-4,
            rejected_last: false,
            finished: false,
            trajectory,
            events: Vec::with_capacity(16),
            stopped_by: None,
            watch,
            started,
        };
        let _ = m;
        sim.y_dense.copy_from_slice(&sim.y);
        sim.record(t0)?;
        for (i, ev) in options.events.iter().enumerate() {
            sim.g_old[i] = (ev.g)(t0, &sim.y[..n], &sim.y[n..2 * n]);
        }
        sim.h = sim.first_step()?;
        Ok(sim)
    }

    fn first_step(&mut self) -> Result<f64, Error> {
        let io = &self.options.integrator;
        let span = self.options.t_end - self.options.t_start;
        let h_max = io.h_max.unwrap_or(span).min(span);
        match (&mut self.stepper, io.method) {
            (_, Method::Rk4 { h }) | (_, Method::Hht { h, .. }) => {
                if !(h > 0.0) {
                    return Err(Error::InvalidInput(format!(
                        "fixed step h = {h} must be positive"
                    )));
                }
                if let Stepper::Explicit(rk) = &mut self.stepper {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n: self.n,
                    };
                    rhs.rhs(self.t, &self.y, rk.k1_mut())?;
                }
                Ok(h.min(span))
            }
            (Stepper::Explicit(rk), method) => {
                let mut rhs = Rhs {
                    system: self.system,
                    dynamics: &mut self.dynamics,
                    n: self.n,
                };
                rhs.rhs(self.t, &self.y, rk.k1_mut())?;
                if let Some(h) = io.h_initial {
                    return Ok(h.min(h_max));
                }
                let order = if method == Method::Dop853 { 8.0 } else { 5.0 };
                let f0 = rk.k1_mut().to_vec(); // before the loop: allowed
                initial_step(
                    &mut rhs,
                    self.t,
                    &self.y,
                    &f0,
                    order,
                    Tolerance {
                        rtol: io.rtol,
                        atol: io.atol,
                    },
                    h_max,
                    &mut self.scratch,
                )
            }
            (Stepper::Hht { .. }, _) => unreachable!("HHT has a fixed step"),
        }
    }

    /// Current time (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// True once the end time or a stopping event is reached.
    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// The samples recorded so far.
    pub fn trajectory(&self) -> &Trajectory {
        &self.trajectory
    }

    /// Runs to the end time (or a stopping event); any failure is an error.
    pub fn run(self) -> Result<Simulation, Error> {
        let simulation = self.run_recording();
        match simulation.failure {
            Some(e) => Err(e),
            None => Ok(simulation),
        }
    }

    /// Runs to the end time, a stopping event or the first failure, which is returned in
    /// [`Simulation::failure`] with the samples recorded before it.
    pub fn run_recording(mut self) -> Simulation {
        let mut failure = None;
        while !self.finished {
            if let Err(e) = self.step() {
                failure = Some(e);
                break;
            }
        }
        self.finish(failure)
    }

    /// Ends the run where it stands (after [`Simulator::step`] returned false or an error):
    /// the trajectory so far, the run counters, and `failure` if the run stopped on one.
    pub fn finish(mut self, failure: Option<Error>) -> Simulation {
        let stats = &mut self.trajectory.stats;
        stats.wall_time_s = self.started.elapsed().as_secs_f64();
        stats.rhs_evaluations = self.dynamics.evaluations;
        stats.augmented_solves = self.dynamics.augmented_solves;
        if let Stepper::Hht { hht, .. } = &self.stepper {
            stats.rhs_evaluations += hht.evaluations;
        }
        Simulation {
            trajectory: self.trajectory,
            events: self.events,
            stopped_by: self.stopped_by,
            failure,
        }
    }

    /// Performs one accepted step (retrying rejected ones), records the output samples and
    /// events inside it and applies the stabilisation. Returns false when finished.
    /// Allocates nothing (apart from event records, which are rare).
    pub fn step(&mut self) -> Result<bool, Error> {
        if self.finished {
            return Ok(false);
        }
        let io = self.options.integrator;
        if self.trajectory.stats.steps >= io.max_steps {
            return Err(Error::TooManySteps {
                t: self.t,
                max_steps: io.max_steps,
            });
        }
        let t_end = self.options.t_end;
        let n = self.n;
        let h_max = io.h_max.unwrap_or(f64::INFINITY);
        let tol = Tolerance {
            rtol: io.rtol,
            atol: io.atol,
        };
        let h = loop {
            let mut h = self.h.min(h_max);
            let last = self.t + h >= t_end - 1e-12 * t_end.abs().max(1.0);
            if last {
                h = t_end - self.t;
            }
            match &mut self.stepper {
                Stepper::Explicit(rk) => {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n,
                    };
                    let err = rk.attempt(&mut rhs, self.t, &self.y, h, &mut self.y_new, tol)?;
                    if !rk.adaptive() {
                        rk.finish(&mut rhs, self.t, &self.y_new, h)?;
                        break h;
                    }
                    let expo = rk.exponent();
                    if err <= 1.0 && err.is_finite() {
                        rk.finish(&mut rhs, self.t, &self.y_new, h)?;
                        let mut fac =
                            0.9 * err.max(1e-10).powf(-expo) * self.errold.powf(rk.pi_beta());
                        fac = fac.clamp(0.2, rk.max_growth());
                        if self.rejected_last {
                            fac = fac.min(1.0);
                        }
                        self.errold = err.max(1e-4);
                        self.rejected_last = false;
                        if !last {
                            self.h = h * fac;
                        }
                        break h;
                    }
                    self.trajectory.stats.rejected_steps += 1;
                    self.rejected_last = true;
                    let fac = if err.is_finite() {
                        (0.9 * err.powf(-expo)).max(0.2)
                    } else {
                        0.2
                    };
                    self.h = h * fac;
                    if self.h < io.h_min {
                        return Err(Error::StepSizeUnderflow {
                            t: self.t,
                            h: self.h,
                        });
                    }
                }
                Stepper::Hht {
                    hht, f0, f1, power, ..
                } => {
                    self.y_new.copy_from_slice(&self.y);
                    f0[..n].copy_from_slice(&self.y[n..2 * n]);
                    f0[n..2 * n].copy_from_slice(hht.accelerations());
                    f0[2 * n] = *power;
                    let (q, rest) = self.y_new.split_at_mut(n);
                    hht.step(self.system, self.t, q, &mut rest[..n], h)?;
                    let p1 = hht.power();
                    self.y_new[2 * n] = self.y[2 * n] + 0.5 * h * (*power + p1);
                    f1[..n].copy_from_slice(&self.y_new[n..2 * n]);
                    f1[n..2 * n].copy_from_slice(hht.accelerations());
                    f1[2 * n] = p1;
                    *power = p1;
                    break h;
                }
            }
        };
        self.dense_ready = false;
        self.h_step = h;
        let t_new = self.t + h;
        let names = &self.system.info().coordinates;
        Error::check_finite(&self.y_new[..n], "position", names, t_new)?;
        Error::check_finite(&self.y_new[n..2 * n], "rate", names, t_new)?;
        if !self.y_new[2 * n].is_finite() {
            return Err(Error::NonFinite {
                what: "work W of the applied forces".into(),
                t: t_new,
            });
        }
        // Events: earliest sign change inside the step, located on the dense output.
        let mut t_stop = t_new;
        let mut stop_event = None;
        if !self.options.events.is_empty() {
            self.locate_events(h, &mut t_stop, &mut stop_event)?;
        }
        // Output samples inside (t, t_stop].
        while self.next_output <= self.outputs {
            let to = self.output_time(self.next_output);
            if to > t_stop + 1e-12 * t_stop.abs().max(1.0) {
                break;
            }
            if stop_event.is_some() && to >= t_stop {
                break;
            }
            self.dense_at(((to - self.t) / h).clamp(0.0, 1.0))?;
            self.record(to)?;
            self.next_output += 1;
        }
        self.trajectory.stats.steps += 1;
        if stop_event.is_none() {
            self.watch_singular(h)?;
        }
        if let Some(k) = stop_event {
            self.dense_at(((t_stop - self.t) / h).clamp(0.0, 1.0))?;
            self.record(t_stop)?;
            self.stopped_by = Some(k);
            self.finished = true;
            self.t = t_stop;
            return Ok(false);
        }
        // Accept: stabilise the new state and start the next step from it.
        self.t = t_new;
        std::mem::swap(&mut self.y, &mut self.y_new);
        // HHT keeps its Newmark state (q, q', a) untouched: projecting q' would break the
        // relation between them; its positions already satisfy Phi = 0 to Newton tolerance.
        let projected = self.options.stabilization == Stabilization::Projection
            && matches!(self.stepper, Stepper::Explicit(_));
        if projected {
            let (q, rest) = self.y.split_at_mut(n);
            self.projector
                .project(self.system, self.t, q, &mut rest[..n])?;
        }
        match &mut self.stepper {
            Stepper::Explicit(rk) => {
                if projected {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n,
                    };
                    rhs.rhs(self.t, &self.y, rk.k1_mut())?;
                } else {
                    rk.reuse_f_new();
                }
            }
            Stepper::Hht { .. } => {}
        }
        for (i, ev) in self.options.events.iter().enumerate() {
            self.g_old[i] = (ev.g)(self.t, &self.y[..n], &self.y[n..2 * n]);
        }
        if self.t >= t_end - 1e-12 * t_end.abs().max(1.0) {
            self.finished = true;
        }
        Ok(!self.finished)
    }

    /// Records the singular configurations passed inside the step just taken (from self.t
    /// to self.t + h, before it is accepted): see [`crate::singular`].
    fn watch_singular(&mut self, h: f64) -> Result<(), Error> {
        let Some(mut watch) = self.watch.take() else {
            return Ok(());
        };
        let (n, t0) = (self.n, self.t);
        let w1 = watch.measure(self.system, t0 + h, &self.y_new[..n]);
        let found = watch.observe_step(t0, h, w1, |w, theta| {
            self.dense_at(theta)?;
            Ok::<f64, Error>(w.measure(self.system, t0 + theta * h, &self.y_dense[..n]))
        });
        self.watch = Some(watch);
        if let Some(p) = found? {
            self.trajectory.singular_passages.push(p);
        }
        Ok(())
    }

    fn output_time(&self, k: usize) -> f64 {
        let o = self.options;
        if k >= self.outputs {
            o.t_end
        } else {
            (o.t_start + k as f64 / o.output_rate).min(o.t_end)
        }
    }

    /// Fills `y_dense` with the continuous extension of the last step at theta.
    fn dense_at(&mut self, theta: f64) -> Result<(), Error> {
        let h = self.last_h();
        match &mut self.stepper {
            Stepper::Explicit(rk) => {
                if !self.dense_ready {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n: self.n,
                    };
                    rk.prepare_dense(&mut rhs, self.t, &self.y, &self.y_new, h)?;
                }
                rk.dense(theta, &mut self.y_dense);
            }
            Stepper::Hht {
                hermite, f0, f1, ..
            } => {
                if !self.dense_ready {
                    hermite.set_hermite(&self.y, &self.y_new, f0, f1, h);
                }
                hermite.eval(theta, &mut self.y_dense);
            }
        }
        self.dense_ready = true;
        Ok(())
    }

    fn last_h(&self) -> f64 {
        self.h_step
    }

    /// Projects `y_dense` when the stabilisation is projection, solves the augmented system
    /// there and appends the sample at time `ts`.
    fn record(&mut self, ts: f64) -> Result<(), Error> {
        let n = self.n;
        let (q, rest) = self.y_dense.split_at_mut(n);
        let (qd, w) = rest.split_at_mut(n);
        if self.options.stabilization == Stabilization::Projection {
            self.projector.project(self.system, ts, q, qd)?;
        }
        self.dynamics.solve(self.system, ts, q, qd)?;
        // Redundant rows leave lambda undetermined: record the minimum-norm choice.
        self.dynamics.min_norm_multipliers();
        let d = &self.dynamics;
        let e = d.evaluation();
        self.trajectory.push(
            ts,
            q,
            qd,
            d.accelerations(),
            d.multipliers(),
            d.constraint_error(),
            d.velocity_constraint_error(qd),
            [e.kinetic, e.potential, w[0]],
        );
        Ok(())
    }

    /// Finds the sign changes of the event functions between the step start (g_old) and
    /// its end, locates each by the Illinois variant of regula falsi on the dense output,
    /// records the crossings up to the first stopping one and reports that one.
    #[allow(clippy::needless_range_loop)] // events, g_old and roots share the index
    fn locate_events(
        &mut self,
        h: f64,
        t_stop: &mut f64,
        stop_event: &mut Option<usize>,
    ) -> Result<(), Error> {
        let n = self.n;
        let events = &self.options.events;
        let t0 = self.t;
        for i in 0..events.len() {
            self.roots[i] = f64::NAN;
            let g = &events[i].g;
            let g0 = self.g_old[i];
            let g1 = g(t0 + h, &self.y_new[..n], &self.y_new[n..2 * n]);
            if g0 == 0.0 || !(g0 * g1 <= 0.0) {
                continue;
            }
            let (mut a, mut fa, mut b, mut fb) = (0.0f64, g0, 1.0f64, g1);
            let mut side = 0i8;
            for _ in 0..200 {
                if fb == 0.0 || (b - a) * h <= 4.0 * f64::EPSILON * (t0.abs() + h) {
                    break;
                }
                let mut c = (a * fb - b * fa) / (fb - fa);
                if !(c > a && c < b) {
                    c = 0.5 * (a + b);
                }
                self.dense_at(c)?;
                let fc = g(t0 + c * h, &self.y_dense[..n], &self.y_dense[n..2 * n]);
                if fc == 0.0 {
                    a = c;
                    b = c;
                    break;
                }
                if (fc > 0.0) == (fb > 0.0) {
                    b = c;
                    fb = fc;
                    if side == -1 {
                        fa *= 0.5;
                    }
                    side = -1;
                } else {
                    a = c;
                    fa = fc;
                    if side == 1 {
                        fb *= 0.5;
                    }
                    side = 1;
                }
            }
            let _ = a;
            self.roots[i] = t0 + b * h;
            if events[i].action == EventAction::Stop && self.roots[i] < *t_stop {
                *t_stop = self.roots[i];
                *stop_event = Some(i);
            }
        }
        // Record the crossings up to the stop, in time order.
        loop {
            let mut best: Option<usize> = None;
            for i in 0..events.len() {
                let r = self.roots[i];
                if r.is_finite() && r <= *t_stop && best.is_none_or(|b| r < self.roots[b]) {
                    best = Some(i);
                }
            }
            let Some(i) = best else { break };
            let tr = self.roots[i];
            self.roots[i] = f64::NAN;
            self.dense_at(((tr - t0) / h).clamp(0.0, 1.0))?;
            let (q, rest) = self.y_dense.split_at_mut(n);
            if self.options.stabilization == Stabilization::Projection {
                self.projector.project(self.system, tr, q, &mut rest[..n])?;
            }
            self.events.push(EventHit {
                event: i,
                t: tr,
                q: q.to_vec(),
                qd: rest[..n].to_vec(),
            });
        }
        Ok(())
    }
}
