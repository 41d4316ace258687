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
    let kkt = KktFactors::new(&e.mass, &e.phi_q, t)?;
    let (qdd, lambda) = kkt.solve(&(e.forces - e.coriolis - e.gravity), &e.gamma);
    Ok(KktSolution { qdd, lambda })
}

/// The factors of one augmented matrix [M, Phi_q^T; Phi_q, 0] (module docs): M~'s Cholesky
/// factor, Y = M~^-1 Phi_q^T and the Cholesky factor of Phi_q Y with its redundant rows
/// dropped, so that each right-hand side costs two triangular solve pairs with M~ and one
/// with Phi_q Y.
pub(crate) struct KktFactors<'a, const N: usize, const M: usize> {
    mass: &'a SMatrix<f64, N, N>,
    phi_q: &'a SMatrix<f64, M, N>,
    alpha: f64,
    m_fac: Cholesky<N>,
    y: SMatrix<f64, N, M>,
    s_fac: Cholesky<M>,
}

impl<'a, const N: usize, const M: usize> KktFactors<'a, N, M> {
    /// Factors the augmented matrix of `mass` and `phi_q` (finite).
    ///
    /// # Errors
    /// [`FixedError::UndeterminedMotion`] when M is singular on an allowed motion (`t`
    /// says when).
    pub(crate) fn new(
        mass: &'a SMatrix<f64, N, N>,
        phi_q: &'a SMatrix<f64, M, N>,
        t: f64,
    ) -> Result<Self, FixedError> {
        let jt = phi_q.transpose();
        let gram = jt * phi_q;
        // Without constraints or without mass there is no scale to match: alpha = 1 (and a
        // zero M is then reported by the pivot test).
        let ratio = mass.trace() / gram.trace();
        let alpha = if ratio > 0.0 && ratio.is_finite() {
            ratio
        } else {
            1.0
        };
        let m_fac = Cholesky::new(mass + gram * alpha, DEFINITE);
        if let Some(coordinate) = m_fac.first_dropped() {
            return Err(FixedError::UndeterminedMotion { coordinate, t });
        }
        let mut y = SMatrix::<f64, N, M>::zeros();
        for i in 0..M {
            y.set_column(i, &m_fac.solve(&jt.column(i).into_owned()));
        }
        let s_fac = Cholesky::new(phi_q * y, REDUNDANT);
        Ok(Self {
            mass,
            phi_q,
            alpha,
            m_fac,
            y,
            s_fac,
        })
    }

    /// (x, mu) with M x + Phi_q^T mu = `r1` and Phi_q x = `r2`, mu = 0 on the dropped rows,
    /// by the Schur complement of M~ on r1 + alpha Phi_q^T r2, then one step of iterative
    /// refinement on the residual of the system that was factored.
    pub(crate) fn solve(
        &self,
        r1: &SVector<f64, N>,
        r2: &SVector<f64, M>,
    ) -> (SVector<f64, N>, SVector<f64, M>) {
        let jt = self.phi_q.transpose();
        let r1 = r1 + jt * r2 * self.alpha;
        let solve = |r1: &SVector<f64, N>, r2: &SVector<f64, M>| {
            let u = self.m_fac.solve(r1);
            let lambda = self.s_fac.solve(&(self.phi_q * u - r2));
            (u - self.y * lambda, lambda)
        };
        let (mut x, mut mu) = solve(&r1, r2);
        let mt = self.mass + jt * self.phi_q * self.alpha;
        let res1 = r1 - mt * x - jt * mu;
        let res2 = r2 - self.phi_q * x;
        let (dx, dmu) = solve(&res1, &res2);
        x += dx;
        mu += dmu;
        (x, mu)
    }
}

/// The run-time finish of the KKT solve that follows M's pattern (the emitted
/// [`crate::Mechanism::constrained_dynamics`] of a mechanism with constraint rows): from
/// u = M^-1 Q, Y = M^-1 Phi_q^T, S = Phi_q M^-1 Phi_q^T and c = Phi_q u - gamma, all
/// computed by the generated factorisation M = L^T D L,
///
/// ```text
/// S lambda = c,   q'' = u - Y lambda
/// ```
///
/// S is positive semi-definite; its rows redundant with earlier ones drop out of its
/// Cholesky factor at the threshold of [`kkt_solve`] and get lambda = 0, as there. Cost:
/// one M x M Cholesky and 2 N M. `None` when an input or the result is not finite (the
/// caller then takes [`kkt_solve`], which reports why). Allocation-free, no std.
pub fn kkt_tree_solve<const N: usize, const M: usize>(
    u: &SVector<f64, N>,
    y: &SMatrix<f64, N, M>,
    s: &SMatrix<f64, M, M>,
    c: &SVector<f64, M>,
) -> Option<KktSolution<N, M>> {
    let s_fac = Cholesky::new(*s, REDUNDANT);
    let lambda = s_fac.solve(c);
    let qdd = u - y * lambda;
    let finite = qdd.iter().chain(lambda.iter()).all(|x| x.is_finite());
    finite.then_some(KktSolution { qdd, lambda })
}
