//! Forward dynamics: the simulation driver.
//!
//! Integrates the index-3 DAE M q'' + C q' + g + Phi_q^T lambda = tau, Phi(q, t) = 0 as the
//! ODE y' = [q', q'', tau . q' + lambda . Phi_t] in y = [q, q', W] (q'' and lambda from the
//! augmented system, [`crate::Dynamics`]; W the work of tau and of the rows that move with t,
//! so that T + Pi - W is constant), with the chosen
//! [`Stabilization`], and records samples at a fixed output rate from the integrator's dense
//! output. Each sample holds q, q', q'', lambda, |Phi|_inf, |Phi_q q' + Phi_t|_inf, T, Pi, W.
//!
//! The step loop ([`Simulator::step`]) allocates nothing: every buffer is created in
//! [`Simulator::new`], and the output trajectory is reserved for all samples up front.
//!
//! The driver orchestrates; its parts: the start checks (`start.rs`), the right-hand side
//! (`rhs.rs`, built once), the method's [`Stepper`] with its step control and dense output
//! (`stepper.rs`), the output samples and singular passages (`simulator/samples.rs`), the
//! events (`simulator/located.rs`) and the fail-fast tests (`fail_fast.rs`).

// Comparisons are written `!(x > 0.0)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::time::Instant;

mod located;
mod samples;

use crate::algorithms::coordinate_singularity;
use crate::algorithms::dynamics::Dynamics;
use crate::algorithms::mobility::mobility;
use crate::algorithms::stabilization::{Projector, Stabilization};
use crate::error::Error;
use crate::integrators::{Method, Tolerance};
use crate::limits::check_output_memory;
use crate::simulation::events::{EventHit, EventLog};
use crate::simulation::fail_fast::FailFast;
use crate::simulation::options::{InitialState, RESERVED_SAMPLES, SimulationOptions};
use crate::simulation::rhs::{Rhs, StageProjection, projection_size};
use crate::simulation::singular::SingularWatch;
use crate::simulation::start::{check_options, initial_state, output_count};
use crate::simulation::stepper::{Stepper, stepper_for};
use crate::simulation::trajectory::Trajectory;
use crate::system::{ConstraintRow, System};

/// How many times one step is retaken because it ends just before a singular position it
/// predicts (`stepper/passage.rs`); A02 has needed 4.
const MAX_RETAKES: usize = 8;

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

/// The forward-dynamics driver, one accepted step at a time ([`Simulator::step`]) or to the
/// end ([`Simulator::run`]).
pub struct Simulator<'a> {
    options: &'a SimulationOptions,
    n: usize,
    /// Current time (s), and whether the end time or a stopping event was reached.
    t: f64,
    finished: bool,
    state: StateBuffers,
    stepper: Box<dyn Stepper>,
    /// y' = f(t, y), with the run's augmented solve.
    rhs: Rhs<'a>,
    /// The local error tolerance (the step control's and the projection's measure).
    tol: Tolerance,
    /// Output samples: the next one's index, how many in all, and the trajectory.
    next_output: usize,
    outputs: usize,
    trajectory: Trajectory,
    events: EventLog,
    /// Taken out while it searches a step (it calls back into the dense output).
    watch: Option<SingularWatch>,
    /// Step-size collapse and divergence tests.
    fail_fast: FailFast,
    started: Instant,
}

/// The state vectors y = [q, q', W] the driver works on, allocated once.
struct StateBuffers {
    /// y at the current time.
    y: Vec<f64>,
    /// y at the end of the step being taken.
    y_new: Vec<f64>,
    /// y from the dense output (samples, events, passages).
    y_dense: Vec<f64>,
    /// [q, q'] before the projection of an accepted step.
    before: Vec<f64>,
}

impl StateBuffers {
    /// Buffers initialised to `y`.
    fn new(y: Vec<f64>, n: usize) -> Self {
        Self {
            y_new: y.clone(),
            y_dense: y.clone(),
            before: vec![0.0; 2 * n],
            y,
        }
    }
}

impl<'a> Simulator<'a> {
    /// The refusals [`Simulator::new`] makes before any work, alone: invalid options, more
    /// than [`crate::MAX_OUTPUT_SAMPLES`] samples or more than [`crate::MAX_OUTPUT_BYTES`]
    /// of them ([`Error::TooMuchOutput`]), a fixed step that needs more than `max_steps`
    /// steps ([`Error::FixedStepTooSmall`]). It reads neither the initial state nor the
    /// system's equations, so a caller can refuse a run before it claims anything for it
    /// (the command-line tool, before it touches the output folder). Returns the number of
    /// output samples after the first.
    pub fn check(system: &dyn System, options: &SimulationOptions) -> Result<usize, Error> {
        check_options(system, options)?;
        let outputs = output_count(options)?;
        check_output_memory(outputs + 1, Trajectory::stride_of(system.info()), 0)?;
        let io = &options.integrator;
        if let Method::Rk4 { h } | Method::Hht { h, .. } = io.method {
            FailFast::check_fixed_step(h, options.t_end - options.t_start, io.max_steps)?;
        }
        Ok(outputs)
    }

    /// Checks the inputs, builds the consistent initial state, records the first sample and
    /// allocates every buffer the step loop needs.
    ///
    /// Refused before any work: invalid options, more than [`crate::MAX_OUTPUT_SAMPLES`]
    /// samples or more than [`crate::MAX_OUTPUT_BYTES`] of them
    /// ([`Error::TooMuchOutput`]), a fixed step that needs more than `max_steps` steps
    /// ([`Error::FixedStepTooSmall`]). An undetermined motion at the start that the
    /// coordinates cause is [`Error::CoordinateSingularity`].
    pub fn new(system: &'a dyn System, options: &'a SimulationOptions) -> Result<Self, Error> {
        Self::start(system, options).map_err(|e| coordinate_singularity::explain(system, e))
    }

    /// [`Simulator::new`] before its failure is named.
    fn start(system: &'a dyn System, options: &'a SimulationOptions) -> Result<Self, Error> {
        let started = Instant::now();
        let info = system.info();
        let (n, t0) = (info.n(), options.t_start);
        let outputs = Self::check(system, options)?;
        let io = &options.integrator;
        let (q, qd) = initial_state(system, options)?;
        let mut dynamics = Dynamics::new(info);
        dynamics.condition_limit = options.condition_limit;
        if let Stabilization::Baumgarte { alpha, beta } = options.stabilization {
            dynamics.baumgarte = Some((alpha, beta));
        }
        let mut projector = Projector::new(info);
        if let Some(s) = system.sparsity() {
            projector.fix_ordered(&s.jacobian, &s.order);
        }
        let mut y = vec![0.0; 2 * n + 1];
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
                return Err(Error::InconsistentInitialState {
                    residual: e,
                    velocity_residual: ev,
                });
            }
        }
        let watch = Some(SingularWatch::new(system, t0, &y[..n]));
        let fail_fast = FailFast::new(&y[..n], &y[n..2 * n], t0, options.t_end - t0, io.max_steps);
        // Reserve the whole output up front (the step loop then never grows it) unless it is
        // very long; beyond that the buffer grows as it fills.
        let reserve = (outputs + 1 + 64).min(RESERVED_SAMPLES);
        let mut trajectory = Trajectory::with_capacity(info.clone(), reserve);
        let mob = mobility(system, t0, &y[..n])?;
        let stage = (options.stabilization == Stabilization::Projection && info.m() > 0)
            .then(|| StageProjection::new(n, !mob.redundant_rows.is_empty()));
        trajectory.mobility = Some(mob);
        let tol = io.tolerance();
        let stepper = stepper_for(system, io, tol, t0, &y, &dynamics)?;
        let mut sim = Self {
            options,
            n,
            t: t0,
            finished: false,
            state: StateBuffers::new(y, n),
            stepper,
            rhs: Rhs::new(system, dynamics, projector, n, stage),
            tol,
            next_output: 1,
            outputs,
            trajectory,
            events: EventLog::new(options.events.len()),
            watch,
            fail_fast,
            started,
        };
        sim.record(t0)?;
        let (q0, qd0) = sim.state.y.split_at(n);
        sim.events.restart(&options.events, t0, q0, &qd0[..n]);
        let span = options.t_end - options.t_start;
        sim.stepper.start(&mut sim.rhs, t0, &sim.state.y, span)?;
        Ok(sim)
    }

    fn system(&self) -> &'a dyn System {
        self.rhs.system
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
        stats.rhs_evaluations = self.rhs.dynamics.evaluations;
        stats.augmented_solves = self.rhs.dynamics.augmented_solves;
        stats.banded_solves = self.rhs.dynamics.banded_solves;
        stats.generated_solves = self.rhs.dynamics.generated_solves;
        stats.factor_work = self.rhs.dynamics.factor_work() + self.rhs.projector.factor_work;
        stats.rhs_evaluations += self.stepper.own_evaluations();
        Simulation {
            trajectory: self.trajectory,
            events: self.events.hits,
            stopped_by: self.events.stopped_by,
            failure,
        }
    }

    /// Performs one accepted step (retrying rejected ones), records the output samples and
    /// events inside it and applies the stabilisation. Returns false when finished.
    /// Allocates nothing (apart from event and passage records, which are rare).
    pub fn step(&mut self) -> Result<bool, Error> {
        let kept = self.trajectory.len();
        match self.step_unnamed() {
            Ok(more) => Ok(more),
            Err(e) => {
                // The samples inside the step that failed came from its dense output: a
                // state the failure shows to be wrong (a fixed step far too large gives
                // angles of 1e5 rad there). They go with the step.
                self.trajectory.truncate(kept);
                Err(self.name_failure(e))
            }
        }
    }

    /// The failure of a step under the name of its cause: a fixed step (RK4, HHT) whose
    /// states the projection or HHT's Newton cannot bring back onto the constraints is
    /// [`Error::StepTooLarge`] (it left them that far within one step); a non-finite entry
    /// evaluated at a state beyond the divergence bounds is [`Error::Diverged`] (the
    /// entry overflowed because the state had); an undetermined motion that the coordinates
    /// cause is [`Error::CoordinateSingularity`]; a step size that collapses next to a
    /// singular position of the constraints is [`Error::StuckAtSingularPosition`].
    fn name_failure(&self, e: Error) -> Error {
        let names = &self.system().info().coordinates;
        let stuck = self.watch.as_ref().and_then(SingularWatch::stuck);
        if let (
            Error::StepSizeUnderflow { t, h } | Error::StepSizeCollapse { t, h, .. },
            Some((t_singular, independence)),
        ) = (&e, stuck)
        {
            let rows = self
                .watch
                .as_ref()
                .map_or_else(Vec::new, SingularWatch::weak_rows);
            let rows = row_names(&self.system().info().constraint_rows, &rows).into();
            return Error::StuckAtSingularPosition {
                t: *t,
                h: *h,
                t_singular,
                rows,
                independence,
                passages: self.trajectory.singular_passages.len(),
                remedy: singular_remedy(self.options.stabilization, self.options.integrator.method)
                    .into(),
            };
        }
        match (e, self.options.integrator.method) {
            (
                Error::NewtonDidNotConverge { t, residual, .. },
                Method::Rk4 { h } | Method::Hht { h, .. },
            ) => Error::StepTooLarge {
                t,
                h,
                method: self.options.integrator.method.name(),
                residual,
            },
            (Error::NonFiniteTerm { term, value, t, q }, _) => {
                match self.fail_fast.check_state(&q, &[], names, t) {
                    Err(diverged) => diverged,
                    Ok(()) => Error::NonFiniteTerm { term, value, t, q },
                }
            }
            // Orientation angles whose axes line up (a body lying flat) rather than a body
            // without inertia.
            (e @ Error::UndeterminedMotion { .. }, _) => {
                coordinate_singularity::explain(self.system(), e)
            }
            (e, _) => e,
        }
    }

    fn step_unnamed(&mut self) -> Result<bool, Error> {
        if self.finished {
            return Ok(false);
        }
        let max_steps = self.options.integrator.max_steps;
        if self.trajectory.stats.steps >= max_steps {
            return Err(Error::TooManySteps {
                t: self.t,
                max_steps,
            });
        }
        // A step that ends just before a singular position predicted only after it is
        // taken again, steered, until its end is far enough from the t* it predicts: each
        // retaken step ends nearer to t* and predicts it better (A02 N = 8 grouped, rtol
        // 1e-8, from 0.108 s away: 0.195, 0.183, 0.154, then 0.108 s ahead). At most
        // `MAX_RETAKES` times.
        let mut retaken = 0;
        let (h, w1) = loop {
            let state = &mut self.state;
            let h = self.stepper.advance(
                &mut self.rhs,
                self.t,
                self.options.t_end,
                &state.y,
                &mut state.y_new,
                &mut self.trajectory.stats.rejected_steps,
            )?;
            self.check_new_state(self.t + h)?;
            let w1 = self.measure_end(h);
            if retaken < MAX_RETAKES && self.retake_before_singular(h, w1)? {
                retaken += 1;
                self.trajectory.stats.rejected_steps += 1;
                continue;
            }
            break (h, w1);
        };
        let t_new = self.t + h;
        // Events: earliest sign change inside the step, located on the dense output.
        let mut t_stop = t_new;
        let mut stop_event = None;
        if !self.options.events.is_empty() {
            self.locate_events(h, &mut t_stop, &mut stop_event)?;
        }
        self.record_outputs(h, t_stop, stop_event.is_some())?;
        self.trajectory.stats.steps += 1;
        if let Some(k) = stop_event {
            self.dense_at(((t_stop - self.t) / h).clamp(0.0, 1.0))?;
            self.record(t_stop)?;
            self.events.stopped_by = Some(k);
            self.finished = true;
            self.t = t_stop;
            return Ok(false);
        }
        self.watch_singular(h, w1)?;
        self.accept(t_new)?;
        if !self.finished {
            let steps = self.trajectory.stats.steps;
            self.fail_fast
                .after_step(steps, t_new, self.options.t_end)?;
        }
        Ok(!self.finished)
    }

    /// The end state of the step must be finite and within the divergence bounds: q, q'
    /// ([`Error::Diverged`]) and the work W.
    fn check_new_state(&self, t_new: f64) -> Result<(), Error> {
        let n = self.n;
        let names = &self.system().info().coordinates;
        let (q, qd) = self.state.y_new.split_at(n);
        self.fail_fast.check_state(q, &qd[..n], names, t_new)?;
        if !self.state.y_new[2 * n].is_finite() {
            return Err(Error::NonFinite {
                what: "work W of the applied forces".into(),
                t: t_new,
            });
        }
        Ok(())
    }

    /// Accepts the step: moves to t_new, stabilises the new state and starts the next step
    /// from it.
    fn accept(&mut self, t_new: f64) -> Result<(), Error> {
        let n = self.n;
        let t_end = self.options.t_end;
        self.t = t_new;
        std::mem::swap(&mut self.state.y, &mut self.state.y_new);
        let projected =
            self.options.stabilization == Stabilization::Projection && self.stepper.projects();
        let mut moved = None;
        if projected {
            let (q, rest) = self.state.y.split_at_mut(n);
            let before = &mut self.state.before;
            before[..n].copy_from_slice(q);
            before[n..].copy_from_slice(&rest[..n]);
            self.rhs
                .projector
                .project(self.rhs.system, t_new, q, &mut rest[..n])?;
            moved = Some(projection_size(&self.state.y[..2 * n], before, self.tol));
        }
        self.stepper
            .restart(&mut self.rhs, t_new, &self.state.y, moved)?;
        let (q, qd) = self.state.y.split_at(n);
        self.events
            .restart(&self.options.events, t_new, q, &qd[..n]);
        if t_new >= t_end - 1e-12 * t_end.abs().max(1.0) {
            self.finished = true;
        }
        Ok(())
    }
}

/// The rows `rows` of Phi by their joint and component (`joint (x)`), `; ` between them;
/// four at most, then how many more (A02 lying flat loses 40 rows at once).
fn row_names(named: &[ConstraintRow], rows: &[usize]) -> String {
    const NAMED: usize = 4;
    let mut names = rows
        .iter()
        .take(NAMED)
        .map(|&r| match named.get(r) {
            Some(c) if !c.component.is_empty() => format!("{} ({})", c.joint, c.component),
            Some(c) => c.joint.clone(),
            None => format!("row {}", r + 1),
        })
        .collect::<Vec<_>>()
        .join("; ");
    if rows.len() > NAMED {
        names.push_str(&format!(" and {} more rows", rows.len() - NAMED));
    }
    names
}

/// What passes a singular position where an adaptive run with `stabilization` stopped
/// ([`Error::StuckAtSingularPosition`]).
fn singular_remedy(stabilization: Stabilization, method: Method) -> String {
    match stabilization {
        Stabilization::Projection => format!(
            "{} cannot meet the tolerance with its stages this near the singular position; \
             a looser --rtol, or a fixed step (--integrator rk4 or hht with --step), passes it",
            method.name()
        ),
        _ => "without projection the state drifts off the constraints, and near a singular \
              position the accelerations amplify that drift; --stabilization projection (the \
              default) passes it"
            .to_string(),
    }
}
