//! The derivatives of the forward dynamics of a [`System`] at one instant, for control and
//! optimisation on a mechanism read at run time (a `.mech` file or a URDF through
//! [`crate::Interpreted::for_derivatives`]) or compiled ([`crate::Compiled`]).
//!
//! q'' and lambda solve the augmented system ([`crate::Dynamics`] without Baumgarte's
//! terms) with an effort u added to the declared forces; differentiating both of its rows
//! at the solution gives, for each x among q, q' and u, the same matrix with new
//! right-hand sides:
//!
//! ```text
//! [ M      Phi_q^T ] [ dq''/dx    ]   [ -dF/dx ]     F = M q'' + C q' + g - tau - u + Phi_q^T lambda
//! [ Phi_q  0       ] [ dlambda/dx ] = [ -dR/dx ]     R = Phi_q q'' - gamma
//! ```
//!
//! with dF/dq, dF/dq' the residual's tangent ([`System::tangent`]), dR/dq, dR/dq' the
//! constraint rows' ([`System::constraint_tangent`]), dF/du = -1, dR/du = 0. Without
//! constraint rows this is dq''/dx = -M^-1 dtau_id/dx and dq''/du = M^-1 (Carpentier &
//! Mansard 2018).
//!
//! The system is solved as the fixed-size solver solves it ([`crate::fixed::kkt_solve`]):
//! the first row plus alpha Phi_q^T times the second, M~ = M + alpha Phi_q^T Phi_q
//! factored (positive definite exactly where q'' is determined), then the Schur complement
//! Phi_q M~^-1 Phi_q^T, whose Cholesky factor drops the rows that depend on earlier ones,
//! and one step of iterative refinement. Redundant rows: q'' and its derivatives are
//! unique; the multipliers are not (any lambda + z with Phi_q^T z = 0 gives the same
//! forces). The rows found dependent on earlier ones get lambda = 0 and dlambda/dx = 0,
//! and the others the multipliers of the independent rows alone and their derivatives:
//! the derivative of that choice of multipliers wherever the same rows stay dependent (an
//! overconstrained linkage along its motion), and the same numbers as
//! [`crate::Mechanism::constrained_dynamics_derivatives`] on the compiled route.
//! [`crate::Dynamics::min_norm_multipliers`] gives other multipliers (the minimum-norm
//! ones) with the same constraint forces.

use nalgebra::DMatrix;

use crate::algorithms::finite;
use crate::error::Error;
use crate::linalg::DenseCholesky;
use crate::system::{ConstraintTangent, Evaluation, System, SystemInfo, Tangent};

/// A pivot of M~ below this fraction of its largest diagonal entry: M is singular on an
/// allowed motion (as in the fixed-size solver).
const DEFINITE: f64 = 1e-12;
/// A pivot of Phi_q M~^-1 Phi_q^T below this fraction marks a redundant row (as in the
/// fixed-size solver: the 1e-6 relative distance of the run-time rank test, squared).
const REDUNDANT: f64 = 1e-12;

/// Workspace and results of the forward dynamics' derivatives (module docs): sizes fixed
/// at creation, nothing allocated by [`DynamicsDerivatives::compute`] after the first call
/// (errors aside).
#[derive(Clone, Debug)]
pub struct DynamicsDerivatives {
    n: usize,
    m: usize,
    names: Vec<String>,
    eval: Evaluation,
    tangent: Tangent,
    rows: ConstraintTangent,
    /// M~ = M + alpha Phi_q^T Phi_q, its factor, Y = M~^-1 Phi_q^T, Phi_q Y and its factor.
    augmented: DMatrix<f64>,
    m_fac: DenseCholesky,
    y: DMatrix<f64>,
    schur: DMatrix<f64>,
    s_fac: DenseCholesky,
    alpha: f64,
    /// Scratch of one solve: right-hand sides, solution, residuals (n, m each).
    r1: Vec<f64>,
    r2: Vec<f64>,
    x: Vec<f64>,
    mu: Vec<f64>,
    res1: Vec<f64>,
    res2: Vec<f64>,
    qdd: Vec<f64>,
    lambda: Vec<f64>,
    dqdd_dq: DMatrix<f64>,
    dqdd_dqd: DMatrix<f64>,
    dqdd_du: DMatrix<f64>,
    dlambda_dq: DMatrix<f64>,
    dlambda_dqd: DMatrix<f64>,
    dlambda_du: DMatrix<f64>,
}

impl DynamicsDerivatives {
    /// A workspace for the sizes of `info` (n coordinates, m constraint rows).
    pub fn new(info: &SystemInfo) -> Self {
        let (n, m) = (info.n(), info.m());
        Self {
            n,
            m,
            names: info.coordinates.clone(),
            eval: Evaluation::zeros(n, m),
            tangent: Tangent::zeros(n),
            rows: ConstraintTangent::zeros(m, n),
            augmented: DMatrix::zeros(n, n),
            m_fac: DenseCholesky::new(n),
            y: DMatrix::zeros(n, m),
            schur: DMatrix::zeros(m, m),
            s_fac: DenseCholesky::new(m),
            alpha: 1.0,
            r1: vec![0.0; n],
            r2: vec![0.0; m],
            x: vec![0.0; n],
            mu: vec![0.0; m],
            res1: vec![0.0; n],
            res2: vec![0.0; m],
            qdd: vec![0.0; n],
            lambda: vec![0.0; m],
            dqdd_dq: DMatrix::zeros(n, n),
            dqdd_dqd: DMatrix::zeros(n, n),
            dqdd_du: DMatrix::zeros(n, n),
            dlambda_dq: DMatrix::zeros(m, n),
            dlambda_dqd: DMatrix::zeros(m, n),
            dlambda_du: DMatrix::zeros(m, n),
        }
    }

    /// q'', lambda and their derivatives by q, q' and u at (t, q, q') with the effort
    /// `effort` (n values, added to the declared forces tau) on `system`, whose sizes are
    /// those this workspace was made for.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a slice of another length; [`Error::NonFinite`] or
    /// [`Error::NonFiniteTerm`] for a NaN or infinity in the state, the equations, their
    /// tangents or the result; [`Error::UndeterminedMotion`] where M is singular on an
    /// allowed motion; [`Error::NotProvided`] for a system without the residual's or
    /// (with rows) the constraint rows' tangent (an [`crate::Interpreted`] not built by
    /// [`crate::Interpreted::for_derivatives`]).
    pub fn compute(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &[f64],
        effort: &[f64],
    ) -> Result<(), Error> {
        let (n, m) = (self.n, self.m);
        for (what, given) in [("q", q.len()), ("q'", qd.len()), ("effort", effort.len())] {
            if given != n {
                return Err(Error::WrongLength {
                    what,
                    expected: n,
                    got: given,
                });
            }
        }
        system.evaluate(t, q, qd, &mut self.eval);
        for (f, u) in self.eval.forces.iter_mut().zip(effort) {
            *f += u;
        }
        if let Some(culprit) = finite::evaluation_entry(&self.eval, system.info()) {
            return Err(finite::term_error(culprit, t, q));
        }
        Error::check_finite(effort, "effort", &self.names, t)?;
        self.factor(t, q)?;
        // q'' and lambda: r1 = tau + u - C q' - g, r2 = gamma.
        let e = &self.eval;
        for i in 0..n {
            self.r1[i] = e.forces[i] - e.coriolis[i] - e.gravity[i];
        }
        self.r2.copy_from_slice(e.gamma.as_slice());
        self.solve();
        self.qdd.copy_from_slice(&self.x);
        self.lambda.copy_from_slice(&self.mu);
        let not_provided = |what: &str| Error::NotProvided {
            what: format!("the {what} tangent of `{}`", system.info().name),
        };
        system
            .tangent(t, q, qd, &self.qdd, &self.lambda, &mut self.tangent)
            .ok_or_else(|| not_provided("residual's"))?;
        if m > 0 {
            system
                .constraint_tangent(t, q, qd, &self.qdd, &mut self.rows)
                .ok_or_else(|| not_provided("constraint rows'"))?;
        }
        for j in 0..n {
            self.column(Variable::Position, j);
            self.column(Variable::Rate, j);
            self.column(Variable::Effort, j);
        }
        let results = [
            &self.dqdd_dq,
            &self.dqdd_dqd,
            &self.dlambda_dq,
            &self.dlambda_dqd,
        ];
        if results.iter().all(|r| r.iter().all(|x| x.is_finite())) {
            Ok(())
        } else {
            Err(Error::NonFinite {
                what: "a derivative of q'' or lambda (the equations' tangents)".into(),
                t,
            })
        }
    }

    /// Factors M~ and the Schur complement of the evaluation (module docs).
    fn factor(&mut self, t: f64, q: &[f64]) -> Result<(), Error> {
        let (n, m) = (self.n, self.m);
        let e = &self.eval;
        let j = &e.phi_q;
        let mut gram_trace = 0.0;
        for a in 0..n {
            for b in 0..n {
                let g: f64 = (0..m).map(|r| j[(r, a)] * j[(r, b)]).sum();
                self.augmented[(a, b)] = g;
            }
            gram_trace += self.augmented[(a, a)];
        }
        // Without rows or without mass there is no scale to match: alpha = 1.
        let ratio = e.mass.trace() / gram_trace;
        self.alpha = if ratio > 0.0 && ratio.is_finite() {
            ratio
        } else {
            1.0
        };
        for a in 0..n {
            for b in 0..n {
                self.augmented[(a, b)] = e.mass[(a, b)] + self.alpha * self.augmented[(a, b)];
            }
        }
        self.m_fac.factor(&self.augmented, DEFINITE);
        if self.m_fac.first_dropped().is_some() {
            return Err(Error::UndeterminedMotion {
                t,
                coordinates: self.names.clone(),
                q: q.to_vec(),
            });
        }
        for r in 0..m {
            for a in 0..n {
                self.x[a] = j[(r, a)];
            }
            self.m_fac.solve(&mut self.x);
            for a in 0..n {
                self.y[(a, r)] = self.x[a];
            }
        }
        for r in 0..m {
            for c in 0..m {
                self.schur[(r, c)] = (0..n).map(|a| j[(r, a)] * self.y[(a, c)]).sum();
            }
        }
        self.s_fac.factor(&self.schur, REDUNDANT);
        Ok(())
    }

    /// Column `j` of the derivatives by `variable`: the right-hand sides of the module
    /// docs, solved.
    fn column(&mut self, variable: Variable, j: usize) {
        let (n, m) = (self.n, self.m);
        for i in 0..n {
            self.r1[i] = match variable {
                Variable::Position => -self.tangent.stiffness[(i, j)],
                Variable::Rate => -self.tangent.damping[(i, j)],
                Variable::Effort => f64::from(u8::from(i == j)),
            };
        }
        for r in 0..m {
            self.r2[r] = match variable {
                Variable::Position => -self.rows.stiffness[(r, j)],
                Variable::Rate => -self.rows.damping[(r, j)],
                Variable::Effort => 0.0,
            };
        }
        self.solve();
        let (dqdd, dlambda) = match variable {
            Variable::Position => (&mut self.dqdd_dq, &mut self.dlambda_dq),
            Variable::Rate => (&mut self.dqdd_dqd, &mut self.dlambda_dqd),
            Variable::Effort => (&mut self.dqdd_du, &mut self.dlambda_du),
        };
        for i in 0..n {
            dqdd[(i, j)] = self.x[i];
        }
        for r in 0..m {
            dlambda[(r, j)] = self.mu[r];
        }
    }

    /// (x, mu) with M x + Phi_q^T mu = r1, Phi_q x = r2 (the buffers), mu = 0 on the
    /// dropped rows: the augmented first row, the Schur complement, one refinement step.
    fn solve(&mut self) {
        let (n, m) = (self.n, self.m);
        let j = &self.eval.phi_q;
        // r1 <- r1 + alpha Phi_q^T r2: the system that was factored.
        for a in 0..n {
            self.r1[a] += self.alpha * (0..m).map(|r| j[(r, a)] * self.r2[r]).sum::<f64>();
        }
        self.res1.copy_from_slice(&self.r1);
        self.res2.copy_from_slice(&self.r2);
        self.x.fill(0.0);
        self.mu.fill(0.0);
        for _ in 0..2 {
            // Solve for the correction of the residual (res1, res2), then add it.
            self.m_fac.solve(&mut self.res1);
            for r in 0..m {
                let ju: f64 = (0..n).map(|a| j[(r, a)] * self.res1[a]).sum();
                self.res2[r] = ju - self.res2[r];
            }
            self.s_fac.solve(&mut self.res2);
            for a in 0..n {
                let ymu: f64 = (0..m).map(|r| self.y[(a, r)] * self.res2[r]).sum();
                self.x[a] += self.res1[a] - ymu;
            }
            for r in 0..m {
                self.mu[r] += self.res2[r];
            }
            // The residual of the factored system at the new (x, mu).
            for a in 0..n {
                let mx: f64 = (0..n).map(|b| self.augmented[(a, b)] * self.x[b]).sum();
                let jmu: f64 = (0..m).map(|r| j[(r, a)] * self.mu[r]).sum();
                self.res1[a] = self.r1[a] - mx - jmu;
            }
            for r in 0..m {
                let jx: f64 = (0..n).map(|a| j[(r, a)] * self.x[a]).sum();
                self.res2[r] = self.r2[r] - jx;
            }
        }
    }

    /// q'' of the last [`DynamicsDerivatives::compute`].
    pub fn accelerations(&self) -> &[f64] {
        &self.qdd
    }
    /// lambda of the last compute (0 on redundant rows; module docs).
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }
    /// dq''/dq (n x n).
    pub fn dqdd_dq(&self) -> &DMatrix<f64> {
        &self.dqdd_dq
    }
    /// dq''/dq' (n x n).
    pub fn dqdd_dqd(&self) -> &DMatrix<f64> {
        &self.dqdd_dqd
    }
    /// dq''/du (n x n); M^-1 without constraint rows.
    pub fn dqdd_du(&self) -> &DMatrix<f64> {
        &self.dqdd_du
    }
    /// dlambda/dq (m x n).
    pub fn dlambda_dq(&self) -> &DMatrix<f64> {
        &self.dlambda_dq
    }
    /// dlambda/dq' (m x n).
    pub fn dlambda_dqd(&self) -> &DMatrix<f64> {
        &self.dlambda_dqd
    }
    /// dlambda/du (m x n).
    pub fn dlambda_du(&self) -> &DMatrix<f64> {
        &self.dlambda_du
    }
}

/// Which variable a column of the derivatives is by.
#[derive(Clone, Copy)]
enum Variable {
    Position,
    Rate,
    Effort,
}
