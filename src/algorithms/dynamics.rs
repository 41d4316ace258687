//! Forward dynamics at one instant: the augmented (KKT) system of the index-3 DAE
//!
//! ```text
//! [ M(q)   Phi_q^T ] [ q''    ]   [ tau - C(q, q') q' - g(q) ]
//! [ Phi_q  0       ] [ lambda ] = [ gamma_s                  ]
//! ```
//!
//! (Van Khang 2011; the seed's eq. 2.11 written out), never by inverting M (which may be
//! singular: the seed lumps its rod into two point masses). Three routes give the same q'':
//!
//! - the **null space** of Phi_q ([`crate::linalg::NullSpace`]: LU of Phi_q^T with row
//!   pivoting splits the coordinates into dependent and independent ones, then the reduced
//!   mass Z^T M Z is factored as L D L^T; static sizes for a compiled mechanism), first for
//!   small systems (n + m <= 40), taken when its condition indicator is at most
//!   `condition_limit` * 1e-3 (well clear of the limit, so no estimate is needed);
//! - **LU** with partial pivoting of the whole matrix, for small systems whose null-space
//!   indicator was larger (or that route failed) and whose matrix is regular and well
//!   conditioned (condition estimate <= `condition_limit`); after it fails, the next 64
//!   solves go straight to the next route;
//! - the **banded direct solve** ([`BandedKkt`]) for larger systems whose structural pattern
//!   (`System::sparsity`) orders into a narrow band (b^2 <= n + m: chains, A02; or whose
//!   independent rows do, when there are more rows than coordinates): the rank
//!   of Phi_q found, gamma made consistent, the matrix with the independent rows factored
//!   by banded LU, O(n + m) per solve; with redundant rows and through singular positions
//!   too;
//! - the **augmented Lagrangian** iteration ([`AugmentedLagrangian`]) otherwise: large
//!   systems without a narrow band (factored inside their envelope), small ones with
//!   redundant constraint rows (the matrix above is then singular although q'' is unique),
//!   configurations near a singular one, and whatever the banded solve declines (a pivot
//!   at round-off).
//!
//! An error is raised only where q'' itself is undetermined: M not positive definite on the
//! null space of Phi_q ([`Error::UndeterminedMotion`]). With redundant rows lambda is not
//! unique; [`Dynamics::min_norm_multipliers`] gives the minimum-norm choice. With
//! Baumgarte stabilisation (Baumgarte 1972) the acceleration right-hand side is
//!
//! ```text
//! gamma_s = gamma - 2 alpha (Phi_q q' + Phi_t) - beta^2 Phi,
//! ```
//!
//! otherwise gamma_s = gamma. Sign convention: lambda enters as +Phi_q^T lambda on the left,
//! so the constraint (reaction) forces on the coordinates are -Phi_q^T lambda.

use crate::algorithms::augmented_lagrangian::AugmentedLagrangian;
use crate::algorithms::banded_kkt::BandedKkt;
use crate::algorithms::finite;
use crate::error::Error;
use crate::linalg::{Lu, NullSpace, NullSpaceSolve, RowBasis, inf_norm, max_nan};
use crate::system::{Evaluation, SolverKey, Sparsity, System, SystemInfo};

/// Default limit on the 1-norm condition estimate of the augmented matrix beyond which the
/// LU route hands the solve to the augmented Lagrangian route (where LU would lose more than
/// about 8 of its 16 digits).
pub const DEFAULT_CONDITION_LIMIT: f64 = 1e8;

/// Largest n + m solved by LU first (dense LU costs (n + m)^3 / 3; beyond this the banded
/// augmented Lagrangian route wins for chains, and dense mechanisms this large are rare).
const LU_MAX_ORDER: usize = 40;

/// Solves that go straight to the augmented Lagrangian route after the LU route failed
/// (redundant rows fail every time; a singular position only for a while).
const LU_RETRY_AFTER: usize = 64;

/// Solves between two condition estimates of the augmented matrix (one DOP853 step has 12).
const ESTIMATE_EVERY: usize = 8;

/// Preallocated workspace for the augmented system; [`Dynamics::solve`] allocates nothing.
#[derive(Clone, Debug)]
pub struct Dynamics {
    n: usize,
    m: usize,
    eval: Evaluation,
    /// The null-space route's solver; replaced on the first solve by the system's own
    /// (static sizes) when it has one, which `specialised` records.
    null_space: Box<dyn NullSpaceSolve>,
    specialised: bool,
    lu: Lu,
    sol: Vec<f64>,
    condition: f64,
    /// Solves since the condition was last estimated.
    since_estimate: usize,
    names: Vec<String>,
    augmented: AugmentedLagrangian,
    /// The banded direct route, when the pattern orders into a narrow band.
    banded: Option<BandedKkt>,
    basis: RowBasis,
    direction: Vec<f64>,
    /// Q = tau - C q' - g of the last augmented solve (for the multipliers), and whether the
    /// last solve took that route.
    force: Vec<f64>,
    last_augmented: bool,
    /// Whether the last solve took the banded route (its multipliers are minimum-norm).
    last_banded: bool,
    /// False after a [`Dynamics::solve_accelerations`] that skipped the multipliers.
    multipliers_current: bool,
    /// The system's structural pattern of M and Phi_q, taken on the first solve when it has
    /// one: the large-system route and the finiteness check then read it instead of the
    /// dense matrices.
    sparsity: Option<Sparsity>,
    /// Solves left before the LU route is tried again.
    skip_lu: usize,
    /// Condition-estimate limit of the LU route (default [`DEFAULT_CONDITION_LIMIT`]).
    pub condition_limit: f64,
    /// Solves done by the augmented Lagrangian route.
    pub augmented_solves: usize,
    /// Solves done by the banded direct route.
    pub banded_solves: usize,
    /// Solves of q'' alone done by the system's generated forward dynamics
    /// ([`System::forward_dynamics`]).
    pub generated_solves: usize,
    /// The effort u = 0 handed to [`System::forward_dynamics`] (tau is in the bias).
    zero_effort: Vec<f64>,
    /// Baumgarte (alpha, beta) in 1/s, or `None` for gamma_s = gamma.
    pub baumgarte: Option<(f64, f64)>,
    /// Number of augmented solves performed (right-hand-side evaluations).
    pub evaluations: usize,
    /// Multiply-adds of the rank factorisations of Phi_q outside the banded route.
    factor_work: u64,
}

impl Dynamics {
    /// A workspace for the sizes of `info`.
    pub fn new(info: &SystemInfo) -> Self {
        let (n, m) = (info.n(), info.m());
        Self {
            n,
            m,
            eval: Evaluation::zeros(n, m),
            null_space: Box::new(NullSpace::new(n, m)),
            specialised: false,
            lu: Lu::new(n + m),
            sol: vec![0.0; n + m],
            condition: f64::NAN,
            since_estimate: usize::MAX,
            names: info.coordinates.clone(),
            augmented: AugmentedLagrangian::new(n, m),
            banded: None,
            basis: RowBasis::new(m, n),
            direction: vec![0.0; n],
            force: vec![0.0; n],
            last_augmented: false,
            last_banded: false,
            multipliers_current: true,
            sparsity: None,
            skip_lu: 0,
            condition_limit: DEFAULT_CONDITION_LIMIT,
            augmented_solves: 0,
            banded_solves: 0,
            generated_solves: 0,
            zero_effort: vec![0.0; n],
            baumgarte: None,
            evaluations: 0,
            factor_work: 0,
        }
    }

    /// Multiply-adds of every rank factorisation of Phi_q so far (the rank basis's own count), the
    /// banded route's included: the counted work that depends on the coordinate order.
    pub fn factor_work(&self) -> u64 {
        self.factor_work + self.banded.as_ref().map_or(0, |b| b.factor_work)
    }

    /// Evaluates the system at (t, q, q') and solves the augmented system for q'' and lambda.
    /// The first solve asks `system` for its null-space solver of static sizes
    /// ([`System::null_space_solver`]; one allocation), the later ones allocate nothing.
    ///
    /// Errors: [`Error::NonFiniteTerm`] naming the first entry of M, C q', g, tau, Phi_q,
    /// Phi_t, gamma (or Phi, with Baumgarte) that is NaN or infinite; [`Error::NonFinite`]
    /// when the state or the solution is not finite;
    /// [`Error::UndeterminedMotion`] when M is not positive definite on the null space of
    /// Phi_q (see the module docs).
    pub fn solve(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &[f64],
    ) -> Result<(), Error> {
        self.solve_for(system, t, q, qd, true)
    }

    /// [`Dynamics::solve`] for q'' only, as an integrator's stages need it: the null-space
    /// route then skips the multipliers (their n m + m^2 operations), and
    /// [`Dynamics::multipliers`] must not be read until the next
    /// [`Dynamics::solve`]. Without constraint rows and past [`LU_MAX_ORDER`] coordinates
    /// it asks the system's generated forward dynamics first ([`System::forward_dynamics`]:
    /// O(n) on a chain of links, where evaluating M and factoring it costs O(n^2) and
    /// n^3 / 3; below, the null-space and LU routes on the evaluation cost as little: a
    /// 20-link chain measured 8.0 us per right-hand side by them, 9.1 us by the generated
    /// routine's tape, a 200-link chain 2.8 ms against 0.2 ms); [`Dynamics::evaluation`]
    /// then holds only tau of this state (what [`Dynamics::power`] reads). Where that
    /// routine is absent, or refuses (M not positive definite beyond round-off, or a value
    /// not finite), the solve goes on as [`Dynamics::solve`], whose errors say why. Same
    /// errors.
    pub(crate) fn solve_accelerations(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &[f64],
    ) -> Result<(), Error> {
        self.solve_for(system, t, q, qd, false)
    }

    fn solve_for(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &[f64],
        multipliers: bool,
    ) -> Result<(), Error> {
        let (n, m) = (self.n, self.m);
        self.multipliers_current = true;
        self.last_banded = false;
        self.evaluations += 1;
        if !self.specialised {
            self.specialised = true;
            // The null-space route serves small systems only: a large one never asks for
            // its static-size solver (whose storage grows with n^2).
            if n + m <= LU_MAX_ORDER
                && let Some(solver) = system.null_space_solver(SolverKey::new())
                && solver.dims() == (n, m)
            {
                self.null_space = solver;
            }
            if let Some(s) = system.sparsity()
                && (s.n, s.m) == (n, m)
            {
                self.augmented.fix_ordered(&s.mass, &s.jacobian, &s.order);
                self.basis.fix_ordered(&s.jacobian, &s.order);
                if n + m > LU_MAX_ORDER && m > 0 {
                    let banded = BandedKkt::new(n, m, &s.mass, &s.jacobian, &s.order);
                    self.banded = (banded.is_banded() || m > n).then_some(banded);
                }
                self.sparsity = Some(s.clone());
            }
        }
        if !multipliers && m == 0 && n > LU_MAX_ORDER && self.solve_generated(system, t, q, qd) {
            return Ok(());
        }
        system.evaluate(t, q, qd, &mut self.eval);
        self.load_rhs(qd);
        let lu = n + m <= LU_MAX_ORDER && self.skip_lu == 0;
        self.skip_lu = self.skip_lu.saturating_sub(1);
        // The inputs are checked for NaN and infinity only when the null-space route declines
        // or its solution is not finite: that route reads every entry of Phi_q and the
        // right-hand side and one of each symmetric pair of M (the derivation makes M
        // symmetric), and declines on a non-finite pivot or indicator, so a non-finite input
        // always reaches its solution (a test in `linalg::null_space` tries every entry).
        if lu && self.solve_null_space(multipliers) {
            self.last_augmented = false;
            self.multipliers_current = multipliers;
            // q'' alone carries every input: M, Phi_q, Q and gamma all reach z or v.
            let solved = if multipliers { n + m } else { n };
            let Some(i) = self.sol[..solved].iter().position(|v| !v.is_finite()) else {
                return Ok(());
            };
            self.load_rhs(qd);
            self.check_inputs(system, t, q, qd)?;
            return Err(self.non_finite_solution(i, t));
        }
        // The banded route reads every structural nonzero of M and Phi_q once and tells
        // whether they are finite; only the right-hand side is checked before it. Any
        // other route checks everything first.
        let banded_first = !lu && self.banded.is_some();
        if !banded_first || !self.sol.iter().fold(true, |ok, x| ok & x.is_finite()) {
            self.check_inputs(system, t, q, qd)?;
        }
        self.last_augmented = !(lu && self.solve_lu());
        if lu && self.last_augmented {
            self.skip_lu = LU_RETRY_AFTER;
        }
        if self.last_augmented && !self.solve_banded() {
            if banded_first {
                // Declined: a non-finite entry (the error names it), or a route the inputs
                // are checked for before it runs.
                self.check_inputs(system, t, q, qd)?;
            }
            self.solve_augmented(t, q)?;
        }
        if let Some(i) = self.sol.iter().position(|v| !v.is_finite()) {
            return Err(self.non_finite_solution(i, t));
        }
        Ok(())
    }

    /// q'' by the system's generated forward dynamics, with tau into the evaluation: true
    /// when solved; false when the system has no such routine or it refused.
    fn solve_generated(&mut self, system: &dyn System, t: f64, q: &[f64], qd: &[f64]) -> bool {
        let (qdd, _) = self.sol.split_at_mut(self.n);
        let forces = self.eval.forces.as_mut_slice();
        if system.forward_dynamics(t, q, qd, &self.zero_effort, qdd, forces) != Some(true) {
            return false;
        }
        self.generated_solves += 1;
        self.multipliers_current = false;
        self.last_augmented = false;
        true
    }

    /// The right-hand side [Q; gamma] into `sol`: Q = tau - C q' - g, and gamma (less
    /// 2 alpha Phi' + beta^2 Phi with Baumgarte).
    fn load_rhs(&mut self, qd: &[f64]) {
        let (n, m) = (self.n, self.m);
        let e = &self.eval;
        let (load, rest) = self.sol.split_at_mut(n);
        let (f, c, g) = (
            e.forces.as_slice(),
            e.coriolis.as_slice(),
            e.gravity.as_slice(),
        );
        for (((s, f), c), g) in load.iter_mut().zip(f).zip(c).zip(g) {
            *s = f - c - g;
        }
        rest[..m].copy_from_slice(e.gamma.as_slice());
        if let Some((alpha, beta)) = self.baumgarte {
            for (r, g) in rest[..m].iter_mut().enumerate() {
                let v = e.phi_t[r]
                    + qd.iter()
                        .enumerate()
                        .map(|(j, w)| e.phi_q[(r, j)] * w)
                        .sum::<f64>();
                *g -= 2.0 * alpha * v + beta * beta * e.phi[r];
            }
        }
    }

    /// [`Error::NonFiniteTerm`] (or the state) when M, Phi_q or the right-hand side in `sol`
    /// holds a NaN or an infinity.
    fn check_inputs(
        &self,
        system: &dyn System,
        t: f64,
        q: &[f64],
        qd: &[f64],
    ) -> Result<(), Error> {
        // Passes that the compiler can vectorise (no early exit).
        let all_finite = |v: &[f64]| v.iter().fold(true, |ok, x| ok & x.is_finite());
        let e = &self.eval;
        let matrices = match &self.sparsity {
            Some(s) => s.all_finite(e),
            None => all_finite(e.mass.as_slice()) & all_finite(e.phi_q.as_slice()),
        };
        if matrices & all_finite(&self.sol) {
            return Ok(());
        }
        Err(finite::evaluation_error(
            e,
            system.info(),
            (t, q, qd),
            "the right-hand side tau - C q' - g or gamma of the equations of motion",
        ))
    }

    /// [`Error::NonFinite`] naming entry `i` of the solution [q''; lambda].
    fn non_finite_solution(&self, i: usize, t: f64) -> Error {
        let what = if i < self.n {
            format!("q'' of {}", self.names[i])
        } else {
            format!("lambda_{}", i - self.n + 1)
        };
        Error::NonFinite { what, t }
    }

    /// The null-space route: true (solved in place) when Phi_q has full row rank, Z^T M Z
    /// is positive definite and the route's condition indicator is at most
    /// `condition_limit` * 1e-3; false (nothing solved) otherwise.
    fn solve_null_space(&mut self, multipliers: bool) -> bool {
        let e = &self.eval;
        match self
            .null_space
            .factor(e.mass.as_slice(), e.phi_q.as_slice())
        {
            Some(kappa) if kappa <= self.condition_limit * 1e-3 => {
                if multipliers {
                    self.null_space.solve(&mut self.sol);
                } else {
                    self.null_space.solve_accelerations(&mut self.sol);
                }
                true
            }
            _ => false,
        }
    }

    /// The LU route: factors [M Phi_q^T; Phi_q 0] and solves in place when the matrix is
    /// regular and its condition estimate is within the limit; false (nothing solved)
    /// otherwise.
    fn solve_lu(&mut self) -> bool {
        let (n, m) = (self.n, self.m);
        let e = &self.eval;
        let k = n + m;
        // Column-major fill of [M Phi_q^T; Phi_q 0], column by column.
        let a = self.lu.matrix_mut().as_mut_slice();
        let (mass, phi_q) = (e.mass.as_slice(), e.phi_q.as_slice());
        for j in 0..n {
            let col = &mut a[j * k..(j + 1) * k];
            col[..n].copy_from_slice(&mass[j * n..(j + 1) * n]);
            col[n..].copy_from_slice(&phi_q[j * m..(j + 1) * m]);
        }
        for r in 0..m {
            let col = &mut a[(n + r) * k..(n + r + 1) * k];
            for (j, v) in col[..n].iter_mut().enumerate() {
                *v = phi_q[j * m + r];
            }
            col[n..].fill(0.0);
        }
        if !self.lu.factor() {
            self.condition = f64::INFINITY;
            return false;
        }
        // The Hager-Higham estimate costs several triangular solves, more than the solve
        // itself. Conditioning changes gradually along a trajectory, so it is estimated on
        // every ESTIMATE_EVERY-th solve, and on every solve once it is within a factor 1e3 of
        // the limit (an exactly singular matrix is always caught by the factorisation).
        let near = self.condition.is_nan() || self.condition > self.condition_limit * 1e-3;
        if near || self.since_estimate >= ESTIMATE_EVERY {
            self.condition = self.lu.condition_estimate();
            self.since_estimate = 0;
        }
        self.since_estimate += 1;
        // NaN (no estimate) must hand over too.
        if self.condition.is_nan() || self.condition > self.condition_limit {
            return false;
        }
        self.lu.solve(&mut self.sol);
        true
    }

    /// The banded direct route, with the right-hand side [Q; gamma_s] in `sol`: true (solved
    /// in place, `last_augmented` cleared) when the system has that route and its LU
    /// accepted every pivot; false (nothing solved) otherwise.
    fn solve_banded(&mut self) -> bool {
        let Some(banded) = &mut self.banded else {
            return false;
        };
        let n = self.n;
        let e = &self.eval;
        let (rhs_q, rhs_g) = self.sol.split_at(n);
        if banded.solve(&e.mass, &e.phi_q, rhs_q, rhs_g).is_err() {
            return false;
        }
        self.banded_solves += 1;
        self.last_banded = true;
        self.sol[..n].copy_from_slice(banded.solution());
        self.sol[n..].copy_from_slice(banded.multipliers());
        self.last_augmented = false;
        true
    }

    /// The augmented Lagrangian route, with the right-hand side [Q; gamma_s] in `sol`.
    fn solve_augmented(&mut self, t: f64, q: &[f64]) -> Result<(), Error> {
        let n = self.n;
        self.augmented_solves += 1;
        let (rhs_q, rhs_g) = self.sol.split_at(n);
        self.force.copy_from_slice(rhs_q);
        let e = &self.eval;
        if let Err(failure) = self.augmented.solve(&e.mass, &e.phi_q, rhs_q, rhs_g) {
            self.augmented
                .undetermined_direction(failure, &mut self.direction);
            return Err(self.undetermined(t, q));
        }
        self.sol[..n].copy_from_slice(self.augmented.solution());
        self.sol[n..].copy_from_slice(self.augmented.multipliers());
        Ok(())
    }

    /// [`Error::UndeterminedMotion`] naming the coordinates that move in `self.direction`.
    fn undetermined(&self, t: f64, q: &[f64]) -> Error {
        let mut involved: Vec<(usize, f64)> = (0..self.n)
            .map(|i| (i, self.direction[i].abs()))
            .filter(|&(_, v)| v > 1e-6)
            .collect();
        involved.sort_by(|a, b| b.1.total_cmp(&a.1));
        Error::UndeterminedMotion {
            t,
            coordinates: involved
                .iter()
                .map(|&(i, _)| self.names[i].clone())
                .collect(),
            q: q.to_vec(),
        }
    }

    /// The minimum-norm multipliers of the last solve: lambda with the same forces
    /// Phi_q^T lambda and no component in the null space of Phi_q^T (the part redundant
    /// rows leave undetermined), written over [`Dynamics::multipliers`]. After the LU route
    /// (full rank) they are the LU multipliers; after the augmented Lagrangian route they are
    /// recovered from the constraint force Phi_q^T lambda = Q - M q'', which is accurate to
    /// round-off (the iteration's own lambda carries the penalty's 1e6 eps); the banded
    /// route's are minimum-norm already.
    /// Allocates nothing.
    pub fn min_norm_multipliers(&mut self) -> &[f64] {
        let (n, m) = (self.n, self.m);
        if m == 0 || self.last_banded {
            return &self.sol[n..];
        }
        let e = &self.eval;
        self.basis.factor(&e.phi_q);
        self.factor_work += self.basis.work();
        if self.last_augmented {
            match &self.sparsity {
                // M q'' over M's pattern only (the other entries are zero).
                Some(s) => {
                    self.direction.copy_from_slice(&self.force);
                    for &(i, j) in &s.mass {
                        self.direction[i] -= e.mass[(i, j)] * self.sol[j];
                    }
                }
                None => {
                    for i in 0..n {
                        let mx: f64 = (0..n).map(|j| e.mass[(i, j)] * self.sol[j]).sum();
                        self.direction[i] = self.force[i] - mx;
                    }
                }
            }
            let (_, lambda) = self.sol.split_at_mut(n);
            self.basis
                .multipliers_for(&e.phi_q, &self.direction, lambda);
        } else {
            self.basis.min_norm(&mut self.sol[n..]);
        }
        &self.sol[n..]
    }

    /// q'' from the last [`Dynamics::solve`].
    pub fn accelerations(&self) -> &[f64] {
        &self.sol[..self.n]
    }

    /// lambda from the last [`Dynamics::solve`] (sign: +Phi_q^T lambda on the left side).
    /// After the augmented Lagrangian route these are the iteration's own multipliers,
    /// accurate to about kappa eps = 1e-10 relative and, with redundant rows, one choice among
    /// many: call [`Dynamics::min_norm_multipliers`] for the minimum-norm ones to round-off.
    pub fn multipliers(&self) -> &[f64] {
        debug_assert!(
            self.multipliers_current,
            "multipliers read after solve_accelerations"
        );
        &self.sol[self.n..]
    }

    /// The evaluation (M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi) of the last solve.
    pub fn evaluation(&self) -> &Evaluation {
        &self.eval
    }

    /// 1-norm condition estimate of the augmented matrix from the LU route's latest estimate
    /// (taken at least every 8 of its solves, and at every one near the limit); NaN until
    /// the LU route has run (the null-space route needs no estimate).
    pub fn condition(&self) -> f64 {
        self.condition
    }

    /// Power of the applied forces, tau . q', at the last solve (the integrand of the work W).
    pub fn power(&self, qd: &[f64]) -> f64 {
        self.eval.forces.iter().zip(qd).map(|(f, v)| f * v).sum()
    }

    /// Power of the constraint forces, lambda . Phi_t, at the last [`Dynamics::solve`]: on
    /// the velocity constraints Phi_q q' + Phi_t = 0 it equals -(Phi_q^T lambda) . q', what
    /// moving rows (a driving row `phi - Omega t`, a moving anchor, the a(q, t) of velocity
    /// rows) put into the mechanism; zero for rows that do not depend on t. With it,
    /// d(T + Pi)/dt = tau . q' + lambda . Phi_t (q'^T (M'/2 - C) q' = 0 for Khang's C).
    /// The same for every choice of lambda with redundant rows: Phi_t lies in the range of
    /// Phi_q, where lambda's undetermined part contributes nothing.
    pub fn constraint_power(&self) -> f64 {
        let phi_t = self.eval.phi_t.iter();
        self.multipliers()
            .iter()
            .zip(phi_t)
            .map(|(l, p)| l * p)
            .sum()
    }

    /// Whether Phi_t at the last solve has a nonzero entry (the rows move with t).
    pub(crate) fn constraints_move(&self) -> bool {
        self.eval.phi_t.iter().any(|&v| v != 0.0)
    }

    /// |Phi|_inf at the last solve.
    pub fn constraint_error(&self) -> f64 {
        inf_norm(self.eval.phi.as_slice())
    }

    /// |Phi_q q' + Phi_t|_inf at the last solve.
    pub fn velocity_constraint_error(&self, qd: &[f64]) -> f64 {
        let e = &self.eval;
        if let Some(s) = &self.sparsity {
            // Phi_q q' over Phi_q's pattern (row-major) only.
            let mut worst = 0.0f64;
            let mut entries = s.jacobian.iter().peekable();
            for r in 0..self.m {
                let mut v = e.phi_t[r];
                while let Some(&(_, j)) = entries.next_if(|(row, _)| *row == r) {
                    v += e.phi_q[(r, j)] * qd[j];
                }
                worst = max_nan(worst, v.abs());
            }
            return worst;
        }
        (0..self.m).fold(0.0, |a, r| {
            let v: f64 = e.phi_t[r] + (0..self.n).map(|j| e.phi_q[(r, j)] * qd[j]).sum::<f64>();
            max_nan(a, v.abs())
        })
    }
}
