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

use std::time::Instant;

use crate::algorithms::dynamics::Dynamics;
use crate::algorithms::kinematics::{assemble, assemble_from};
use crate::algorithms::mobility::mobility;
use crate::algorithms::stabilization::{Projector, Stabilization};
use crate::error::Error;
use crate::integrators::{
    Dense, Dop853, Dopri5, Hht, Method, OdeRhs, Rk4, StepController, Tolerance, initial_step,
};
use crate::limits::{MAX_OUTPUT_SAMPLES, check_output_memory};
use crate::simulation::events::{EventAction, EventHit, EventLog};
use crate::simulation::fail_fast::FailFast;
use crate::simulation::options::{InitialState, RESERVED_SAMPLES, SimulationOptions};
use crate::simulation::singular::SingularWatch;
use crate::simulation::stepper::{
    REUSE_AFTER_PROJECTION, Rhs, StageProjection, StateBuffers, StepControl, Stepper,
    projection_size,
};
use crate::simulation::trajectory::Trajectory;
use crate::system::System;

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
    system: &'a dyn System,
    options: &'a SimulationOptions,
    n: usize,
    clock: StepControl,
    state: StateBuffers,
    stepper: Stepper,
    dynamics: Dynamics,
    projector: Projector,
    /// The projection of the stage states (redundant rows only: see [`StageProjection`]).
    stage: Option<StageProjection>,
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

impl<'a> Simulator<'a> {
    /// Checks the inputs, builds the consistent initial state, records the first sample and
    /// allocates every buffer the step loop needs.
    ///
    /// Refused before any work: invalid options, more than [`MAX_OUTPUT_SAMPLES`] samples
    /// or more than [`crate::MAX_OUTPUT_BYTES`] of them ([`Error::TooMuchOutput`]), a fixed
    /// step that needs more than `max_steps` steps ([`Error::FixedStepTooSmall`]).
    pub fn new(system: &'a dyn System, options: &'a SimulationOptions) -> Result<Self, Error> {
        let started = Instant::now();
        let info = system.info();
        let (n, t0) = (info.n(), options.t_start);
        check_options(system, options)?;
        let outputs = output_count(options)?;
        check_output_memory(outputs + 1, Trajectory::stride_of(info), 0)?;
        let io = &options.integrator;
        if let Method::Rk4 { h } | Method::Hht { h, .. } = io.method {
            FailFast::check_fixed_step(h, options.t_end - t0, io.max_steps)?;
        }
        let (q, qd) = initial_state(system, options)?;
        let mut dynamics = Dynamics::new(info);
        dynamics.condition_limit = options.condition_limit;
        if let Stabilization::Baumgarte { alpha, beta } = options.stabilization {
            dynamics.baumgarte = Some((alpha, beta));
        }
        let mut projector = Projector::new(info);
        if let Some(s) = system.sparsity() {
            projector.fix(&s.jacobian);
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
        let fail_fast = FailFast::new(
            &y[..n],
            &y[n..2 * n],
            t0,
            options.t_end - t0,
            options.integrator.max_steps,
        );
        // Reserve the whole output up front (the step loop then never grows it) unless it is
        // very long; beyond that the buffer grows as it fills.
        let reserve = (outputs + 1 + 64).min(RESERVED_SAMPLES);
        let mut trajectory = Trajectory::with_capacity(info.clone(), reserve);
        let mob = mobility(system, t0, &y[..n])?;
        let stage = (options.stabilization == Stabilization::Projection
            && !mob.redundant_rows.is_empty())
        .then(|| StageProjection::new(Projector::new(info), n));
        trajectory.mobility = Some(mob);
        let stepper = make_stepper(system, options, t0, &y, &dynamics)?;
        let mut sim = Self {
            system,
            options,
            n,
            clock: StepControl::new(t0),
            state: StateBuffers::new(y),
            stepper,
            dynamics,
            projector,
            stage,
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
        sim.clock.h = sim.first_step()?;
        Ok(sim)
    }

    fn first_step(&mut self) -> Result<f64, Error> {
        let io = &self.options.integrator;
        let span = self.options.t_end - self.options.t_start;
        let h_max = io.h_max.unwrap_or(span).min(span);
        match (&mut self.stepper, io.method) {
            (_, Method::Rk4 { h }) | (_, Method::Hht { h, .. }) => {
                if !(h > 0.0) {
                    return Err(Error::InvalidOption {
                        option: "h",
                        value: h,
                        allowed: "a positive step in seconds",
                    });
                }
                if let Stepper::Explicit(rk) = &mut self.stepper {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n: self.n,
                        onto: self.stage.as_mut(),
                    };
                    rhs.rhs(self.clock.t, &self.state.y, rk.k1_mut())?;
                }
                Ok(h.min(span))
            }
            (Stepper::Explicit(rk), method) => {
                let mut rhs = Rhs {
                    system: self.system,
                    dynamics: &mut self.dynamics,
                    n: self.n,
                    onto: self.stage.as_mut(),
                };
                rhs.rhs(self.clock.t, &self.state.y, rk.k1_mut())?;
                if let Some(h) = io.h_initial {
                    return Ok(h.min(h_max));
                }
                let order = if method == Method::Dop853 { 8.0 } else { 5.0 };
                let f0 = rk.k1_mut().to_vec(); // before the loop: allowed
                initial_step(
                    &mut rhs,
                    self.clock.t,
                    &self.state.y,
                    &f0,
                    order,
                    Tolerance {
                        rtol: io.rtol,
                        atol: io.atol,
                    },
                    h_max,
                    &mut self.state.scratch,
                )
            }
            (Stepper::Hht { .. }, _) => unreachable!("HHT has a fixed step"),
        }
    }

    /// Current time (s).
    pub fn time(&self) -> f64 {
        self.clock.t
    }

    /// True once the end time or a stopping event is reached.
    pub fn is_finished(&self) -> bool {
        self.clock.finished
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
        while !self.clock.finished {
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
            events: self.events.hits,
            stopped_by: self.events.stopped_by,
            failure,
        }
    }

    /// Performs one accepted step (retrying rejected ones), records the output samples and
    /// events inside it and applies the stabilisation. Returns false when finished.
    /// Allocates nothing (apart from event and passage records, which are rare).
    pub fn step(&mut self) -> Result<bool, Error> {
        self.step_unnamed().map_err(|e| self.name_failure(e))
    }

    /// The failure of a step under the name of its cause: a fixed step (RK4, HHT) whose
    /// states the projection or HHT's Newton cannot bring back onto the constraints is
    /// [`Error::StepTooLarge`] (it left them that far within one step); a non-finite entry
    /// evaluated at a state beyond the divergence bounds is [`Error::Diverged`] (the
    /// entry overflowed because the state had).
    fn name_failure(&self, e: Error) -> Error {
        let names = &self.system.info().coordinates;
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
            (e, _) => e,
        }
    }

    fn step_unnamed(&mut self) -> Result<bool, Error> {
        if self.clock.finished {
            return Ok(false);
        }
        let max_steps = self.options.integrator.max_steps;
        if self.trajectory.stats.steps >= max_steps {
            return Err(Error::TooManySteps {
                t: self.clock.t,
                max_steps,
            });
        }
        let h = self.attempt_until_accepted()?;
        self.state.dense_ready = false;
        self.clock.h_step = h;
        let t_new = self.clock.t + h;
        self.check_new_state(t_new)?;
        // Events: earliest sign change inside the step, located on the dense output.
        let mut t_stop = t_new;
        let mut stop_event = None;
        if !self.options.events.is_empty() {
            self.locate_events(h, &mut t_stop, &mut stop_event)?;
        }
        self.record_outputs(h, t_stop, stop_event.is_some())?;
        self.trajectory.stats.steps += 1;
        if let Some(k) = stop_event {
            self.dense_at(((t_stop - self.clock.t) / h).clamp(0.0, 1.0))?;
            self.record(t_stop)?;
            self.events.stopped_by = Some(k);
            self.clock.finished = true;
            self.clock.t = t_stop;
            return Ok(false);
        }
        self.watch_singular(h)?;
        self.accept(t_new)?;
        if !self.clock.finished {
            let steps = self.trajectory.stats.steps;
            self.fail_fast
                .after_step(steps, t_new, self.options.t_end)?;
        }
        Ok(!self.clock.finished)
    }

    /// Tries steps from the current state until one is accepted (for the adaptive methods:
    /// error norm <= 1, with Hairer's PI control of the next size); returns its size, with
    /// the end state in `state.y_new`.
    fn attempt_until_accepted(&mut self) -> Result<f64, Error> {
        let io = self.options.integrator;
        let (n, t_end) = (self.n, self.options.t_end);
        let h_max = io.h_max.unwrap_or(f64::INFINITY);
        let tol = Tolerance {
            rtol: io.rtol,
            atol: io.atol,
        };
        loop {
            let mut h = self.clock.h.min(h_max);
            let last = self.clock.t + h >= t_end - 1e-12 * t_end.abs().max(1.0);
            if last {
                h = t_end - self.clock.t;
            }
            let (t, state) = (self.clock.t, &mut self.state);
            match &mut self.stepper {
                Stepper::Explicit(rk) => {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n,
                        onto: self.stage.as_mut(),
                    };
                    let err = match rk.attempt(&mut rhs, t, &state.y, h, &mut state.y_new, tol) {
                        Ok(err) => err,
                        // A stage that cannot be evaluated (a non-finite entry, a
                        // projection or solve failing far from the last state) rejects the
                        // step like an error norm above 1: a smaller step takes its stages
                        // closer. A failure that persists down to h_min is returned.
                        Err(e) if rk.adaptive() && is_trial_failure(&e) => {
                            self.trajectory.stats.rejected_steps += 1;
                            self.clock.rejected_last = true;
                            self.clock.h = h * 0.2;
                            if self.clock.h < io.h_min {
                                return Err(e);
                            }
                            continue;
                        }
                        Err(e) => return Err(e),
                    };
                    if !rk.adaptive() {
                        rk.finish(&mut rhs, t, &state.y_new, h)?;
                        return Ok(h);
                    }
                    let expo = rk.exponent();
                    let clock = &mut self.clock;
                    if err <= 1.0 && err.is_finite() {
                        rk.finish(&mut rhs, t, &state.y_new, h)?;
                        let mut fac =
                            0.9 * err.max(1e-10).powf(-expo) * clock.errold.powf(rk.pi_beta());
                        if io.controller == StepController::Predictive {
                            let k = expo + 0.2 * rk.pi_beta();
                            fac = fac.min(clock.predictive(h, err, k));
                        }
                        fac = fac.clamp(0.2, rk.max_growth());
                        if clock.rejected_last {
                            fac = fac.min(1.0);
                        }
                        clock.errold = err.max(1e-4);
                        clock.rejected_last = false;
                        if !last {
                            clock.h = h * fac;
                        }
                        return Ok(h);
                    }
                    self.trajectory.stats.rejected_steps += 1;
                    clock.rejected_last = true;
                    let fac = if err.is_finite() {
                        (0.9 * err.powf(-expo)).max(0.2)
                    } else {
                        0.2
                    };
                    clock.h = h * fac;
                    if clock.h < io.h_min {
                        return Err(Error::StepSizeUnderflow { t, h: clock.h });
                    }
                }
                Stepper::Hht {
                    hht, f0, f1, power, ..
                } => {
                    state.y_new.copy_from_slice(&state.y);
                    f0[..n].copy_from_slice(&state.y[n..2 * n]);
                    f0[n..2 * n].copy_from_slice(hht.accelerations());
                    f0[2 * n] = *power;
                    let (q, rest) = state.y_new.split_at_mut(n);
                    hht.step(self.system, t, q, &mut rest[..n], h)?;
                    let p1 = hht.power();
                    state.y_new[2 * n] = state.y[2 * n] + 0.5 * h * (*power + p1);
                    f1[..n].copy_from_slice(&state.y_new[n..2 * n]);
                    f1[n..2 * n].copy_from_slice(hht.accelerations());
                    f1[2 * n] = p1;
                    *power = p1;
                    return Ok(h);
                }
            }
        }
    }

    /// The end state of the step must be finite and within the divergence bounds: q, q'
    /// ([`Error::Diverged`]) and the work W.
    fn check_new_state(&self, t_new: f64) -> Result<(), Error> {
        let n = self.n;
        let names = &self.system.info().coordinates;
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

    /// Records the output samples that fall inside (t, t_stop] of the step of size h (before
    /// t_stop itself when an event stops the run there).
    fn record_outputs(&mut self, h: f64, t_stop: f64, stopping: bool) -> Result<(), Error> {
        while self.next_output <= self.outputs {
            let to = self.output_time(self.next_output);
            if to > t_stop + 1e-12 * t_stop.abs().max(1.0) || (stopping && to >= t_stop) {
                break;
            }
            self.dense_at(((to - self.clock.t) / h).clamp(0.0, 1.0))?;
            self.record(to)?;
            self.next_output += 1;
        }
        Ok(())
    }

    /// Accepts the step: moves to t_new, stabilises the new state and starts the next step
    /// from it (the right-hand side anew after a projection, else the method's last stage).
    fn accept(&mut self, t_new: f64) -> Result<(), Error> {
        let n = self.n;
        let t_end = self.options.t_end;
        self.clock.t = t_new;
        std::mem::swap(&mut self.state.y, &mut self.state.y_new);
        // HHT keeps its Newmark state (q, q', a) untouched: projecting q' would break the
        // relation between them; its positions already satisfy Phi = 0 to Newton tolerance.
        let projected = self.options.stabilization == Stabilization::Projection
            && matches!(self.stepper, Stepper::Explicit(_));
        let mut moved = 0.0;
        if projected {
            let (q, rest) = self.state.y.split_at_mut(n);
            let before = &mut self.state.scratch[..2 * n];
            before[..n].copy_from_slice(q);
            before[n..].copy_from_slice(&rest[..n]);
            self.projector
                .project(self.system, t_new, q, &mut rest[..n])?;
            let tol = Tolerance {
                rtol: self.options.integrator.rtol,
                atol: self.options.integrator.atol,
            };
            moved = projection_size(&self.state.y[..2 * n], before, tol);
        }
        if let Stepper::Explicit(rk) = &mut self.stepper {
            // Only an adaptive method has an accepted local error to measure the projection
            // against: RK4 (fixed step, rtol and atol unused) always evaluates afresh.
            if !projected || (rk.adaptive() && moved <= REUSE_AFTER_PROJECTION) {
                // The step's last stage f(y_new) serves as the next step's first (FSAL).
                // After a projection that moved y by at most the accepted local error, it
                // differs from f(projected y) by at most L times that error; its position
                // rows take the projected q' exactly.
                rk.reuse_f_new();
                if projected {
                    rk.k1_mut()[..n].copy_from_slice(&self.state.y[n..2 * n]);
                }
            } else {
                let mut rhs = Rhs {
                    system: self.system,
                    dynamics: &mut self.dynamics,
                    n,
                    onto: self.stage.as_mut(),
                };
                rhs.rhs(t_new, &self.state.y, rk.k1_mut())?;
            }
        }
        let (q, qd) = self.state.y.split_at(n);
        self.events
            .restart(&self.options.events, t_new, q, &qd[..n]);
        if t_new >= t_end - 1e-12 * t_end.abs().max(1.0) {
            self.clock.finished = true;
        }
        Ok(())
    }

    /// Records the singular configurations passed inside the step just taken (from self.clock.t
    /// to self.clock.t + h, before it is accepted): see [`crate::singular`].
    fn watch_singular(&mut self, h: f64) -> Result<(), Error> {
        let Some(mut watch) = self.watch.take() else {
            return Ok(());
        };
        let (n, t0) = (self.n, self.clock.t);
        let w1 = watch.measure(self.system, t0 + h, &self.state.y_new[..n]);
        let found = watch.observe_step(t0, h, w1, |w, theta| {
            self.dense_at(theta)?;
            Ok::<f64, Error>(w.measure(self.system, t0 + theta * h, &self.state.y_dense[..n]))
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
                if !self.state.dense_ready {
                    let mut rhs = Rhs {
                        system: self.system,
                        dynamics: &mut self.dynamics,
                        n: self.n,
                        onto: self.stage.as_mut(),
                    };
                    rk.prepare_dense(&mut rhs, self.clock.t, &self.state.y, &self.state.y_new, h)?;
                }
                rk.dense(theta, &mut self.state.y_dense);
            }
            Stepper::Hht {
                hermite, f0, f1, ..
            } => {
                if !self.state.dense_ready {
                    hermite.set_hermite(&self.state.y, &self.state.y_new, f0, f1, h);
                }
                hermite.eval(theta, &mut self.state.y_dense);
            }
        }
        self.state.dense_ready = true;
        Ok(())
    }

    fn last_h(&self) -> f64 {
        self.clock.h_step
    }

    /// Projects `y_dense` when the stabilisation is projection, solves the augmented system
    /// there and appends the sample at time `ts`.
    fn record(&mut self, ts: f64) -> Result<(), Error> {
        let n = self.n;
        let (q, rest) = self.state.y_dense.split_at_mut(n);
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
        let t0 = self.clock.t;
        for i in 0..events.len() {
            self.events.roots[i] = f64::NAN;
            let g = &events[i].g;
            let g0 = self.events.g_old[i];
            let g1 = g(t0 + h, &self.state.y_new[..n], &self.state.y_new[n..2 * n]);
            if g0 == 0.0 || !(g0 * g1 <= 0.0) {
                continue;
            }
            let b = illinois(g0, g1, h, t0, |c| {
                self.dense_at(c)?;
                let y = &self.state.y_dense;
                Ok(g(t0 + c * h, &y[..n], &y[n..2 * n]))
            })?;
            self.events.roots[i] = t0 + b * h;
            if events[i].action == EventAction::Stop && self.events.roots[i] < *t_stop {
                *t_stop = self.events.roots[i];
                *stop_event = Some(i);
            }
        }
        self.record_crossings(h, *t_stop)
    }

    /// Records the located crossings up to t_stop, in time order (projected onto the
    /// constraints when the stabilisation is projection).
    fn record_crossings(&mut self, h: f64, t_stop: f64) -> Result<(), Error> {
        let (n, t0) = (self.n, self.clock.t);
        loop {
            let roots = &self.events.roots;
            let best = (0..roots.len())
                .filter(|&i| roots[i].is_finite() && roots[i] <= t_stop)
                .min_by(|&a, &b| roots[a].total_cmp(&roots[b]));
            let Some(i) = best else { break };
            let tr = self.events.roots[i];
            self.events.roots[i] = f64::NAN;
            self.dense_at(((tr - t0) / h).clamp(0.0, 1.0))?;
            let (q, rest) = self.state.y_dense.split_at_mut(n);
            if self.options.stabilization == Stabilization::Projection {
                self.projector.project(self.system, tr, q, &mut rest[..n])?;
            }
            self.events.hits.push(EventHit {
                event: i,
                t: tr,
                q: q.to_vec(),
                qd: rest[..n].to_vec(),
            });
        }
        Ok(())
    }
}

/// Failures of a trial step that a smaller step may avoid (see
/// [`Simulator::step`]): an entry of the equations or a solve that is not finite, a
/// projection that does not converge, a motion that is undetermined there.
fn is_trial_failure(e: &Error) -> bool {
    matches!(
        e,
        Error::NonFiniteTerm { .. }
            | Error::NonFinite { .. }
            | Error::NewtonDidNotConverge { .. }
            | Error::UndeterminedMotion { .. }
    )
}

/// Parameters finite; t_end > t_start, output_rate > 0, rtol > 0 and atol >= 0 finite.
fn check_options(system: &dyn System, options: &SimulationOptions) -> Result<(), Error> {
    let info = system.info();
    let mut params = vec![0.0; info.parameters.len()];
    system.parameter_values(&mut params);
    Error::check_finite(&params, "parameter", &info.parameters, options.t_start)?;
    let io = &options.integrator;
    let bad = |option, value, allowed| {
        Err(Error::InvalidOption {
            option,
            value,
            allowed,
        })
    };
    if !(options.t_end > options.t_start) {
        return bad("t_end", options.t_end, "after t_start");
    }
    if !(options.output_rate > 0.0) {
        return bad(
            "output_rate",
            options.output_rate,
            "positive, in samples per second",
        );
    }
    if !(io.rtol > 0.0 && io.rtol.is_finite()) {
        return bad("rtol", io.rtol, "positive and finite");
    }
    if !(io.atol >= 0.0 && io.atol.is_finite()) {
        return bad("atol", io.atol, "zero or positive, and finite");
    }
    Ok(())
}

/// Output samples after the first: one per 1/output_rate, the end time always included;
/// refused beyond [`MAX_OUTPUT_SAMPLES`] before any work.
fn output_count(options: &SimulationOptions) -> Result<usize, Error> {
    let span = options.t_end - options.t_start;
    // t_end > t_start and rate > 0 are checked, so this is not NaN.
    let samples = ((span * options.output_rate) - 1e-9).ceil().max(1.0);
    if samples > MAX_OUTPUT_SAMPLES as f64 {
        return Err(Error::TooManySamples {
            span,
            rate: options.output_rate,
            samples,
            limit: MAX_OUTPUT_SAMPLES,
        });
    }
    Ok(samples as usize)
}

/// q(t0) and q'(t0): assembled from the declared or given independent coordinates, or the
/// consistent state given (its consistency is checked after the first solve).
fn initial_state(
    system: &dyn System,
    options: &SimulationOptions,
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let info = system.info();
    let (n, t0) = (info.n(), options.t_start);
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
            for (what, v) in [("q", q), ("q'", qd)] {
                if v.len() != n {
                    return Err(Error::WrongLength {
                        what,
                        expected: n,
                        got: v.len(),
                    });
                }
            }
            (q.clone(), qd.clone())
        }
    };
    Error::check_finite(&q, "initial position", &info.coordinates, t0)?;
    Error::check_finite(&qd, "initial rate", &info.coordinates, t0)?;
    Ok((q, qd))
}

/// The stepper of the chosen method for the state `y` (HHT starts from the accelerations
/// and multipliers of the first solve).
fn make_stepper(
    system: &dyn System,
    options: &SimulationOptions,
    t0: f64,
    y: &[f64],
    dynamics: &Dynamics,
) -> Result<Stepper, Error> {
    let info = system.info();
    let (n, dim) = (info.n(), y.len());
    Ok(match options.integrator.method {
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
        Method::Rk4 { .. } => Stepper::Explicit(Box::new(Rk4::new(dim))),
        Method::Dopri5 => Stepper::Explicit(Box::new(Dopri5::new(dim))),
        Method::Dop853 => Stepper::Explicit(Box::new(Dop853::new(dim))),
    })
}

/// The root of g on the step, as a fraction of it, by the Illinois variant of regula falsi
/// (Dowell & Jarratt 1971) from g(0) = g0 and g(1) = g1 of opposite signs, to 4 eps of t;
/// `g(c)` evaluates g at t0 + c h on the dense output.
fn illinois(
    g0: f64,
    g1: f64,
    h: f64,
    t0: f64,
    mut g: impl FnMut(f64) -> Result<f64, Error>,
) -> Result<f64, Error> {
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
        let fc = g(c)?;
        if fc == 0.0 {
            return Ok(c);
        }
        // Keep the bracket; halve the retained end's value when it is kept twice.
        if (fc > 0.0) == (fb > 0.0) {
            (b, fb) = (c, fc);
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            (a, fa) = (c, fc);
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    Ok(b)
}
