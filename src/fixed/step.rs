//! One fixed step of the index-1 equations with projection onto the constraints.

use nalgebra::{SMatrix, SVector};

use super::FixedError;
use super::cholesky::Cholesky;
use crate::Mechanism;

/// The rows of Phi_q Phi_q^T whose pivot falls below this fraction are redundant (the same
/// relative distance 1e-6 as the run-time rank test, squared).
const REDUNDANT: f64 = 1e-12;

/// Time and state (q, q') of a mechanism with static sizes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State<const N: usize> {
    /// Time t, s.
    pub t: f64,
    /// Coordinates q.
    pub q: SVector<f64, N>,
    /// Rates q'.
    pub qd: SVector<f64, N>,
}

/// The classical fourth-order Runge–Kutta step of y = (q, q'), y' = (q', q''(t, q, q')) with
/// q'' from [`Mechanism::constrained_dynamics`] (the dense [`kkt_solve`](super::kkt_solve),
/// or the solve that follows M's pattern), followed by projection back onto the constraint
/// manifold:
///
/// ```text
/// q  <- q - Phi_q^T (Phi_q Phi_q^T)^-1 Phi(q, t)        (Newton, to `tolerance`)
/// q' <- q' - Phi_q^T (Phi_q Phi_q^T)^-1 (Phi_q q' + Phi_t)
/// ```
///
/// (the nearest point in the Euclidean norm of q). The Runge–Kutta error is O(h^5) per step;
/// the projection removes the drift of Phi and Phi' that integrating the index-1 form alone
/// would accumulate, without changing the order. Four evaluations and four KKT solves per
/// step, no allocation, no std.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedStep {
    /// Step size h, s.
    pub h: f64,
    /// Projection stops when max |Phi_i| <= tolerance (in the units of Phi, usually m).
    pub tolerance: f64,
    /// Newton iterations allowed for the position projection.
    pub max_iterations: usize,
}

impl FixedStep {
    /// Steps of `h` seconds, projecting to max |Phi_i| <= 1e-12 in at most 10 iterations
    /// (Newton converges quadratically from the O(h^5) drift of one step: two or three).
    pub fn new(h: f64) -> Self {
        Self {
            h,
            tolerance: 1e-12,
            max_iterations: 10,
        }
    }

    /// Advances `state` by one step of h. On error `state` is left as it was.
    ///
    /// # Errors
    /// Those of [`kkt_solve`](super::kkt_solve) at a stage, and [`FixedError::ProjectionDidNotConverge`].
    pub fn step<S, const N: usize, const M: usize>(
        &self,
        mechanism: &S,
        state: &mut State<N>,
    ) -> Result<(), FixedError>
    where
        S: Mechanism<N, M>,
    {
        let (t, h) = (state.t, self.h);
        let accel = |t: f64, q: &SVector<f64, N>, qd: &SVector<f64, N>| {
            mechanism.constrained_dynamics(t, q, qd).map(|s| s.qdd)
        };
        let (q, qd) = (state.q, state.qd);
        let a1 = accel(t, &q, &qd)?;
        let (q2, v2) = (q + qd * (h / 2.0), qd + a1 * (h / 2.0));
        let a2 = accel(t + h / 2.0, &q2, &v2)?;
        let (q3, v3) = (q + v2 * (h / 2.0), qd + a2 * (h / 2.0));
        let a3 = accel(t + h / 2.0, &q3, &v3)?;
        let (q4, v4) = (q + v3 * h, qd + a3 * h);
        let a4 = accel(t + h, &q4, &v4)?;
        let t1 = t + h;
        let mut next = State {
            t: t1,
            q: q + (qd + v2 * 2.0 + v3 * 2.0 + v4) * (h / 6.0),
            qd: qd + (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0),
        };
        self.project(mechanism, &mut next)?;
        *state = next;
        Ok(())
    }

    /// Moves (q, q') to the nearest consistent state at `state.t` (in the Euclidean norm):
    /// Newton on Phi(q, t) = 0, then q' onto Phi_q q' + Phi_t = 0. Also what makes a
    /// declared initial guess consistent before the first step (all coordinates move,
    /// the independent ones included). On error `state` is left as it was.
    ///
    /// # Errors
    /// [`FixedError::ProjectionDidNotConverge`], [`FixedError::NotFinite`].
    pub fn project<S, const N: usize, const M: usize>(
        &self,
        mechanism: &S,
        state: &mut State<N>,
    ) -> Result<(), FixedError>
    where
        S: Mechanism<N, M>,
    {
        let (t, mut q, mut qd) = (state.t, state.q, state.qd);
        self.project_positions(mechanism, t, &mut q)?;
        project_velocities(mechanism, t, &q, &mut qd);
        if !(q.iter().chain(qd.iter()).all(|x| x.is_finite())) {
            return Err(FixedError::NotFinite { t });
        }
        *state = State { t, q, qd };
        Ok(())
    }

    /// Newton's iteration for Phi(q, t) = 0 by minimum-norm corrections.
    fn project_positions<S, const N: usize, const M: usize>(
        &self,
        mechanism: &S,
        t: f64,
        q: &mut SVector<f64, N>,
    ) -> Result<(), FixedError>
    where
        S: Mechanism<N, M>,
    {
        let mut phi = mechanism.constraints(t, q);
        for iterations in 0.. {
            let residual = phi.amax();
            if residual <= self.tolerance {
                break;
            }
            // (A NaN residual fails the test above and ends here too.)
            if iterations == self.max_iterations || !residual.is_finite() {
                return Err(FixedError::ProjectionDidNotConverge {
                    residual,
                    iterations,
                    t,
                });
            }
            let j = mechanism.constraint_jacobian(t, q);
            *q -= min_norm_correction(&j, &phi);
            phi = mechanism.constraints(t, q);
        }
        Ok(())
    }
}

/// q' <- q' minus its part that violates Phi_q q' + Phi_t = 0.
fn project_velocities<S, const N: usize, const M: usize>(
    mechanism: &S,
    t: f64,
    q: &SVector<f64, N>,
    qd: &mut SVector<f64, N>,
) where
    S: Mechanism<N, M>,
{
    let j = mechanism.constraint_jacobian(t, q);
    let violation = j * *qd + mechanism.constraint_time_derivative(t, q);
    *qd -= min_norm_correction(&j, &violation);
}

/// dx = J^T (J J^T)^-1 r, the smallest dx with J dx = r (redundant rows of J dropped).
fn min_norm_correction<const N: usize, const M: usize>(
    j: &SMatrix<f64, M, N>,
    r: &SVector<f64, M>,
) -> SVector<f64, N> {
    let gram = Cholesky::new(j * j.transpose(), REDUNDANT);
    j.transpose() * gram.solve(r)
}
