//! The integrator as the simulation driver holds it: one [`Stepper`] per run, which owns
//! its step-size control and its dense output, chosen once from the method
//! ([`stepper_for`]).
//!
//! What enters each call: the run's [`Rhs`] and the state y = [q, q', W] the driver owns.
//! What leaves: the accepted step's size and end state, and y anywhere inside that step.

mod explicit;
mod implicit;
mod passage;

use crate::algorithms::dynamics::Dynamics;
use crate::error::Error;
use crate::integrators::{Dop853, Dopri5, IntegratorOptions, Method, Rk4, Tolerance};
use crate::simulation::rhs::Rhs;
use crate::system::System;

use explicit::Explicit;
use implicit::HhtStepper;

/// A time stepper: step-size control, the steps and their continuous extension.
///
/// Protocol: [`Stepper::start`] once at t0; then per step [`Stepper::advance`] (which
/// retries rejected trials), [`Stepper::dense`] any number of times inside the accepted
/// step, and [`Stepper::restart`] at its end (after the driver's projection, if any).
/// Nothing allocates after [`stepper_for`].
pub(crate) trait Stepper {
    /// Checks the method's own options and returns the first step size, at most `span`;
    /// evaluates f(t, y) where the method starts from it.
    fn start(&mut self, rhs: &mut Rhs<'_>, t: f64, y: &[f64], span: f64) -> Result<f64, Error>;

    /// Tries steps from (t, y), the last one ending at `t_end`, until one is accepted;
    /// writes its end state into `y_new`, counts the rejected trials into `rejected` and
    /// returns the accepted size.
    fn advance(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        t_end: f64,
        y: &[f64],
        y_new: &mut [f64],
        rejected: &mut usize,
    ) -> Result<f64, Error>;

    /// True when the driver may project the accepted state onto the constraints (false
    /// for HHT, whose Newmark state (q, q', q'') projecting q' alone would break; its
    /// positions satisfy Phi = 0 to its Newton tolerance).
    fn projects(&self) -> bool;

    /// Starts the next step from the accepted state (t, y); `moved` is the size of the
    /// driver's projection of it ([`crate::simulation::rhs::projection_size`]), `None`
    /// when it was not projected.
    fn restart(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        y: &[f64],
        moved: Option<f64>,
    ) -> Result<(), Error>;

    /// y(t + theta h), 0 <= theta <= 1, on the last accepted step from (t, y) to `y_new`,
    /// into `out`; the continuous extension is built on the first call after a step.
    fn dense(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        y: &[f64],
        y_new: &[f64],
        theta: f64,
        out: &mut [f64],
    ) -> Result<(), Error>;

    /// Whether [`Stepper::dense`] inside the last accepted step evaluates no right-hand
    /// side now (its continuous extension is built, or costs none).
    fn dense_built(&self) -> bool;

    /// The singular position predicted ahead of the accepted state, t* (s), or `None`:
    /// an adaptive explicit method places its next steps so that no stage falls near it
    /// (`stepper/passage.rs`); a fixed-step method ignores it.
    fn steer(&mut self, _crossing: Option<f64>) {}

    /// Whether the step just taken from t, of size `h`, is to be taken again because a
    /// singular position predicted only after it, at `crossing`, lies just after its end
    /// (`stepper/passage.rs`: no step ends just before t*). If so the stepper restores its
    /// step control to what it was before the step and steers the next [`Stepper::advance`]
    /// from the same (t, y) by `crossing`; the driver has not accepted the step. A
    /// fixed-step method never retakes.
    fn retake(&mut self, _t: f64, _h: f64, _crossing: f64) -> bool {
        false
    }

    /// Whether [`Stepper::retake`] can ever be true (an adaptive explicit method): the
    /// driver predicts nothing for it otherwise.
    fn retakes(&self) -> bool {
        false
    }

    /// Right-hand sides evaluated outside `rhs` (HHT's Newton iterations), for the run's
    /// counters.
    fn own_evaluations(&self) -> usize;
}

/// The stepper of `io.method` for the state `y` at `t0`, the error measured against `tol`
/// (HHT starts from the accelerations and multipliers of the first solve, in `dynamics`).
pub(crate) fn stepper_for(
    system: &dyn System,
    io: &IntegratorOptions,
    tol: Tolerance,
    t0: f64,
    y: &[f64],
    dynamics: &Dynamics,
) -> Result<Box<dyn Stepper>, Error> {
    let dim = y.len();
    Ok(match io.method {
        Method::Rk4 { h } => Box::new(Explicit::fixed(Box::new(Rk4::new(dim)), h, io, tol)),
        Method::Dopri5 => Box::new(Explicit::adaptive(Box::new(Dopri5::new(dim)), 5.0, io, tol)),
        Method::Dop853 => Box::new(Explicit::adaptive(Box::new(Dop853::new(dim)), 8.0, io, tol)),
        Method::Hht { h, alpha } => {
            Box::new(HhtStepper::new(system, h, alpha, io, t0, y, dynamics)?)
        }
    })
}

/// A fixed step `h` checked positive, at most `span`.
fn fixed_first_step(h: f64, span: f64) -> Result<f64, Error> {
    // Written `!(h > 0.0)` on purpose: NaN must fail it.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if !(h > 0.0) {
        return Err(Error::InvalidOption {
            option: "h",
            value: h,
            allowed: "a positive step in seconds",
        });
    }
    Ok(h.min(span))
}

/// The size of a trial step from t: the next size `h` capped at `h_max`, and cut to end at
/// `t_end` when it reaches it to round-off (then also true: the run's last step).
fn trial_step(h: f64, h_max: f64, t: f64, t_end: f64) -> (f64, bool) {
    let h = h.min(h_max);
    let last = t + h >= t_end - 1e-12 * t_end.abs().max(1.0);
    if last { (t_end - t, true) } else { (h, false) }
}
