//! HHT-alpha on the index-3 DAE (Hilber, Hughes & Taylor, Earthquake Eng. Struct. Dyn. 5,
//! 1977), with the scaling of Negrut, Rampalli, Ottarsson & Sandu (J. Comput. Nonlinear
//! Dyn. 2, 2007). Unknowns at t_{n+1} = t_n + h are a = q''_{n+1} and lambda:
//!
//! ```text
//! q_{n+1} = q_n + h q'_n + h^2/2 [(1 - 2 beta) a_n + 2 beta a]
//! q'_{n+1} = q'_n + h [(1 - gamma) a_n + gamma a]
//! R1 = M(q_{n+1}) a + (1 + alpha) [Phi_q^T lambda - Q]_{n+1} - alpha [Phi_q^T lambda - Q]_n = 0
//! R2 = Phi(q_{n+1}, t_{n+1}) / (beta h^2) = 0
//! ```
//!
//! with Q = tau - C q' - g, alpha in [-1/3, 0], gamma = 1/2 - alpha, beta = (1 - alpha)^2/4:
//! Negrut et al.'s HHT-I3, in which the constraint forces are alpha-weighted together with
//! the applied forces (lambda_{n+1} is the multiplier at t_{n+1}). The scaling of R2 by
//! 1/(beta h^2) keeps the Newton matrix
//!
//! ```text
//! [ M + (1 + alpha)(beta h^2 K + gamma h D)   (1 + alpha) Phi_q^T ]
//! [ Phi_q                                     0                   ]
//! ```
//!
//! well conditioned as h -> 0; K = dF/dq and D = dF/dq' of F = M q'' + C q' + g - tau +
//! Phi_q^T lambda come from [`System::tangent`] when the system provides them, otherwise from
//! forward differences (2n evaluations). The matrix is formed once per step (modified Newton)
//! and refreshed if the iteration is slow. A system of more than 40 unknowns whose Newton
//! matrix orders into a narrow band (a chain) has it factored there ([`LearntBand`]: O(n b^2)
//! where dense LU is O(n^3)); forming it and the residual stay O(n^2) per step.
//!
//! Accuracy (`tests/runtime_integrators.rs`): alpha = 0 (the trapezoidal Newmark rule) is
//! second order on the four-bar but has no numerical damping, and on the seed (singular M)
//! its Newton iteration diverges: use alpha < 0 on index-3 DAEs (the CLI uses -0.05). With
//! alpha < 0 the seed, whose M is constant, converges at second order; the four-bar, whose
//! M depends on q, only at first order: M a is taken at t_{n+1} while the velocity-dependent
//! inertial forces C q' are alpha-weighted with Q. Arnold & Brüls (Multibody Syst. Dyn. 18,
//! 2007) analyse such order reductions of HHT / generalised-alpha on index-3 DAEs. Positions
//! satisfy Phi = 0 to the Newton tolerance at every step; velocities satisfy
//! Phi_q q' + Phi_t = 0 only to O(h^2),
//! so the driver projects the recorded samples but never the internal Newmark state.

use crate::algorithms::finite;
use crate::error::Error;
use crate::linalg::{LearntBand, Lu, inf_norm, max_nan};
use crate::system::{Evaluation, System, SystemInfo, Tangent};

/// HHT-alpha integrator state and preallocated Newton workspace.
#[derive(Clone, Debug)]
pub struct Hht {
    n: usize,
    m: usize,
    alpha: f64,
    beta: f64,
    gamma: f64,
    a_n: Vec<f64>,
    lam_n: Vec<f64>,
    term_n: Vec<f64>,
    a: Vec<f64>,
    lam: Vec<f64>,
    term: Vec<f64>,
    q1: Vec<f64>,
    v1: Vec<f64>,
    r: Vec<f64>,
    f0: Vec<f64>,
    qp: Vec<f64>,
    eval: Evaluation,
    eval_p: Evaluation,
    tangent: Tangent,
    lu: Lu,
    /// The Newton matrix's band (systems of more than [`DENSE_MAX_ORDER`] unknowns), made
    /// at the first Newton matrix from the system's structural pattern.
    band: Option<LearntBand>,
    /// Whether the last Newton matrix was factored in `band` (else by `lu`).
    banded: bool,
    /// Newton stops when the position correction beta h^2 |da|_inf is below
    /// `newton_tolerance * (1 + |q|_inf)` (default 1e-12).
    pub newton_tolerance: f64,
    /// Newton iterations per Jacobian before a refresh (default 6).
    pub max_iterations: usize,
    /// Number of Newton matrices formed.
    pub jacobians: usize,
    /// Number of system evaluations.
    pub evaluations: usize,
}

impl Hht {
    /// Workspace for `info` with numerical damping `alpha` in [-1/3, 0].
    pub fn new(info: &SystemInfo, alpha: f64) -> Result<Self, Error> {
        if !(-1.0 / 3.0..=0.0).contains(&alpha) {
            return Err(Error::InvalidOption {
                option: "alpha",
                value: alpha,
                allowed: "[-1/3, 0]",
            });
        }
        let (n, m) = (info.n(), info.m());
        let v = |k| vec![0.0; k];
        Ok(Self {
            n,
            m,
            alpha,
            beta: (1.0 - alpha).powi(2) / 4.0,
            gamma: 0.5 - alpha,
            a_n: v(n),
            lam_n: v(m),
            term_n: v(n),
            a: v(n),
            lam: v(m),
            term: v(n),
            q1: v(n),
            v1: v(n),
            r: v(n + m),
            f0: v(n),
            qp: v(n),
            eval: Evaluation::zeros(n, m),
            eval_p: Evaluation::zeros(n, m),
            tangent: Tangent::zeros(n),
            lu: Lu::new(n + m),
            band: None,
            banded: false,
            newton_tolerance: 1e-12,
            max_iterations: 6,
            jacobians: 0,
            evaluations: 0,
        })
    }

    /// Sets the state at the start: accelerations and multipliers from the augmented
    /// system at (t, q, q'), so that [Phi_q^T lambda - Q]_0 = -M a_0.
    pub fn start(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        lambda: &[f64],
    ) {
        self.a_n.copy_from_slice(qdd);
        self.lam_n.copy_from_slice(lambda);
        system.evaluate(t, q, qd, &mut self.eval);
        self.evaluations += 1;
        Self::dynamic_term(&self.eval, &self.lam_n, qd.len(), &mut self.term_n);
    }

    /// Phi_q^T lambda - Q = Phi_q^T lambda - tau + C q' + g: the force term HHT weights.
    fn dynamic_term(e: &Evaluation, lam: &[f64], n: usize, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate().take(n) {
            *o = -e.forces[i] + e.coriolis[i] + e.gravity[i] + Self::constraint_force(e, lam, i);
        }
    }

    fn constraint_force(e: &Evaluation, lam: &[f64], i: usize) -> f64 {
        lam.iter()
            .enumerate()
            .map(|(r, l)| e.phi_q[(r, i)] * l)
            .sum()
    }

    /// F = M a + C q' + g - tau + Phi_q^T lambda for one evaluation.
    fn dynamic_residual(e: &Evaluation, a: &[f64], lam: &[f64], out: &mut [f64]) {
        let n = a.len();
        Self::dynamic_term(e, lam, n, out);
        for (i, o) in out.iter_mut().enumerate() {
            *o += (0..n).map(|j| e.mass[(i, j)] * a[j]).sum::<f64>();
        }
    }

    /// Positions and velocities at t + h for the current iterate a.
    fn predict(&mut self, q: &[f64], v: &[f64], h: f64) {
        let (b, g) = (self.beta, self.gamma);
        for i in 0..self.n {
            self.q1[i] = q[i]
                + h * v[i]
                + 0.5 * h * h * ((1.0 - 2.0 * b) * self.a_n[i] + 2.0 * b * self.a[i]);
            self.v1[i] = v[i] + h * ((1.0 - g) * self.a_n[i] + g * self.a[i]);
        }
    }

    /// Evaluates R1, R2 at the current iterate into `self.r`; returns |Phi|_inf.
    fn residual(&mut self, system: &dyn System, t1: f64, h: f64) -> Result<f64, Error> {
        let (n, m) = (self.n, self.m);
        system.evaluate(t1, &self.q1, &self.v1, &mut self.eval);
        self.evaluations += 1;
        Self::dynamic_term(&self.eval, &self.lam, n, &mut self.term);
        for i in 0..n {
            let ma: f64 = (0..n).map(|j| self.eval.mass[(i, j)] * self.a[j]).sum();
            self.r[i] = ma + (1.0 + self.alpha) * self.term[i] - self.alpha * self.term_n[i];
        }
        let s = 1.0 / (self.beta * h * h);
        let mut phi_max = 0.0f64;
        for k in 0..m {
            self.r[n + k] = self.eval.phi[k] * s;
            phi_max = max_nan(phi_max, self.eval.phi[k].abs());
        }
        if self.r.iter().any(|x| !x.is_finite()) {
            return Err(finite::evaluation_error(
                &self.eval,
                system.info(),
                (t1, &self.q1, &self.v1),
                "the HHT residual (accelerations or multipliers of the Newton iterate)",
            ));
        }
        Ok(phi_max)
    }

    /// K = dF/dq and D = dF/dq' by forward differences (2n evaluations), for systems that do
    /// not provide [`System::tangent`].
    fn finite_difference_tangent(&mut self, system: &dyn System, t1: f64) {
        let n = self.n;
        // Forward differences of F in q and q'.
        Self::dynamic_residual(&self.eval, &self.a, &self.lam, &mut self.f0);
        for col in 0..2 * n {
            let j = col % n;
            let base = if col < n { self.q1[j] } else { self.v1[j] };
            let d = 1.5e-8 * (1.0 + base.abs());
            self.qp
                .copy_from_slice(if col < n { &self.q1 } else { &self.v1 });
            self.qp[j] += d;
            if col < n {
                system.evaluate(t1, &self.qp, &self.v1, &mut self.eval_p);
            } else {
                system.evaluate(t1, &self.q1, &self.qp, &mut self.eval_p);
            }
            self.evaluations += 1;
            Self::dynamic_residual(&self.eval_p, &self.a, &self.lam, &mut self.term);
            let target = if col < n {
                &mut self.tangent.stiffness
            } else {
                &mut self.tangent.damping
            };
            for i in 0..n {
                target[(i, j)] = (self.term[i] - self.f0[i]) / d;
            }
        }
        Self::dynamic_term(&self.eval, &self.lam, n, &mut self.term);
    }

    /// Forms and factors the Newton matrix at the current iterate (after `residual`).
    fn jacobian(&mut self, system: &dyn System, t1: f64, h: f64) -> Result<(), Error> {
        let (n, m) = (self.n, self.m);
        self.jacobians += 1;
        if system
            .tangent(
                t1,
                &self.q1,
                &self.v1,
                &self.a,
                &self.lam,
                &mut self.tangent,
            )
            .is_none()
        {
            self.finite_difference_tangent(system, t1);
        }
        let (ap, bh2, gh) = (1.0 + self.alpha, self.beta * h * h, self.gamma * h);
        let e = &self.eval;
        let k = &self.tangent;
        let a = self.lu.matrix_mut();
        for i in 0..n {
            for j in 0..n {
                a[(i, j)] =
                    e.mass[(i, j)] + ap * (bh2 * k.stiffness[(i, j)] + gh * k.damping[(i, j)]);
            }
        }
        // Redundant rows make the exact Newton matrix singular (lambda is not unique). A
        // shift -eps I in its zero block, far below the Schur complement Phi_q A^-1 Phi_q^T
        // of any independent row, keeps it regular; Newton still converges to the residual's
        // zero (only the iteration matrix changes), and the shift damps lambda's undetermined
        // part to zero.
        let mass_scale = (0..n).fold(0.0f64, |x, i| max_nan(x, a[(i, i)].abs()));
        let row_scale = (0..m).fold(0.0f64, |x, r| {
            max_nan(x, (0..n).map(|j| e.phi_q[(r, j)].powi(2)).sum::<f64>())
        });
        let eps = if mass_scale > 0.0 {
            1e-12 * row_scale / mass_scale
        } else {
            0.0
        };
        for r in 0..m {
            for j in 0..n {
                a[(j, n + r)] = ap * e.phi_q[(r, j)];
                a[(n + r, j)] = e.phi_q[(r, j)];
            }
            for c in 0..m {
                a[(n + r, n + c)] = if c == r { -eps } else { 0.0 };
            }
        }
        if n + m > DENSE_MAX_ORDER && self.band.is_none() {
            self.band = Some(LearntBand::new(n + m, newton_pattern(system, n, m)));
        }
        // A failed pivot in the band leaves the matrix to dense LU, which pivots the same
        // way (the entries outside the band are zero), fails at the same pivot and says so.
        let band = self.band.as_mut().map(|b| b.factor(self.lu.matrix()));
        self.banded = matches!(band, Some(Ok(true)));
        if !self.banded && !self.lu.factor() {
            return Err(Error::SingularConfiguration {
                t: t1,
                q: self.q1.clone(),
                condition: f64::INFINITY,
            });
        }
        Ok(())
    }

    /// Solves the last Newton matrix for `self.r` in place.
    fn newton_solve(&mut self) {
        match self.band.as_mut() {
            Some(band) if self.banded => band.solve(&mut self.r),
            _ => self.lu.solve(&mut self.r),
        }
    }

    /// Advances (q, q') from t to t + h in place. Afterwards [`Hht::accelerations`] and
    /// [`Hht::multipliers`] hold a and lambda at t + h.
    pub fn step(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &mut [f64],
        v: &mut [f64],
        h: f64,
    ) -> Result<(), Error> {
        let (n, m) = (self.n, self.m);
        let t1 = t + h;
        self.a.copy_from_slice(&self.a_n);
        self.lam.copy_from_slice(&self.lam_n);
        self.predict(q, v, h);
        let mut phi = self.residual(system, t1, h)?;
        let qscale = 1.0 + inf_norm(q);
        let mut converged = false;
        let mut iterations = 0;
        // Up to 10 refreshes of the Newton matrix: where accelerations change fast the
        // Newmark predictor is poor and the first corrections are large.
        'refresh: for _ in 0..10 {
            self.jacobian(system, t1, h)?;
            let mut prev = f64::INFINITY;
            for _ in 0..self.max_iterations {
                iterations += 1;
                for x in self.r.iter_mut() {
                    *x = -*x;
                }
                self.newton_solve();
                let mut da = 0.0f64;
                for i in 0..n {
                    self.a[i] += self.r[i];
                    da = max_nan(da, self.r[i].abs());
                }
                for k in 0..m {
                    self.lam[k] += self.r[n + k];
                }
                self.predict(q, v, h);
                phi = self.residual(system, t1, h)?;
                let dq = self.beta * h * h * da;
                if dq <= self.newton_tolerance * qscale {
                    converged = true;
                    break 'refresh;
                }
                if dq > 0.5 * prev {
                    // No longer contracting: at the rounding floor (a correction a thousand
                    // times the tolerance, ~1e-9 relative, is noise there) accept, else the
                    // iteration is slow: refresh the Newton matrix.
                    if dq <= 1e3 * self.newton_tolerance * qscale {
                        converged = true;
                        break 'refresh;
                    }
                    continue 'refresh;
                }
                prev = dq;
            }
        }
        if !converged {
            return Err(Error::NewtonDidNotConverge {
                t: t1,
                iterations,
                residual: phi,
                q: self.q1.clone(),
            });
        }
        q.copy_from_slice(&self.q1);
        v.copy_from_slice(&self.v1);
        self.a_n.copy_from_slice(&self.a);
        self.lam_n.copy_from_slice(&self.lam);
        self.term_n.copy_from_slice(&self.term);
        Ok(())
    }

    /// a = q'' at the end of the last step (the algorithmic acceleration).
    pub fn accelerations(&self) -> &[f64] {
        &self.a_n
    }

    /// lambda at the end of the last step.
    pub fn multipliers(&self) -> &[f64] {
        &self.lam_n
    }

    /// tau . q' + lambda . Phi_t at the end of the last step (from its last evaluation): the
    /// power of the applied forces and of the moving constraint rows
    /// ([`crate::Dynamics::constraint_power`]).
    pub fn power(&self) -> f64 {
        let e = &self.eval;
        let applied: f64 = e.forces.iter().zip(&self.v1).map(|(f, v)| f * v).sum();
        let rows: f64 = self.lam_n.iter().zip(&e.phi_t).map(|(l, p)| l * p).sum();
        applied + rows
    }
}

/// Newton matrices of at most this order are factored densely (the KKT solve's threshold
/// for its small-system routes).
const DENSE_MAX_ORDER: usize = 40;

/// The entries of the Newton matrix that can be nonzero, as far as the system's structural
/// pattern tells: M, Phi_q and Phi_q^T, and Phi_q^T Phi_q (the stiffness of the constraint
/// forces Phi_q^T lambda couples the coordinates of one row; rows of more than 64 entries
/// are left out, their band would be too wide anyway). The band widens to any other entry
/// the first matrices show.
fn newton_pattern(system: &dyn System, n: usize, m: usize) -> Vec<(usize, usize)> {
    let Some(s) = system.sparsity().filter(|s| (s.n, s.m) == (n, m)) else {
        return Vec::new();
    };
    let mut edges: Vec<(usize, usize)> = s.mass.clone();
    edges.extend(s.jacobian.iter().map(|&(r, j)| (n + r, j)));
    let mut rows = vec![Vec::new(); m];
    for &(r, j) in &s.jacobian {
        rows[r].push(j);
    }
    for row in rows.iter().filter(|row| row.len() <= 64) {
        for (k, &i) in row.iter().enumerate() {
            edges.extend(row[k + 1..].iter().map(|&j| (i, j)));
        }
    }
    edges
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::kinematics::assemble;

    /// A02 with N = 40 (n + m = 163): its Newton matrix is factored in a band, and 20 steps
    /// give the states of the dense factorisation (forced by a full pattern) to the Newton
    /// tolerance. Each step stops when the position correction is below 1e-12 (1 + |q|),
    /// 4.1e-11 m here, and a velocity differs by gamma / (beta h) = 2,000 /s times that.
    #[test]
    fn a_chain_newton_matrix_in_its_band_steps_as_the_dense_one() {
        let system = crate::builtin::builtin("n_four_bar").expect("built in");
        let info = system.info();
        let (n, m) = (info.n(), info.m());
        let s = assemble(system.as_ref(), 0.0, &Default::default()).expect("assembles");
        let run = |dense: bool| {
            let mut hht = Hht::new(info, -0.05).expect("alpha in range");
            if dense {
                let all = (0..n + m).flat_map(|i| (0..n + m).map(move |j| (i, j)));
                hht.band = Some(LearntBand::new(n + m, all.collect()));
            }
            let (qdd, lambda) = (vec![0.0; n], vec![0.0; m]);
            hht.start(system.as_ref(), 0.0, &s.q, &s.qd, &qdd, &lambda);
            let (mut q, mut v) = (s.q.clone(), s.qd.clone());
            for k in 0..20 {
                let t = k as f64 * 1e-3;
                hht.step(system.as_ref(), t, &mut q, &mut v, 1e-3)
                    .expect("steps");
            }
            (q, v, hht.banded)
        };
        let (q_band, v_band, banded) = run(false);
        let (q_dense, v_dense, dense_banded) = run(true);
        assert!(banded && !dense_banded, "routes {banded} {dense_banded}");
        let scale = 1.0 + inf_norm(&q_dense);
        for (a, b) in q_band.iter().zip(&q_dense) {
            assert!((a - b).abs() <= 20.0 * 1e-12 * scale, "q {a} vs {b}");
        }
        for (a, b) in v_band.iter().zip(&v_dense) {
            assert!((a - b).abs() <= 20.0 * 2e3 * 1e-12 * scale, "q' {a} vs {b}");
        }
    }
}
