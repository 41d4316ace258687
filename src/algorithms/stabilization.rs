//! Constraint stabilisation for the index-3 DAE integrated as an ODE in (q, q').
//!
//! Plain integration of q'' from the augmented system keeps only Phi'' = 0, so Phi and
//! Phi' drift (linearly and quadratically in t). Three choices:
//!
//! - [`Stabilization::None`]: measure the drift, do nothing.
//! - [`Stabilization::Baumgarte`] (Baumgarte 1972, Comput. Methods Appl. Mech. Eng. 1):
//!   replace Phi'' = 0 by Phi'' + 2 alpha Phi' + beta^2 Phi = 0, i.e. solve with
//!   gamma - 2 alpha (Phi_q q' + Phi_t) - beta^2 Phi (see [`crate::Dynamics`]). Damps the
//!   drift but does not remove it.
//! - [`Stabilization::Projection`] (default; Hairer & Wanner, Solving ODEs II, sec. VII.2;
//!   Eich 1993): after each accepted step, Newton onto Phi(q, t) = 0 with the minimum-norm
//!   correction dq = -Phi_q^T (Phi_q Phi_q^T + mu I)^-1 Phi, iterated until
//!   |Phi|_inf <= 1e-14 or stalling, then the velocities onto Phi_q q' = -Phi_t with
//!   dq' = -Phi_q^T (Phi_q Phi_q^T + mu I)^-1 (Phi_q q' + Phi_t). Closes the loops to
//!   round-off.
//!
//! The shift mu = 1e-12 max_i (Phi_q Phi_q^T)_ii (Levenberg–Marquardt) keeps the Gram
//! matrix positive definite when rows are redundant or the configuration is singular: the
//! correction is still the minimum-norm one in every direction where Phi_q has a singular
//! value above 1e-6 of its largest, and no step is taken along directions the constraints
//! no longer control (at a singular configuration Newton would otherwise jump branches).
//! Redundant rows are consistent, so their residual lies in the controlled directions. The
//! Gram matrix is formed from each row's nonzero span and factored inside its envelope.
//! With more rows than coordinates (a redundant set: 1,000 copies of one row) the same
//! correction is computed on the coordinates' side, n x n instead of m x m,
//!
//! ```text
//! Phi_q^T (Phi_q Phi_q^T + mu I)^-1 = (Phi_q^T Phi_q + mu I)^-1 Phi_q^T,
//! ```
//!
//! so a redundant set costs O(m) per correction for a fixed n, not O(m^3).

use nalgebra::DMatrix;

use crate::algorithms::finite::{check_jacobian, check_rows};
use crate::error::Error;
use crate::linalg::{Envelope, RowSpans, inf_norm, max_nan};
use crate::system::{System, SystemInfo};

/// Relative Levenberg–Marquardt shift of the Gram matrix (see the module docs).
const GRAM_SHIFT: f64 = 1e-12;

/// How the drift off Phi = 0 and Phi' = 0 is controlled.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Stabilization {
    /// No stabilisation: the constraint residual drifts and is only recorded.
    None,
    /// Baumgarte: Phi'' + 2 alpha Phi' + beta^2 Phi = 0 (alpha, beta in 1/s).
    Baumgarte {
        /// Velocity-level gain alpha (1/s).
        alpha: f64,
        /// Position-level gain beta (1/s).
        beta: f64,
    },
    /// Coordinate projection after every accepted step (the default).
    #[default]
    Projection,
}

/// Preallocated workspace for the projections; allocates nothing after [`Projector::new`].
#[derive(Clone, Debug)]
pub struct Projector {
    m: usize,
    phi: Vec<f64>,
    phi_t: Vec<f64>,
    phi_q: DMatrix<f64>,
    spans: RowSpans,
    gram: Envelope,
    /// With m > n: Phi_q^T Phi_q + mu I (n x n) instead of the Gram matrix, and its
    /// right-hand side.
    normal: Option<(Envelope, Vec<f64>)>,
    z: Vec<f64>,
    /// Whether `gram` holds a factorisation (of the last velocity projection).
    factored: bool,
    /// Target |Phi|_inf: iterate until below this (default 1e-14) ...
    pub tolerance: f64,
    /// ... or until the iteration stalls, which is accepted only below this (default 1e-12).
    pub accept: f64,
    /// Iteration limit (default 20).
    pub max_iterations: usize,
    /// Multiply-adds of every Gram matrix Phi_q Phi_q^T formed ([`RowSpans::gram`]).
    pub(crate) factor_work: u64,
}

impl Projector {
    /// A workspace for the sizes of `info`.
    pub fn new(info: &SystemInfo) -> Self {
        let (n, m) = (info.n(), info.m());
        Self {
            m,
            phi: vec![0.0; m],
            phi_t: vec![0.0; m],
            phi_q: DMatrix::zeros(m, n),
            spans: RowSpans::new(m, n),
            gram: Envelope::new(if m > n { 0 } else { m }),
            normal: (m > n).then(|| (Envelope::new(n), vec![0.0; n])),
            z: vec![0.0; m],
            factored: false,
            tolerance: 1e-14,
            accept: 1e-12,
            max_iterations: 20,
            factor_work: 0,
        }
    }

    /// Fixes the row spans of Phi_q from its structural nonzeros (see
    /// [`RowSpans::fix_ordered`]), in the column order `order` (the mechanism's
    /// `Sparsity::order`; empty for the declaration's): no scan of the dense Jacobian per
    /// projection, and the Gram matrix Phi_q Phi_q^T costs the overlaps of the rows in that
    /// order. With more rows than coordinates the projection factors Phi_q^T Phi_q, indexed
    /// by coordinate, and keeps the declaration's order.
    pub fn fix_ordered(&mut self, pattern: &[(usize, usize)], order: &[usize]) {
        match (&self.normal, order.is_empty()) {
            (None, false) => self.spans.fix_ordered(pattern, order),
            _ => self.spans.fix(pattern),
        }
        match &mut self.normal {
            Some((normal, _)) => {
                normal.reserve(&self.spans.normal_profile((0..normal.dim()).collect()));
            }
            None => self.gram.reserve(&self.spans.gram_profile()),
        }
    }

    /// [`check_jacobian`] of the last Phi_q; with fixed spans it reads the spans only,
    /// unless one of their entries is not finite.
    fn check_jacobian(&self, system: &dyn System, t: f64, q: &[f64]) -> Result<(), Error> {
        if self.spans.is_fixed() && self.spans.all_finite(&self.phi_q) {
            return Ok(());
        }
        check_jacobian(&self.phi_q, system.info(), t, q)
    }

    fn factor_gram(&mut self, t: f64) -> Result<(), Error> {
        self.factored = false;
        self.spans.scan(&self.phi_q);
        // mu from the largest |row|^2, the largest diagonal entry of the Gram matrix.
        let a = self.phi_q.as_slice();
        let m = self.m;
        let scale = (0..m).fold(0.0f64, |worst, r| {
            let row: f64 = self
                .spans
                .span(r)
                .map(|j| a[r + j * m] * a[r + j * m])
                .sum();
            max_nan(worst, row)
        });
        let gram = match &mut self.normal {
            Some((normal, _)) => {
                normal.clear();
                self.spans.add_gram_transpose(&self.phi_q, 1.0, normal);
                normal
            }
            None => {
                self.spans.gram(&self.phi_q, 0.0, &mut self.gram);
                self.factor_work += self.spans.work;
                &mut self.gram
            }
        };
        if !scale.is_finite() {
            return Err(Error::NonFinite {
                what: "constraint Jacobian Phi_q in projection".into(),
                t,
            });
        }
        // A zero Jacobian (scale 0) gets the shift 1: no correction at all.
        let mu = if scale > 0.0 { GRAM_SHIFT * scale } else { 1.0 };
        for i in 0..gram.dim() {
            gram.add(i, i, mu);
        }
        gram.factor(0.0).map_err(|_| Error::NonFinite {
            what: "constraint Jacobian Phi_q in projection".into(),
            t,
        })?;
        self.factored = true;
        Ok(())
    }

    /// Subtracts Phi_q^T (Phi_q Phi_q^T + mu I)^-1 r from x, with r in `self.z` (on the
    /// coordinates' side when m > n, see the module docs).
    fn correct(&mut self, x: &mut [f64]) {
        if let Some((normal, w)) = &mut self.normal {
            self.spans.mul_transpose(&self.phi_q, &self.z, w);
            normal.solve(w);
            for (x, w) in x.iter_mut().zip(w.iter()) {
                *x -= w;
            }
            return;
        }
        self.gram.solve(&mut self.z);
        for r in 0..self.m {
            let zr = self.z[r];
            for k in self.spans.span(r) {
                x[k] -= self.phi_q[(r, k)] * zr;
            }
        }
    }

    /// Projects q onto Phi(q, t) = 0 (minimum-norm Newton); returns the final |Phi|_inf.
    ///
    /// The first corrections reuse the Gram factorisation of the last velocity projection,
    /// made at the previous step's q (simplified Newton: an integrator step moves q so little
    /// that the old Jacobian still contracts the residual by orders of magnitude per
    /// iteration, and it saves a Jacobian and a factorisation per step). As soon as a
    /// correction reduces |Phi| by less than a factor 4, the Jacobian is evaluated at the
    /// current q and Newton goes on from there. The stale corrections leave the minimum-norm
    /// projection by a second-order amount, |dq| times the change of Phi_q over the step.
    pub fn project_positions(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &mut [f64],
    ) -> Result<f64, Error> {
        self.positions(system, t, q, true)
    }

    /// [`Projector::project_positions`], the first corrections reusing the last
    /// factorisation when `reuse` is set, every one from the Jacobian at the current q
    /// otherwise.
    fn positions(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &mut [f64],
        reuse: bool,
    ) -> Result<f64, Error> {
        if self.m == 0 {
            return Ok(0.0);
        }
        let mut stale = reuse && self.factored;
        let mut prev = f64::INFINITY;
        let mut it = 0;
        loop {
            system.constraints(t, q, &mut self.phi);
            let r = inf_norm(&self.phi);
            if !r.is_finite() {
                check_rows("Phi", &self.phi, system.info(), t, q)?;
            }
            if r <= self.tolerance {
                return Ok(r);
            }
            if stale && r > 0.25 * prev {
                stale = false;
            } else if r >= 0.5 * prev && r <= self.accept {
                return Ok(r);
            } else if it == self.max_iterations || r >= prev {
                return Err(Error::NewtonDidNotConverge {
                    t,
                    iterations: it,
                    residual: r,
                    q: q.to_vec(),
                });
            }
            prev = r;
            if !stale {
                system.constraint_jacobian(t, q, &mut self.phi_q, &mut self.phi_t);
                self.check_jacobian(system, t, q)?;
                self.factor_gram(t)?;
            }
            self.z.copy_from_slice(&self.phi);
            self.correct(q);
            it += 1;
        }
    }

    /// Projects q' onto Phi_q q' + Phi_t = 0 at q (one linear solve is exact).
    pub fn project_velocities(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &mut [f64],
    ) -> Result<(), Error> {
        if self.m == 0 {
            return Ok(());
        }
        system.constraint_jacobian(t, q, &mut self.phi_q, &mut self.phi_t);
        self.check_jacobian(system, t, q)?;
        check_rows("Phi_t", &self.phi_t, system.info(), t, q)?;
        self.factor_gram(t)?;
        for i in 0..self.m {
            let span = self.spans.span(i);
            self.z[i] = self.phi_t[i] + span.map(|k| self.phi_q[(i, k)] * qd[k]).sum::<f64>();
        }
        self.correct(qd);
        Ok(())
    }

    /// The projection of a Runge-Kutta stage state (`simulation/rhs.rs`): positions by
    /// Newton with the Jacobian of every iterate (no reuse of an earlier factorisation),
    /// then velocities. A stage lies off Phi = 0 by its own truncation error, far more than
    /// an accepted state, and a correction made with the Jacobian of another q leaves the
    /// minimum-norm projection by |dq| times the change of Phi_q between the two: a
    /// displacement along the constraint manifold that the step's error estimate does not
    /// see (on A02 near its singular positions, energy errors 25 times those of the steps
    /// elsewhere).
    pub(crate) fn project_stage(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &mut [f64],
        qd: &mut [f64],
    ) -> Result<(), Error> {
        self.positions(system, t, q, false)?;
        self.project_velocities(system, t, q, qd)
    }

    /// Positions, then velocities at the projected positions.
    pub fn project(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &mut [f64],
        qd: &mut [f64],
    ) -> Result<(), Error> {
        self.project_positions(system, t, q)?;
        self.project_velocities(system, t, q, qd)
    }
}
