//! The derivatives of the forward dynamics with static sizes, for control and optimisation
//! on the robot's own computer: no allocation, no std.
//!
//! Without constraint rows, q'' = M^-1 (u - b(q, q')) with b = C q' + g - tau, and
//! differentiating M q'' + b = u at the q'' it gives (Carpentier & Mansard 2018):
//!
//! ```text
//! dq''/dq = -M^-1 dtau_id/dq,   dq''/dq' = -M^-1 dtau_id/dq',   dq''/du = M^-1,
//! ```
//!
//! with tau_id = M q'' + C q' + g - tau the inverse dynamics, whose derivatives the emitted
//! code computes ([`crate::Mechanism::inverse_dynamics_derivatives`]).
//!
//! With constraint rows the accelerations and multipliers solve the augmented system
//! ([`super::kkt_solve`]); differentiating both of its rows at the solution gives, for each
//! variable x among q, q' and the effort u, the same matrix with new right-hand sides:
//!
//! ```text
//! [ M      Phi_q^T ] [ dq''/dx    ]   [ -dF/dx ]     F = M q'' + C q' + g - tau - u + Phi_q^T lambda
//! [ Phi_q  0       ] [ dlambda/dx ] = [ -dR/dx ]     R = Phi_q q'' - gamma
//! ```
//!
//! dF/dq and dF/dq' are the residual's tangent ([`crate::Mechanism::residual_tangent`]),
//! dR/dq and dR/dq' the constraint rows' ([`crate::Mechanism::constraint_tangent`]);
//! dF/du = -1 and dR/du = 0. The one factorisation of [`super::kkt_solve`] serves all 3 N
//! right-hand sides. Redundant rows: q'' and its derivatives are unique; the multipliers
//! are not, and [`super::kkt_solve`] gives the rows it finds dependent on earlier ones
//! lambda = 0. The same rows get dlambda/dx = 0 here, and the others the derivatives of
//! their multipliers, so the result is the derivative of what [`super::kkt_solve`]
//! returns wherever the same rows stay dependent (of an overconstrained linkage like
//! Bricard's, along its motion).

use nalgebra::{SMatrix, SVector};

use super::FixedError;
use super::cholesky::Cholesky;
use super::kkt::KktFactors;
use crate::Mechanism;

/// q'', lambda and their derivatives by q, q' and the effort u at one (t, q, q', u): see
/// the module docs (row r of the multipliers' derivatives is zero where row r of the
/// constraints is redundant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KktDerivatives<const N: usize, const M: usize> {
    /// Accelerations q''.
    pub qdd: SVector<f64, N>,
    /// Multipliers lambda (constraint forces -Phi_q^T lambda; 0 on redundant rows).
    pub lambda: SVector<f64, M>,
    /// dq''/dq (N x N).
    pub dqdd_dq: SMatrix<f64, N, N>,
    /// dq''/dq' (N x N).
    pub dqdd_dqd: SMatrix<f64, N, N>,
    /// dq''/du (N x N): the response to an effort along the coordinates.
    pub dqdd_du: SMatrix<f64, N, N>,
    /// dlambda/dq (M x N).
    pub dlambda_dq: SMatrix<f64, M, N>,
    /// dlambda/dq' (M x N).
    pub dlambda_dqd: SMatrix<f64, M, N>,
    /// dlambda/du (M x N).
    pub dlambda_du: SMatrix<f64, M, N>,
}

/// A pivot below 1e-14 of M's largest diagonal entry: M is singular to round-off (the
/// tolerance of [`crate::Mechanism::forward_dynamics`]).
const SINGULAR: f64 = 1e-14;

/// (dq''/dq, dq''/dq', M^-1) of a mechanism without constraint rows at (t, q, q') and the
/// effort `effort` (module docs); `None` with constraint rows, where M is not positive
/// definite at q, or where a value is not finite.
pub fn forward_dynamics_derivatives<T, const N: usize, const M: usize>(
    mechanism: &T,
    t: f64,
    q: &SVector<f64, N>,
    qd: &SVector<f64, N>,
    effort: &SVector<f64, N>,
) -> Option<(SMatrix<f64, N, N>, SMatrix<f64, N, N>, SMatrix<f64, N, N>)>
where
    T: Mechanism<N, M>,
{
    if M != 0 {
        return None;
    }
    let (mass, bias) = mechanism.mass_and_bias(t, q, qd);
    let chol = Cholesky::new(mass, SINGULAR);
    if chol.first_dropped().is_some() {
        return None;
    }
    let qdd = chol.solve(&(effort - bias));
    // M^-1 = L^-T L^-1, its lower triangle computed and mirrored (exactly symmetric).
    let inverse = chol.inverse();
    let (dq, dqd) = mechanism.inverse_dynamics_derivatives(t, q, qd, &qdd);
    // -M^-1 dtau/dx by the factors: N^3 multiply-adds per matrix, as the product with M^-1.
    let (dq, dqd) = (-chol.solve_columns(&dq), -chol.solve_columns(&dqd));
    let finite = [&dq, &dqd, &inverse]
        .iter()
        .all(|m| all_finite(m.as_slice()));
    finite.then_some((dq, dqd, inverse))
}

/// q'', lambda and their derivatives by q, q' and u at (t, q, q') with the effort `effort`
/// added to the declared forces (module docs).
///
/// # Errors
/// [`FixedError::NotFinite`] for a NaN or infinity in the equations, their tangents or the
/// result; [`FixedError::UndeterminedMotion`] where M is singular on an allowed motion;
/// [`FixedError::TangentNotProvided`] for a mechanism without the residual's or the
/// constraint rows' tangent (a hand-written impl).
pub fn kkt_derivatives<T, const N: usize, const M: usize>(
    mechanism: &T,
    t: f64,
    q: &SVector<f64, N>,
    qd: &SVector<f64, N>,
    effort: &SVector<f64, N>,
) -> Result<KktDerivatives<N, M>, FixedError>
where
    T: Mechanism<N, M>,
{
    let mut e = mechanism.evaluate(t, q, qd);
    e.forces += effort;
    let solution = super::kkt_solve(&e, t)?;
    let (qdd, lambda) = (solution.qdd, solution.lambda);
    let (k, d) = mechanism
        .residual_tangent(t, q, qd, &qdd, &lambda)
        .ok_or(FixedError::TangentNotProvided { t })?;
    let (_, r_q, r_qd) = if M == 0 {
        (SMatrix::zeros(), SMatrix::zeros(), SMatrix::zeros())
    } else {
        mechanism
            .constraint_tangent(t, q, qd, &qdd)
            .ok_or(FixedError::TangentNotProvided { t })?
    };
    let finite = [&k, &d].iter().all(|m| all_finite(m.as_slice()))
        && [&r_q, &r_qd].iter().all(|m| all_finite(m.as_slice()));
    if !finite {
        return Err(FixedError::NotFinite { t });
    }
    let kkt = KktFactors::new(&e.mass, &e.phi_q, t)?;
    let mut out = KktDerivatives {
        qdd,
        lambda,
        dqdd_dq: SMatrix::zeros(),
        dqdd_dqd: SMatrix::zeros(),
        dqdd_du: SMatrix::zeros(),
        dlambda_dq: SMatrix::zeros(),
        dlambda_dqd: SMatrix::zeros(),
        dlambda_du: SMatrix::zeros(),
    };
    for j in 0..N {
        let (x, mu) = kkt.solve(&-k.column(j), &-r_q.column(j));
        out.dqdd_dq.set_column(j, &x);
        out.dlambda_dq.set_column(j, &mu);
        let (x, mu) = kkt.solve(&-d.column(j), &-r_qd.column(j));
        out.dqdd_dqd.set_column(j, &x);
        out.dlambda_dqd.set_column(j, &mu);
        let mut unit = SVector::<f64, N>::zeros();
        unit[j] = 1.0;
        let (x, mu) = kkt.solve(&unit, &SVector::zeros());
        out.dqdd_du.set_column(j, &x);
        out.dlambda_du.set_column(j, &mu);
    }
    let finite = [&out.dqdd_dq, &out.dqdd_dqd]
        .iter()
        .all(|m| all_finite(m.as_slice()))
        && [&out.dlambda_dq, &out.dlambda_dqd]
            .iter()
            .all(|m| all_finite(m.as_slice()));
    if !finite {
        return Err(FixedError::NotFinite { t });
    }
    Ok(out)
}

/// Whether every value is finite, in one branch-free pass (an `and` of the tests, which the
/// compiler vectorises, rather than a branch per value).
fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// dtau_id/dq and dtau_id/dq' of a mechanism that does not emit them: the residual's tangent
/// at lambda = 0 where it provides one (the same matrices), else central differences of
/// [`crate::Mechanism::inverse_dynamics`] with the step h_k = 6e-6 max(1, |x_k|) (eps^(1/3):
/// truncation h^2 and round-off eps/h balanced, about 1e-10 relative).
pub(crate) fn inverse_dynamics_derivatives<T, const N: usize, const M: usize>(
    mechanism: &T,
    t: f64,
    q: &SVector<f64, N>,
    qd: &SVector<f64, N>,
    qdd: &SVector<f64, N>,
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>)
where
    T: Mechanism<N, M>,
{
    if let Some(kd) = mechanism.residual_tangent(t, q, qd, qdd, &SVector::zeros()) {
        return kd;
    }
    let mut dq = SMatrix::<f64, N, N>::zeros();
    let mut dqd = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let h = 6e-6 * q[j].abs().max(1.0);
        let (mut up, mut down) = (*q, *q);
        up[j] += h;
        down[j] -= h;
        let diff = mechanism.inverse_dynamics(t, &up, qd, qdd)
            - mechanism.inverse_dynamics(t, &down, qd, qdd);
        dq.set_column(j, &(diff / (up[j] - down[j])));
        let h = 6e-6 * qd[j].abs().max(1.0);
        let (mut up, mut down) = (*qd, *qd);
        up[j] += h;
        down[j] -= h;
        let diff = mechanism.inverse_dynamics(t, q, &up, qdd)
            - mechanism.inverse_dynamics(t, q, &down, qdd);
        dqd.set_column(j, &(diff / (up[j] - down[j])));
    }
    (dq, dqd)
}
