//! The augmented (KKT) solve for q'' and lambda, with static sizes.
//!
//! ```text
//! [ M      Phi_q^T ] [ q''    ]   [ Q     ]       Q = tau - C q' - g
//! [ Phi_q  0       ] [ lambda ] = [ gamma ]
//! ```
//!
//! M alone may be singular (coordinates that carry no mass of their own, as in the seed's
//! redundant set), so it is not inverted. Adding alpha Phi_q^T (Phi_q q'' - gamma) = 0 to the
//! first row gives the same solution with M~ = M + alpha Phi_q^T Phi_q, which is symmetric
//! positive definite exactly when M is positive definite on null(Phi_q), the condition for
//! the motion to be determined. Then, by the Schur complement of M~:
//!
//! ```text
//! r = Q + alpha Phi_q^T gamma,   Y = M~^-1 Phi_q^T,   u = M~^-1 r
//! (Phi_q Y) lambda = Phi_q u - gamma,                 q'' = u - Y lambda
//! ```
//!
//! alpha = tr M / tr(Phi_q^T Phi_q) puts both terms of M~ on one scale, so M~ is as well
//! conditioned as the mechanism allows. Phi_q Y is positive semi-definite: a redundant row
//! drops out of its Cholesky factor and gets lambda = 0 (lambda is not unique there; q'' is).
//! One step of iterative refinement on the whole system follows. Cost: one N x N and one
//! M x M Cholesky, and M + 2 triangular solve pairs with M~.

use nalgebra::{SMatrix, SVector};

use super::FixedError;
use super::cholesky::Cholesky;
use crate::StaticEvaluation;

/// A pivot of M~ below this fraction of its largest diagonal entry means M is singular on an
/// allowed motion. Round-off leaves about 1e-16 relative; a genuinely light but determined
/// coordinate has a pivot far above 1e-12 after the alpha scaling.
const DEFINITE: f64 = 1e-12;
/// A pivot of Phi_q Y below this fraction (squared distance of a row to the span of the rows
/// before it, relative) marks a redundant row: the same 1e-6 relative distance the run-time
/// rank test uses.
const REDUNDANT: f64 = 1e-12;

/// q'' and lambda at one (t, q, q').
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KktSolution<const N: usize, const M: usize> {
    /// Accelerations q''.
    pub qdd: SVector<f64, N>,
    /// Lagrange multipliers lambda (sign: the constraint forces on q are -Phi_q^T lambda;
    /// 0 on rows redundant with earlier ones).
    pub lambda: SVector<f64, M>,
}

/// Solves the augmented system of one evaluation for q'' and lambda; see the module doc.
/// Allocation-free, no std.
///
/// # Errors
/// [`FixedError::UndeterminedMotion`] when M is singular on an allowed motion,
/// [`FixedError::NotFinite`] when an input is NaN or infinite (`t` is only used to say when).
pub fn kkt_solve<const N: usize, const M: usize>(
    e: &StaticEvaluation<N, M>,
    t: f64,
) -> Result<KktSolution<N, M>, FixedError> {
    let finite = e.mass.iter().all(|x| x.is_finite())
        && e.phi_q.iter().all(|x| x.is_finite())
        && e.gamma.iter().all(|x| x.is_finite())
        && (e.forces - e.coriolis - e.gravity)
            .iter()
            .all(|x| x.is_finite());
    if !finite {
        return Err(FixedError::NotFinite { t });
    }
    let jt = e.phi_q.transpose();
    let gram = jt * e.phi_q;
    // Without constraints or without mass there is no scale to match: alpha = 1 (and a
    // zero M is then reported by the pivot test).
    let ratio = e.mass.trace() / gram.trace();
    let alpha = if ratio > 0.0 && ratio.is_finite() {
        ratio
    } else {
        1.0
    };
    let mt = e.mass + gram * alpha;
    let m_fac = Cholesky::new(mt, DEFINITE);
    if let Some(coordinate) = m_fac.first_dropped() {
        return Err(FixedError::UndeterminedMotion { coordinate, t });
    }
    let mut y = SMatrix::<f64, N, M>::zeros();
    for i in 0..M {
        y.set_column(i, &m_fac.solve(&jt.column(i).into_owned()));
    }
    let s_fac = Cholesky::new(e.phi_q * y, REDUNDANT);
    let solve = |r1: &SVector<f64, N>, r2: &SVector<f64, M>| {
        let u = m_fac.solve(r1);
        let lambda = s_fac.solve(&(e.phi_q * u - r2));
        (u - y * lambda, lambda)
    };
    let q_load = e.forces - e.coriolis - e.gravity;
    let r1 = q_load + jt * e.gamma * alpha;
    let (mut qdd, mut lambda) = solve(&r1, &e.gamma);
    // One refinement step on the residual of the system that was factored.
    let res1 = r1 - mt * qdd - jt * lambda;
    let res2 = e.gamma - e.phi_q * qdd;
    let (dq, dl) = solve(&res1, &res2);
    qdd += dq;
    lambda += dl;
    Ok(KktSolution { qdd, lambda })
}
