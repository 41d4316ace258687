//! RK4, DOPRI5 and DOP853 as a [`Stepper`]: the Runge-Kutta method of
//! [`crate::integrators`], the step-size control of the adaptive ones (Hairer's PI
//! controller, optionally capped by Gustafsson's predictive step: [`StepController`]) and
//! the method's own dense output.

// Comparisons are written `!(x > 0.0)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::passage::{ends_too_near, steer, straddles, widest_gap};
use super::{Stepper, fixed_first_step, trial_step};
use crate::error::Error;
use crate::integrators::{
    IntegratorOptions, OdeRhs, RungeKutta, StepController, Tolerance, initial_step,
};
use crate::simulation::rhs::{REUSE_AFTER_PROJECTION, Rhs};

/// Step-size control state of an adaptive method.
#[derive(Clone, Copy)]
struct StepControl {
    /// Next step size to try (s).
    h: f64,
    /// Error norm of the last accepted step (PI controller).
    errold: f64,
    /// The last attempt was rejected (no growth on the next).
    rejected_last: bool,
    /// Size and error norm of the last accepted step (the predictive controller's memory;
    /// h_acc = 0 before the first).
    h_acc: f64,
    err_acc: f64,
}

impl StepControl {
    fn new() -> Self {
        Self {
            h: 0.0,
            errold: 1e-4,
            rejected_last: false,
            h_acc: 0.0,
            err_acc: 1e-2,
        }
    }

    /// Gustafsson's predictive step factor h_new / h after accepting a step of size `h`
    /// with error norm `err` (exponent `k`): 0.9 (h / h_acc) (err_acc / err^2)^k, or
    /// infinite for the first step; then remembers h and err (see [`StepController`]).
    fn predictive(&mut self, h: f64, err: f64, k: f64) -> f64 {
        let err = err.max(1e-10);
        let fac = if self.h_acc > 0.0 {
            0.9 * (h / self.h_acc) * (self.err_acc / (err * err)).powf(k)
        } else {
            f64::INFINITY
        };
        self.h_acc = h;
        self.err_acc = err.max(1e-2);
        fac
    }

    /// After a step of size `h` with error norm `err` <= 1 is accepted: the next size
    /// (unchanged when `last`), h_new = h clamp(0.9 err^-expo errold^beta, 0.2, growth),
    /// capped by the predictive step and by 1 after a rejection.
    fn accepted(
        &mut self,
        rk: &dyn RungeKutta,
        controller: StepController,
        h: f64,
        err: f64,
        last: bool,
    ) {
        let expo = rk.exponent();
        let mut fac = 0.9 * err.max(1e-10).powf(-expo) * self.errold.powf(rk.pi_beta());
        if controller == StepController::Predictive {
            let k = expo + 0.2 * rk.pi_beta();
            fac = fac.min(self.predictive(h, err, k));
        }
        fac = fac.clamp(0.2, rk.max_growth());
        if self.rejected_last {
            fac = fac.min(1.0);
        }
        self.errold = err.max(1e-4);
        self.rejected_last = false;
        if !last {
            self.h = h * fac;
        }
    }

    /// After a trial of size `h` is rejected with error norm `err` (> 1, or not finite):
    /// the next trial's size, h max(0.9 err^-expo, 0.2) (0.2 h for an error norm that is
    /// not finite).
    fn rejected(&mut self, expo: f64, h: f64, err: f64) {
        self.rejected_last = true;
        let fac = if err.is_finite() {
            (0.9 * err.powf(-expo)).max(0.2)
        } else {
            0.2
        };
        self.h = h * fac;
    }
}

/// An explicit Runge-Kutta method with its step control and dense output.
pub(super) struct Explicit {
    rk: Box<dyn RungeKutta>,
    /// The fixed step (RK4), or `None` for an adaptive method.
    fixed: Option<f64>,
    /// Order of the adaptive method's solution, for the starting step (8 or 5).
    order: f64,
    control: StepControl,
    /// The control as it was before the last [`Stepper::advance`], for a retaken step.
    control_before: StepControl,
    options: IntegratorOptions,
    tol: Tolerance,
    /// Size of the last accepted step, and whether its dense output is built.
    h_step: f64,
    dense_ready: bool,
    /// Scratch for the starting-step estimate.
    scratch: Vec<f64>,
    /// The widest interval of (0, 1) between the method's nodes, and the singular position
    /// predicted ahead (see [`Stepper::steer`]).
    gap: (f64, f64),
    crossing: Option<f64>,
    /// Whether a straddle of the passage ahead was rejected with the control's size
    /// spared (see [`Stepper::advance`]); cleared when no singular position is predicted.
    spared: bool,
}

impl Explicit {
    /// A fixed-step method with step `h`.
    pub(super) fn fixed(
        rk: Box<dyn RungeKutta>,
        h: f64,
        options: &IntegratorOptions,
        tol: Tolerance,
    ) -> Self {
        Self::new(rk, Some(h), 0.0, options, tol)
    }

    /// An adaptive method whose solution has order `order`.
    pub(super) fn adaptive(
        rk: Box<dyn RungeKutta>,
        order: f64,
        options: &IntegratorOptions,
        tol: Tolerance,
    ) -> Self {
        Self::new(rk, None, order, options, tol)
    }

    fn new(
        mut rk: Box<dyn RungeKutta>,
        fixed: Option<f64>,
        order: f64,
        options: &IntegratorOptions,
        tol: Tolerance,
    ) -> Self {
        let dim = rk.k1_mut().len();
        let gap = widest_gap(rk.nodes());
        Self {
            rk,
            fixed,
            order,
            control: StepControl::new(),
            control_before: StepControl::new(),
            options: *options,
            tol,
            h_step: 0.0,
            dense_ready: false,
            scratch: vec![0.0; 2 * dim],
            gap,
            crossing: None,
            spared: false,
        }
    }
}

/// Failures of a trial step that a smaller step may avoid: an entry of the equations or a
/// solve that is not finite, a projection that does not converge, a motion that is
/// undetermined there.
fn is_trial_failure(e: &Error) -> bool {
    matches!(
        e,
        Error::NonFiniteTerm { .. }
            | Error::NonFinite { .. }
            | Error::NewtonDidNotConverge { .. }
            | Error::UndeterminedMotion { .. }
    )
}

impl Stepper for Explicit {
    fn start(&mut self, rhs: &mut Rhs<'_>, t: f64, y: &[f64], span: f64) -> Result<f64, Error> {
        if let Some(h) = self.fixed {
            let h = fixed_first_step(h, span)?;
            rhs.rhs(t, y, self.rk.k1_mut())?;
            self.control.h = h;
            return Ok(h);
        }
        let io = &self.options;
        let h_max = io.h_max.unwrap_or(span).min(span);
        rhs.rhs(t, y, self.rk.k1_mut())?;
        let h = match io.h_initial {
            Some(h) => h.min(h_max),
            None => {
                let f0 = self.rk.k1_mut().to_vec(); // before the loop: allowed
                initial_step(
                    rhs,
                    t,
                    y,
                    &f0,
                    self.order,
                    self.tol,
                    h_max,
                    &mut self.scratch,
                )?
            }
        };
        self.control.h = h;
        Ok(h)
    }

    fn advance(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        t_end: f64,
        y: &[f64],
        y_new: &mut [f64],
        rejected: &mut usize,
    ) -> Result<f64, Error> {
        self.dense_ready = false;
        self.control_before = self.control;
        let io = self.options;
        let h_max = io.h_max.unwrap_or(f64::INFINITY);
        let adaptive = self.rk.adaptive();
        let mut straddle_rejected = false;
        loop {
            // Ahead of a predicted singular position, the step that passes it puts it
            // between two nodes, and no step ends just before it (`passage.rs`).
            let ahead = self
                .crossing
                .map(|ts| ts - t)
                .filter(|&d| adaptive && d > 0.0);
            let control_h = self.control.h;
            let wanted = match ahead {
                Some(d) => steer(control_h, d, self.gap, straddle_rejected),
                None => control_h,
            };
            let (h, last) = trial_step(wanted, h_max, t, t_end);
            let straddling = ahead.is_some_and(|d| straddles(h, d));
            let err = match self.rk.attempt(rhs, t, y, h, y_new, self.tol) {
                Ok(err) => err,
                // A stage that cannot be evaluated (a non-finite entry, a projection or
                // solve failing far from the last state) rejects the step like an error
                // norm above 1: a smaller step takes its stages closer. A failure that
                // persists down to h_min is returned.
                Err(e) if adaptive && is_trial_failure(&e) => {
                    straddle_rejected |= straddling;
                    *rejected += 1;
                    self.control.rejected_last = true;
                    self.control.h = h * 0.2;
                    if self.control.h < io.h_min {
                        return Err(e);
                    }
                    continue;
                }
                Err(e) => return Err(e),
            };
            if !adaptive || (err <= 1.0 && err.is_finite()) {
                self.rk.finish(rhs, t, y_new, h)?;
                if adaptive {
                    self.control
                        .accepted(self.rk.as_ref(), io.controller, h, err, last);
                    if straddle_rejected && wanted < control_h && !last {
                        // The approach after a rejected straddle, shortened to end before
                        // t*, says nothing against the size the control asked for: the
                        // next step may have that size (shrunk as this step's error
                        // asks). A straddle rejected because t* was mispredicted (A02,
                        // N = 5: by 0.01 s from 0.045 s away) is then followed by one of
                        // about the control's size, placed by the prediction made nearer
                        // to t*, instead of one capped by the approach, whose stages fall
                        // so near t* that it fails on the noise of f there.
                        let shrink = (self.control.h / h).min(1.0);
                        self.control.h = self.control.h.max(control_h * shrink);
                    }
                }
                self.h_step = h;
                return Ok(h);
            }
            *rejected += 1;
            straddle_rejected |= straddling;
            if straddling && !self.spared {
                // The first straddle of a passage rejected leaves the control's size as it
                // was: its t* came from a prediction made farther away (A02: 0.013 to
                // 0.018 s off, onto a node), and the straddle placed by the prediction the
                // approach step makes needs that size (a shorter one fails on the noise
                // of f near t*; `passage.rs`). The approach step ends before t* anyway.
                self.spared = true;
                self.control.rejected_last = true;
            } else {
                self.control.rejected(self.rk.exponent(), h, err);
            }
            if self.control.h < io.h_min {
                return Err(Error::StepSizeUnderflow {
                    t,
                    h: self.control.h,
                });
            }
        }
    }

    fn projects(&self) -> bool {
        true
    }

    fn restart(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        y: &[f64],
        moved: Option<f64>,
    ) -> Result<(), Error> {
        // Only an adaptive method has an accepted local error to measure the projection
        // against: RK4 (fixed step, rtol and atol unused) always evaluates afresh.
        let reuse = match moved {
            None => true,
            Some(size) => self.rk.adaptive() && size <= REUSE_AFTER_PROJECTION,
        };
        if reuse {
            // The step's last stage f(y_new) serves as the next step's first (FSAL). After
            // a projection that moved y by at most the accepted local error, it differs
            // from f(projected y) by at most L times that error; its position rows take
            // the projected q' exactly.
            self.rk.reuse_f_new();
            if moved.is_some() {
                let n = (y.len() - 1) / 2; // y = [q, q', W]
                self.rk.k1_mut()[..n].copy_from_slice(&y[n..2 * n]);
            }
            Ok(())
        } else {
            rhs.rhs(t, y, self.rk.k1_mut())
        }
    }

    fn dense(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        y: &[f64],
        y_new: &[f64],
        theta: f64,
        out: &mut [f64],
    ) -> Result<(), Error> {
        if !self.dense_ready {
            self.rk.prepare_dense(rhs, t, y, y_new, self.h_step)?;
            self.dense_ready = true;
        }
        self.rk.dense(theta, out);
        Ok(())
    }

    fn dense_built(&self) -> bool {
        self.dense_ready
    }

    fn steer(&mut self, crossing: Option<f64>) {
        self.crossing = crossing;
        if crossing.is_none() {
            self.spared = false;
        }
    }

    fn retakes(&self) -> bool {
        self.rk.adaptive()
    }

    fn retake(&mut self, t: f64, h: f64, crossing: f64) -> bool {
        if !self.rk.adaptive() || !ends_too_near(h, crossing - (t + h), self.gap) {
            return false;
        }
        // The first stage f(y) is untouched by the trials, the accepted step and its dense
        // output (they write the other stages and y_new), so the step restarts from (t, y)
        // as it was. The retaken step projects its stages (the driver sets that); y, the
        // accepted state, is projected already, so f(y) is f(P(y)) to round-off.
        self.control = self.control_before;
        self.crossing = Some(crossing);
        true
    }

    fn own_evaluations(&self) -> usize {
        0
    }
}
