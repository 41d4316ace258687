//! The integrator as the simulation driver holds it: the right-hand side through the
//! augmented system, the explicit Runge-Kutta or HHT stepper, and the step-size control
//! state.

use crate::algorithms::dynamics::Dynamics;
use crate::algorithms::stabilization::Projector;
use crate::error::Error;
use crate::integrators::{Dense, Hht, OdeRhs, RungeKutta, Tolerance};
use crate::system::System;

/// Largest projection, in units of the error tolerance (see [`projection_size`]), after
/// which the next step of an adaptive method still starts from the last stage's f(y_new)
/// instead of a new right-hand side at the projected state. 1: the projection moved y by no more than a
/// local error the step-size control accepts, so the reused derivative is off by at most
/// L times that (L the Lipschitz constant of f), and the next step's result by h L times
/// it, below its own truncation error wherever the step is accurate (h L < 1). On the
/// seed this saves one right-hand side of the 13 per accepted DOP853 step, with the same
/// steps and a change of the result at 10 s a thousand times below its error.
pub(crate) const REUSE_AFTER_PROJECTION: f64 = 1.0;

/// max_i |y_i - before_i| / (atol + rtol max(|y_i|, |before_i|)) over the positions and
/// rates: how far the projection moved the state, in units of the error tolerance.
pub(crate) fn projection_size(y: &[f64], before: &[f64], tol: Tolerance) -> f64 {
    y.iter()
        .zip(before)
        .fold(0.0, |m, (a, b)| m.max((a - b).abs() / tol.scale(*a, *b)))
}

/// The projection of every stage state onto Phi = 0 and Phi_q q' = -Phi_t, used when the
/// constraints have redundant rows and the stabilisation is projection.
///
/// Why: with a redundant row (Bricard's 30 rows of rank 29 on the constraint manifold),
/// Phi_q off the manifold regains full rank with a smallest singular value proportional to
/// the distance d from it, and the row's part of gamma is proportional to d too. Once d
/// exceeds the rank tolerance of the augmented solve (1e-6 relative), the solve treats the
/// row as independent and q'' gains a component of order 1 along the near-null direction:
/// perturbing Bricard's state by 1e-6 changes q'' by 9e-6, by 1e-4 changes it by 1.8. A
/// Runge-Kutta stage of a step at a loose tolerance lies that far off the manifold; its
/// spurious acceleration throws the next stage further off, and at rtol = atol = 1e-6 the
/// run grew to 1e77 within one step (at 1e-7 to 1e-9 it was instead held back by rejected
/// steps: 30 to 48 % of them, more steps than at 1e-10). Evaluating f at the projected
/// stage, f(P(y)), gives a right-hand side as smooth as the constraints near the manifold,
/// equal to f on it, where the exact solution stays: the integrated solution is the same,
/// and the error estimate measures the truncation error again.
pub(crate) struct StageProjection {
    projector: Projector,
    q: Vec<f64>,
    qd: Vec<f64>,
}

impl StageProjection {
    /// A workspace for `n` coordinates and the projector of the system.
    pub(crate) fn new(projector: Projector, n: usize) -> Self {
        Self {
            projector,
            q: vec![0.0; n],
            qd: vec![0.0; n],
        }
    }
}

/// y' = [q', q'', tau . q'] through the augmented system (at the projected state when
/// `onto` is set: see [`StageProjection`]).
pub(crate) struct Rhs<'s> {
    pub(crate) system: &'s dyn System,
    pub(crate) dynamics: &'s mut Dynamics,
    pub(crate) n: usize,
    pub(crate) onto: Option<&'s mut StageProjection>,
}

impl OdeRhs for Rhs<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let n = self.n;
        let (q, qd) = match self.onto.as_deref_mut() {
            Some(p) => {
                p.q.copy_from_slice(&y[..n]);
                p.qd.copy_from_slice(&y[n..2 * n]);
                p.projector.project(self.system, t, &mut p.q, &mut p.qd)?;
                (&p.q[..], &p.qd[..])
            }
            None => (&y[..n], &y[n..2 * n]),
        };
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_size_is_in_units_of_the_tolerance() {
        let tol = Tolerance {
            rtol: 1e-6,
            atol: 1e-9,
        };
        // Scales 1e-9 + 1e-6 * 2 and 1e-9 + 1e-6 * 2e-9: moves of 1.0005e-6 (0.5 scales)
        // and 2e-9 (just under 2 scales, the larger).
        let before = [2.0, 0.0];
        let y = [2.0 - 1.0005e-6, 2e-9];
        let want = 2e-9 / (1e-9 + 1e-6 * 2e-9);
        let s = projection_size(&y, &before, tol);
        assert!(
            (s - want).abs() <= 4.0 * f64::EPSILON * want,
            "{s} vs {want}"
        );
        assert!(projection_size(&before, &before, tol) == 0.0);
        // atol = 0 and an exact zero: no movement, not 0 / 0.
        let pure = Tolerance {
            rtol: 1e-6,
            atol: 0.0,
        };
        assert_eq!(projection_size(&[0.0, 1.0], &[0.0, 1.0], pure), 0.0);
    }
}
