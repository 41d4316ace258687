//! The right-hand side y' = f(t, y) of the simulation in y = [q, q', W], through the
//! augmented system, and the projection of its stage states where the constraints have
//! redundant rows.

use crate::algorithms::dynamics::Dynamics;
use crate::algorithms::stabilization::Projector;
use crate::error::Error;
use crate::integrators::{OdeRhs, Tolerance};
use crate::system::System;

/// Largest projection, in units of the error tolerance (see [`projection_size`]), after
/// which the next step of an adaptive method still starts from the last stage's f(y_new)
/// instead of a new right-hand side at the projected state. 1: the projection moved y by
/// no more than a local error the step-size control accepts, so the reused derivative is
/// off by at most L times that (L the Lipschitz constant of f), and the next step's result
/// by h L times it, below its own truncation error wherever the step is accurate
/// (h L < 1). It saves one right-hand side per accepted step (BENCHMARKS.md).
pub(crate) const REUSE_AFTER_PROJECTION: f64 = 1.0;

/// max_i |y_i - before_i| / (atol + rtol max(|y_i|, |before_i|)) over the positions and
/// rates: how far the projection moved the state, in units of the error tolerance.
pub(crate) fn projection_size(y: &[f64], before: &[f64], tol: Tolerance) -> f64 {
    y.iter()
        .zip(before)
        .fold(0.0, |m, (a, b)| m.max((a - b).abs() / tol.scale(*a, *b)))
}

/// When the stage states of a step are projected onto Phi = 0 and Phi_q q' = -Phi_t
/// (stabilisation by projection only): at every stage where the constraints have redundant
/// rows, and on the steps near a singular position otherwise.
///
/// Why, with redundant rows: Phi_q off the constraint manifold regains full rank with a
/// smallest singular value proportional to the distance d from it, and the row's part of
/// gamma is proportional to d too. Once d exceeds the rank tolerance of the augmented
/// solve (1e-6 relative), the solve treats the row as independent and q'' gains a
/// component of order 1 along the near-null direction, which throws the next Runge-Kutta
/// stage further off the manifold; at a loose tolerance the run diverges or rejects most
/// of its steps (RELIABILITY.md records Bricard's case).
///
/// Why, near a singular position: there q'' at a state off the manifold by eps (a stage's
/// own truncation error, 1e-9 and more) differs from q'' on it by about eps / w^3 (w the
/// weakest row independence, ~ |t - t*|): the motion on the level set Phi = eps turns onto
/// another branch at the crossing (`stepper/passage.rs`). On the manifold eps is round-off.
///
/// f evaluated at the projected stage, f(P(y)), is as smooth as the constraints near the
/// manifold and equal to f on it, where the exact solution stays: the integrated solution
/// is the same, and the error estimate measures the truncation error. The driver switches
/// between f and f(P(y)) only between steps, so that each step integrates one function.
pub(crate) struct StageProjection {
    q: Vec<f64>,
    qd: Vec<f64>,
    /// Every stage (redundant rows), or only while `near` is set.
    always: bool,
    near: bool,
}

impl StageProjection {
    /// Workspace for `n` coordinates; `always` for constraints with redundant rows.
    pub(crate) fn new(n: usize, always: bool) -> Self {
        Self {
            q: vec![0.0; n],
            qd: vec![0.0; n],
            always,
            near: false,
        }
    }
}

/// y' = [q', q'', tau . q' + lambda . Phi_t] through the augmented system (at the projected
/// state when the stages are projected: see [`StageProjection`]): W integrates the power
/// of the applied forces and of the moving constraint rows
/// ([`Dynamics::constraint_power`]). Built once per run; it owns the run's [`Dynamics`],
/// whose last solve the driver reads for its samples, and the run's [`Projector`], which
/// the driver uses for the accepted states and the samples.
pub(crate) struct Rhs<'s> {
    pub(crate) system: &'s dyn System,
    pub(crate) dynamics: Dynamics,
    pub(crate) projector: Projector,
    n: usize,
    stages: Option<StageProjection>,
    /// Set at the first solve whose Phi_t is not zero: from then on every solve computes
    /// the multipliers that the constraint power needs (rows that do not move with t,
    /// the common case, never pay for them).
    moving: bool,
}

impl<'s> Rhs<'s> {
    /// The right-hand side of `system` with `n` coordinates, solved by `dynamics`, its
    /// stage states projected by `projector` as `stages` says (`None`: never).
    pub(crate) fn new(
        system: &'s dyn System,
        dynamics: Dynamics,
        projector: Projector,
        n: usize,
        stages: Option<StageProjection>,
    ) -> Self {
        Self {
            system,
            dynamics,
            projector,
            n,
            stages,
            moving: false,
        }
    }

    /// Whether the next steps start near a singular position (their stages are then
    /// projected, when the run projects at all).
    pub(crate) fn near_singular(&mut self, near: bool) {
        if let Some(s) = self.stages.as_mut() {
            s.near = near;
        }
    }
}

impl OdeRhs for Rhs<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let n = self.n;
        let (q, qd) = match self.stages.as_mut().filter(|p| p.always || p.near) {
            Some(p) => {
                p.q.copy_from_slice(&y[..n]);
                p.qd.copy_from_slice(&y[n..2 * n]);
                self.projector
                    .project_stage(self.system, t, &mut p.q, &mut p.qd)?;
                (&p.q[..], &p.qd[..])
            }
            None => (&y[..n], &y[n..2 * n]),
        };
        if self.moving {
            self.dynamics.solve(self.system, t, q, qd)?;
        } else {
            self.dynamics.solve_accelerations(self.system, t, q, qd)?;
            if self.dynamics.constraints_move() {
                self.moving = true;
                self.dynamics.solve(self.system, t, q, qd)?;
            }
        }
        dy[..n].copy_from_slice(qd);
        dy[n..2 * n].copy_from_slice(self.dynamics.accelerations());
        dy[2 * n] = self.dynamics.power(qd);
        if self.moving {
            dy[2 * n] += self.dynamics.constraint_power();
        }
        Ok(())
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
