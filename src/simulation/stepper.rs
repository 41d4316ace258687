//! The integrator as the simulation driver holds it: the right-hand side through the
//! augmented system, the explicit Runge-Kutta or HHT stepper, and the step-size control
//! state.

use crate::algorithms::dynamics::Dynamics;
use crate::error::Error;
use crate::integrators::{Dense, Hht, OdeRhs, RungeKutta};
use crate::system::System;

/// y' = [q', q'', tau . q'] through the augmented system.
pub(crate) struct Rhs<'s> {
    pub(crate) system: &'s dyn System,
    pub(crate) dynamics: &'s mut Dynamics,
    pub(crate) n: usize,
}

impl OdeRhs for Rhs<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let n = self.n;
        let (q, rest) = y.split_at(n);
        let qd = &rest[..n];
        self.dynamics.solve_accelerations(self.system, t, q, qd)?;
        dy[..n].copy_from_slice(qd);
        dy[n..2 * n].copy_from_slice(self.dynamics.accelerations());
        dy[2 * n] = self.dynamics.power(qd);
        Ok(())
    }
}

/// The stepper of the chosen method.
pub(crate) enum Stepper {
    /// RK4, DOPRI5 or DOP853 (with error estimate and dense output).
    Explicit(Box<dyn RungeKutta>),
    /// HHT-alpha, with a cubic Hermite dense output from the step's end values.
    Hht {
        hht: Box<Hht>,
        hermite: Dense,
        f0: Vec<f64>,
        f1: Vec<f64>,
        power: f64,
    },
}

/// Time and step-size control of a run.
pub(crate) struct StepControl {
    /// Current time (s).
    pub(crate) t: f64,
    /// Next step size to try (s).
    pub(crate) h: f64,
    /// Size of the last accepted step (s).
    pub(crate) h_step: f64,
    /// Error norm of the last accepted step (PI controller).
    pub(crate) errold: f64,
    /// The last attempt was rejected (no growth on the next).
    pub(crate) rejected_last: bool,
    /// Size and error norm of the last accepted step (the predictive controller's memory;
    /// h_acc = 0 before the first).
    pub(crate) h_acc: f64,
    pub(crate) err_acc: f64,
    /// The end time or a stopping event was reached.
    pub(crate) finished: bool,
}

impl StepControl {
    /// Control state at t0.
    pub(crate) fn new(t0: f64) -> Self {
        Self {
            t: t0,
            h: 0.0,
            h_step: 0.0,
            errold: 1e-4,
            rejected_last: false,
            h_acc: 0.0,
            err_acc: 1e-2,
            finished: false,
        }
    }

    /// Gustafsson's predictive step factor h_new / h after accepting a step of size `h`
    /// with error norm `err` (exponent `k`): 0.9 (h / h_acc) (err_acc / err^2)^k, or
    /// infinite for the first step; then remembers h and err (see
    /// [`crate::StepController`]).
    pub(crate) fn predictive(&mut self, h: f64, err: f64, k: f64) -> f64 {
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
}

/// The state vectors y = [q, q', W] the driver works on, allocated once.
pub(crate) struct StateBuffers {
    /// y at the current time.
    pub(crate) y: Vec<f64>,
    /// y at the end of the step being taken.
    pub(crate) y_new: Vec<f64>,
    /// y from the dense output (samples, events, passages).
    pub(crate) y_dense: Vec<f64>,
    /// Scratch for the starting-step estimate.
    pub(crate) scratch: Vec<f64>,
    /// The dense output of the last step is built.
    pub(crate) dense_ready: bool,
}

impl StateBuffers {
    /// Buffers initialised to `y`.
    pub(crate) fn new(y: Vec<f64>) -> Self {
        let dim = y.len();
        Self {
            y_new: y.clone(),
            y_dense: y.clone(),
            scratch: vec![0.0; 2 * dim],
            y,
            dense_ready: false,
        }
    }
}
