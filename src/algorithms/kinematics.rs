//! Assembly and kinematic analysis: consistent positions, velocities and accelerations from
//! the independent coordinates.
//!
//! With the coordinates split into fixed ones u (independent or driven, values given) and
//! dependent ones v, the three levels are (Haug, Computer-Aided Kinematics and Dynamics of
//! Mechanical Systems, 1989, ch. 3; Nikravesh 1988, ch. 3):
//!
//! ```text
//! positions      Phi(u, v, t) = 0                       damped Newton in v
//! velocities     Phi_v v' = -Phi_t - Phi_u u'            linear
//! accelerations  Phi_v v'' = gamma - Phi_u u''            linear, gamma as in `Evaluation`
//! ```
//!
//! These routines allocate (they use an SVD for rank-robust least-squares steps, or LU where
//! the system is square and certainly well-conditioned, which gives the SVD's answer:
//! [`crate::linalg::conditioned_solve`]); they run at assembly time and per output sample,
//! never inside the integrator's step loop.

use std::fmt;
use std::sync::Arc;

use nalgebra::DMatrix;

use crate::algorithms::finite::{check_jacobian, check_rows};
use crate::algorithms::reach::{Stall, classify};
use crate::algorithms::velocity_rows::check_velocity_rows;
use crate::error::Error;
use crate::linalg::{
    MAX_CERTIFIED_CONDITION, conditioned_solve, inf_norm, least_squares, rank_and_least_squares,
};
use crate::system::{Evaluation, Independent, Kinematic, System, SystemInfo};

/// Tolerances of the position Newton iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AssemblyOptions {
    /// Converged when |Phi|_inf is at most this (constraint units, e.g. m) ...
    pub tolerance: f64,
    /// ... and the last Newton step is at most `step_tolerance * (1 + |q|_inf)`.
    pub step_tolerance: f64,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Singular values below `rank_tolerance * sigma_max` count as zero (rank tests).
    pub rank_tolerance: f64,
    /// A failed iteration whose dependent Jacobian has a condition above this is reported as
    /// [`Error::SingularConfiguration`] (the mechanism cannot be assembled there: a dead
    /// point or a position out of reach) instead of [`Error::NewtonDidNotConverge`].
    pub singular_condition: f64,
}

impl Default for AssemblyOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            step_tolerance: 1e-14,
            max_iterations: 50,
            rank_tolerance: 1e-10,
            singular_condition: 1e6,
        }
    }
}

/// A prescribed motion q_k = f(t) of one coordinate, i.e. the driver constraint
/// q_k - f(t) = 0 (Haug 1989, sec. 3.5). `f(t)` returns [f, f', f''].
#[derive(Clone)]
pub struct Drive {
    /// Index of the driven coordinate in q.
    pub coordinate: usize,
    /// t -> [f(t), f'(t), f''(t)].
    pub f: Arc<dyn Fn(f64) -> [f64; 3] + Send + Sync>,
}

impl Drive {
    /// A drive of coordinate index `coordinate`.
    pub fn new(coordinate: usize, f: impl Fn(f64) -> [f64; 3] + Send + Sync + 'static) -> Self {
        Self {
            coordinate,
            f: Arc::new(f),
        }
    }

    /// A drive of the coordinate called `name`, or [`Error::UnknownCoordinate`].
    pub fn by_name(
        info: &SystemInfo,
        name: &str,
        f: impl Fn(f64) -> [f64; 3] + Send + Sync + 'static,
    ) -> Result<Self, Error> {
        let k = info
            .coordinate_index(name)
            .ok_or_else(|| Error::UnknownCoordinate {
                name: name.to_string(),
                known: info.coordinates.clone(),
            })?;
        Ok(Self::new(k, f))
    }
}

impl fmt::Debug for Drive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Drive")
            .field("coordinate", &self.coordinate)
            .finish_non_exhaustive()
    }
}

/// A consistent kinematic state at time t.
#[derive(Clone, Debug, PartialEq)]
pub struct KinematicState {
    /// Time (s).
    pub t: f64,
    /// Positions q with Phi(q, t) = 0.
    pub q: Vec<f64>,
    /// Rates q' with Phi_q q' + Phi_t = 0.
    pub qd: Vec<f64>,
    /// Accelerations q'' with Phi_q q'' = gamma (zero when not computed).
    pub qdd: Vec<f64>,
}

/// Checks driver/independent indices: in range and not repeated.
pub(crate) fn check_fixed(info: &SystemInfo, fixed: &[usize]) -> Result<(), Error> {
    let n = info.n();
    for (i, &k) in fixed.iter().enumerate() {
        if k >= n {
            return Err(Error::UnknownDriver { coordinate: k, n });
        }
        if fixed[..i].contains(&k) {
            return Err(Error::RepeatedCoordinate {
                name: info.coordinates[k].clone(),
            });
        }
    }
    Ok(())
}

fn dependent_of(n: usize, fixed: &[usize]) -> Vec<usize> {
    (0..n).filter(|k| !fixed.contains(k)).collect()
}

fn columns(a: &DMatrix<f64>, cols: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), cols.len(), |i, j| a[(i, cols[j])])
}

fn not_determined(info: &SystemInfo, fixed: &[usize], dependent: usize, rank: usize) -> Error {
    Error::IndependentSetDoesNotDetermine {
        independent: fixed.iter().map(|&k| info.coordinates[k].clone()).collect(),
        dependent,
        rank,
    }
}

/// Solves Phi(q, t) = 0 for the coordinates not in `fixed`, starting from `q` (which holds the
/// fixed values and the guesses for the rest); on success `q` is the assembled configuration.
///
/// Damped Newton (Gauss–Newton when there are more rows than dependent coordinates):
/// Phi_v dv = -Phi, minimum-norm least squares by SVD, step halved until |Phi|_2 decreases.
/// Converged when |Phi|_inf <= tolerance and the step is below step_tolerance (1 + |q|_inf).
/// Returns the iterations used.
pub fn solve_positions(
    system: &dyn Kinematic,
    t: f64,
    fixed: &[usize],
    q: &mut [f64],
    options: &AssemblyOptions,
) -> Result<usize, Error> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    check_fixed(info, fixed)?;
    if q.len() != n {
        return Err(Error::WrongLength {
            what: "q",
            expected: n,
            got: q.len(),
        });
    }
    Error::check_finite(q, "initial guess", &info.coordinates, t)?;
    let dep = dependent_of(n, fixed);
    if m < dep.len() {
        return Err(not_determined(info, fixed, dep.len(), m));
    }
    let mut phi = vec![0.0; m];
    let mut phi_t = vec![0.0; m];
    let mut trial = q.to_vec();
    let mut phi_q = DMatrix::zeros(m, n);
    // With nothing to solve for, only the residual test remains.
    let mut last_step = if dep.is_empty() { 0.0 } else { f64::INFINITY };
    let mut residual = f64::INFINITY;
    for it in 0..=options.max_iterations {
        system.constraints(t, q, &mut phi);
        // NaN-propagating: one NaN row must not read as a small residual.
        let r = inf_norm(&phi);
        if !r.is_finite() {
            check_rows("Phi", &phi, info, t, q)?;
        }
        residual = r;
        let scale = 1.0 + inf_norm(q);
        if r <= options.tolerance && last_step <= options.step_tolerance * scale {
            return Ok(it);
        }
        if it == options.max_iterations || dep.is_empty() {
            break;
        }
        system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
        check_jacobian(&phi_q, info, t, q)?;
        let a = columns(&phi_q, &dep);
        let rhs: Vec<f64> = phi.iter().map(|v| -v).collect();
        // A square, well-conditioned Phi_v (a mechanism away from its singular positions)
        // by LU; the SVD's minimum-norm least squares otherwise.
        let dx = conditioned_solve(&a, &rhs, MAX_CERTIFIED_CONDITION)
            .unwrap_or_else(|| least_squares(&a, &rhs, 1e-14));
        let step = inf_norm(&dx);
        let Some(alpha) = line_search(system, t, q, &dep, &dx, &mut trial, &mut phi) else {
            if r <= options.tolerance {
                return Ok(it); // the residual is at round-off level and cannot decrease
            }
            break; // stalled at a least-squares point with Phi != 0
        };
        q.copy_from_slice(&trial);
        last_step = alpha * step;
        if step <= options.step_tolerance * scale && r <= options.tolerance {
            return Ok(it + 1);
        }
    }
    if !dep.is_empty()
        && let Some(condition) = cannot_pass(system, t, q, &dep, options)
    {
        return Err(Error::SingularConfiguration {
            t,
            q: q.to_vec(),
            condition,
        });
    }
    Err(Error::NewtonDidNotConverge {
        t,
        iterations: options.max_iterations,
        residual,
        q: q.to_vec(),
    })
}

/// Armijo backtracking on |Phi|_2^2 along the Newton step dx of the dependent coordinates:
/// the largest alpha = 2^-k (k < 30) with a sufficient decrease, the trial point left in
/// `trial`; `None` when none decreases the residual (a stalled least-squares point). `phi`
/// holds Phi(q) on entry and Phi(trial) on exit.
fn line_search(
    system: &dyn Kinematic,
    t: f64,
    q: &[f64],
    dep: &[usize],
    dx: &[f64],
    trial: &mut [f64],
    phi: &mut [f64],
) -> Option<f64> {
    let r2 = phi.iter().map(|v| v * v).sum::<f64>();
    let mut alpha = 1.0;
    for _ in 0..30 {
        trial.copy_from_slice(q);
        for (j, &k) in dep.iter().enumerate() {
            trial[k] += alpha * dx[j];
        }
        system.constraints(t, trial, phi);
        let r2_try = phi.iter().map(|v| v * v).sum::<f64>();
        if r2_try.is_finite() && (r2_try < (1.0 - 1e-4 * alpha) * r2 || r2_try == 0.0) {
            return Some(alpha);
        }
        alpha *= 0.5;
    }
    None
}

/// After Newton failed at `q`: `Some(condition of Phi_v)` when `q` bears one of the two
/// signatures of a configuration the mechanism cannot pass (a dead point, a position out of
/// reach), else `None` (Newton simply did not converge). The signatures: the dependent
/// Jacobian Phi_v is (nearly) singular, or the residual Phi that Newton cannot remove lies
/// almost entirely outside the span of the well-conditioned left singular directions of
/// Phi_v (Gauss-Newton creeping towards a fold of the constraint manifold).
fn cannot_pass(
    system: &dyn Kinematic,
    t: f64,
    q: &[f64],
    dep: &[usize],
    options: &AssemblyOptions,
) -> Option<f64> {
    let (n, m) = (system.info().n(), system.info().m());
    let mut phi = vec![0.0; m];
    let mut phi_t = vec![0.0; m];
    let mut phi_q = DMatrix::zeros(m, n);
    system.constraints(t, q, &mut phi);
    system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
    let svd = columns(&phi_q, dep).svd(true, false);
    let sv = &svd.singular_values;
    let (imax, imin) = (sv.imax(), sv.imin());
    let condition = if sv[imin] > 0.0 {
        sv[imax] / sv[imin]
    } else {
        f64::INFINITY
    };
    let pnorm = phi.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut unreachable = 0.0;
    if let Some(u) = &svd.u {
        let mut reach2 = 0.0;
        for i in (0..sv.len()).filter(|&i| i != imin) {
            let c: f64 = (0..m).map(|r| u[(r, i)] * phi[r]).sum();
            reach2 += c * c;
        }
        unreachable = ((pnorm * pnorm - reach2).max(0.0)).sqrt() / pnorm.max(1e-300);
    }
    (condition > options.singular_condition || (unreachable > 0.9 && condition > 4.0))
        .then_some(condition)
}

/// Solves Phi_v v' = -Phi_t - Phi_u u' for the rates of the coordinates not in `fixed`
/// (`qd` holds the fixed rates on entry). Least squares by SVD; reports
/// [`Error::SingularConfiguration`] when Phi_v is rank deficient at q.
pub fn solve_velocities(
    system: &dyn Kinematic,
    t: f64,
    q: &[f64],
    fixed: &[usize],
    qd: &mut [f64],
    options: &AssemblyOptions,
) -> Result<(), Error> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    let mut phi_q = DMatrix::zeros(m, n);
    let mut phi_t = vec![0.0; m];
    system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
    check_jacobian(&phi_q, info, t, q)?;
    check_rows("Phi_t", &phi_t, info, t, q)?;
    let rhs: Vec<f64> = (0..m)
        .map(|i| -phi_t[i] - fixed.iter().map(|&k| phi_q[(i, k)] * qd[k]).sum::<f64>())
        .collect();
    solve_dependent(info, t, q, fixed, &phi_q, &rhs, qd, options)
}

/// Solves Phi_v v'' = gamma - Phi_u u'' for the accelerations of the coordinates not in
/// `fixed` (`qdd` holds the fixed accelerations on entry); gamma from [`System::evaluate`].
pub fn solve_accelerations(
    system: &dyn System,
    t: f64,
    q: &[f64],
    qd: &[f64],
    fixed: &[usize],
    qdd: &mut [f64],
    options: &AssemblyOptions,
) -> Result<(), Error> {
    let info = system.info();
    let mut e = Evaluation::zeros(info.n(), info.m());
    system.evaluate(t, q, qd, &mut e);
    check_jacobian(&e.phi_q, info, t, q)?;
    check_rows("gamma", e.gamma.as_slice(), info, t, q)?;
    let rhs: Vec<f64> = (0..info.m())
        .map(|i| e.gamma[i] - fixed.iter().map(|&k| e.phi_q[(i, k)] * qdd[k]).sum::<f64>())
        .collect();
    solve_dependent(info, t, q, fixed, &e.phi_q, &rhs, qdd, options)
}

#[allow(clippy::too_many_arguments)]
fn solve_dependent(
    info: &SystemInfo,
    t: f64,
    q: &[f64],
    fixed: &[usize],
    phi_q: &DMatrix<f64>,
    rhs: &[f64],
    out: &mut [f64],
    options: &AssemblyOptions,
) -> Result<(), Error> {
    let dep = dependent_of(info.n(), fixed);
    if dep.is_empty() {
        return Ok(());
    }
    let a = columns(phi_q, &dep);
    // A square Phi_v whose condition is certainly small has full rank by the SVD's test as
    // well (its tolerance is above 1 / MAX_CERTIFIED_CONDITION), and LU gives the SVD's
    // solution. Otherwise one SVD, O(m d^2), for both the rank test and the solution.
    let certified = (options.rank_tolerance * MAX_CERTIFIED_CONDITION < 1.0)
        .then(|| conditioned_solve(&a, rhs, MAX_CERTIFIED_CONDITION))
        .flatten();
    let (rank, s, x) = match certified {
        Some(x) => (dep.len(), Vec::new(), x),
        None => rank_and_least_squares(&a, rhs, options.rank_tolerance, 1e-14),
    };
    if rank < dep.len() {
        if info.m() < dep.len() {
            return Err(not_determined(info, fixed, dep.len(), rank));
        }
        let smin = s.get(dep.len() - 1).copied().unwrap_or(0.0);
        let condition = if smin > 0.0 {
            s[0] / smin
        } else {
            f64::INFINITY
        };
        return Err(Error::SingularConfiguration {
            t,
            q: q.to_vec(),
            condition,
        });
    }
    for (j, &k) in dep.iter().enumerate() {
        out[k] = x[j];
    }
    Error::check_finite(out, "rate", &info.coordinates, t)
}

/// Consistent initial state from independent coordinates: q_k = position, q_k' = velocity
/// for each entry of `independent`; the rest by Newton from `guess` (positions), then
/// Phi_q q' = -Phi_t (velocities). Redundant position rows are accepted (see
/// [`crate::mobility()`]); a velocity row that is a combination of the rows above it is
/// not ([`Error::VelocityRowRedundant`], [`Error::VelocityRowContradicts`]); the
/// independent set must determine the others. Where the constraints cannot be closed
/// (`algorithms/reach.rs` tells why): [`Error::GivenOutOfReach`] when the given values
/// admit no position (naming the nearest that do), [`Error::ConstraintsUnsatisfiable`]
/// when no nearby given value would help, naming the rows left with a residual, and
/// [`Error::NewtonDidNotConverge`] when Newton lost its way from the guesses.
pub fn assemble_from(
    system: &dyn Kinematic,
    t: f64,
    independent: &[Independent],
    guess: &[f64],
    options: &AssemblyOptions,
) -> Result<KinematicState, Error> {
    let info = system.info();
    let fixed: Vec<usize> = independent.iter().map(|i| i.coordinate).collect();
    check_fixed(info, &fixed)?;
    if guess.len() != info.n() {
        return Err(Error::WrongLength {
            what: "guess",
            expected: info.n(),
            got: guess.len(),
        });
    }
    let mut q = guess.to_vec();
    let mut qd = vec![0.0; info.n()];
    for ind in independent {
        q[ind.coordinate] = ind.position;
        qd[ind.coordinate] = ind.velocity;
    }
    over_specified(system, t, independent, &q, options)?;
    solve_positions(system, t, &fixed, &mut q, options).map_err(|e| {
        let stuck = match &e {
            Error::SingularConfiguration { q, .. } | Error::NewtonDidNotConverge { q, .. } => q,
            _ => return e,
        };
        match classify(system, t, stuck, &fixed, options.tolerance) {
            Stall::GivenOutOfReach { nearest } => out_of_reach(system, t, &fixed, stuck, &nearest),
            Stall::Unsatisfiable => unsatisfiable(system, t, stuck.clone()),
            // The residual still falls from where Newton stopped (a start on a symmetry
            // line, on the wrong side of a fold): a closer guess gets through.
            Stall::Saddle => Error::NewtonDidNotConverge {
                t,
                iterations: options.max_iterations,
                residual: largest_rows(system, t, stuck).0,
                q: stuck.clone(),
            },
            // At assembly there is no motion to be singular: Newton stopped where the
            // loops cannot be closed.
            Stall::Undecided => match e {
                Error::SingularConfiguration { q: stuck, .. } => unsatisfiable(system, t, stuck),
                other => other,
            },
        }
    })?;
    check_velocity_rows(system, t, &q, options.rank_tolerance)?;
    solve_velocities(system, t, &q, &fixed, &mut qd, options)?;
    Ok(KinematicState {
        t,
        q,
        qd,
        qdd: vec![0.0; info.n()],
    })
}

/// [`Error::OverSpecified`] when more coordinates are given than the mechanism's degrees
/// of freedom (n minus the rank of Phi_q where the positions are solved from `q`, the
/// guesses with the given values, or at `q` when they cannot be), naming the constraint
/// rows the values violate when every coordinate is given.
fn over_specified(
    system: &dyn Kinematic,
    t: f64,
    independent: &[Independent],
    q: &[f64],
    options: &AssemblyOptions,
) -> Result<(), Error> {
    let info = system.info();
    if independent.len() <= info.n().saturating_sub(info.m()) {
        return Ok(()); // within Grubler's count: never more than the degrees of freedom
    }
    let Ok(mut mob) = crate::algorithms::mobility::mobility(system, t, q) else {
        return Ok(()); // a non-finite Jacobian: left to the assembly to name
    };
    if independent.len() <= mob.degrees_of_freedom {
        return Ok(());
    }
    // The guesses are off the constraint manifold, where a row that the others imply only
    // on it (x^2 + y^2 = L^2 beside x = L sin th, y = -L cos th) looks independent: the
    // rank that counts is the one where the constraints hold, if they can be closed.
    let fixed: Vec<usize> = independent.iter().map(|i| i.coordinate).collect();
    let mut solved = q.to_vec();
    if solve_positions(system, t, &fixed, &mut solved, options).is_ok()
        && let Ok(there) = crate::algorithms::mobility::mobility(system, t, &solved)
    {
        if independent.len() <= there.degrees_of_freedom {
            return Ok(());
        }
        mob = there;
    }
    let mut violated = Vec::new();
    if independent.len() == info.n() {
        let mut phi = vec![0.0; info.m()];
        system.constraints(t, q, &mut phi);
        violated = (0..info.m())
            .filter(|&r| phi[r].is_nan() || phi[r].abs() > options.tolerance)
            .map(|r| format!("{} by {:.3e}", info.constraint_label(r), phi[r]))
            .collect();
    }
    Err(Error::OverSpecified {
        given: independent
            .iter()
            .map(|i| info.coordinates[i.coordinate].clone())
            .collect(),
        degrees_of_freedom: mob.degrees_of_freedom,
        violated,
    })
}

/// The residual |Phi|_inf at `q` and the rows whose residual is within a factor 10 of it.
fn largest_rows(system: &dyn Kinematic, t: f64, q: &[f64]) -> (f64, Vec<String>) {
    let info = system.info();
    let mut phi = vec![0.0; info.m()];
    system.constraints(t, q, &mut phi);
    let residual = inf_norm(&phi);
    let rows = (0..info.m())
        .filter(|&r| phi[r].abs() >= 0.1 * residual)
        .map(|r| info.constraint_label(r))
        .collect();
    (residual, rows)
}

/// [`Error::ConstraintsUnsatisfiable`] at `q`, naming the rows whose residual is within a
/// factor 10 of the largest.
fn unsatisfiable(system: &dyn Kinematic, t: f64, q: Vec<f64>) -> Error {
    let (residual, rows) = largest_rows(system, t, &q);
    Error::ConstraintsUnsatisfiable {
        t,
        residual,
        rows,
        q,
    }
}

/// [`Error::GivenOutOfReach`] at `q`: the given coordinates (of `fixed`) that `nearest`
/// moves, or all of them when it moves none beyond round-off.
fn out_of_reach(
    system: &dyn Kinematic,
    t: f64,
    fixed: &[usize],
    q: &[f64],
    nearest: &[f64],
) -> Error {
    let info = system.info();
    let moved = |&&k: &&usize| (nearest[k] - q[k]).abs() > 1e-9 * (1.0 + q[k].abs());
    let mut named: Vec<usize> = fixed.iter().filter(moved).copied().collect();
    if named.is_empty() {
        named = fixed.to_vec();
    }
    let short = |x: f64| format!("{x:.6e}").parse::<f64>().unwrap_or(x);
    let (residual, rows) = largest_rows(system, t, q);
    Error::GivenOutOfReach {
        t,
        values: (named.iter())
            .map(|&k| (info.coordinates[k].clone(), q[k], short(nearest[k])))
            .collect(),
        residual,
        rows,
        q: q.to_vec(),
    }
}

/// [`assemble_from`] with the declared independent coordinates and initial guesses.
pub fn assemble(
    system: &dyn Kinematic,
    t: f64,
    options: &AssemblyOptions,
) -> Result<KinematicState, Error> {
    let info = system.info();
    assemble_from(system, t, &info.independent, &info.initial_guess, options)
}

/// Kinematic analysis for a prescribed motion: at each time, the driven coordinates follow
/// their [`Drive`]s and the others follow from positions, velocities and accelerations as in
/// the module equations. Each solve starts from the previous configuration (the first from
/// the declared guesses), so the assembly branch is followed continuously.
pub fn kinematic_analysis(
    system: &dyn System,
    drives: &[Drive],
    times: &[f64],
    options: &AssemblyOptions,
) -> Result<Vec<KinematicState>, Error> {
    let info = system.info();
    let fixed: Vec<usize> = drives.iter().map(|d| d.coordinate).collect();
    check_fixed(info, &fixed)?;
    let n = info.n();
    let mut q = info.initial_guess.clone();
    let mut out = Vec::with_capacity(times.len());
    for &t in times {
        let mut qd = vec![0.0; n];
        let mut qdd = vec![0.0; n];
        for d in drives {
            let [f, fd, fdd] = (d.f)(t);
            if !(f.is_finite() && fd.is_finite() && fdd.is_finite()) {
                return Err(Error::NonFinite {
                    what: format!("drive of {}", info.coordinates[d.coordinate]),
                    t,
                });
            }
            q[d.coordinate] = f;
            qd[d.coordinate] = fd;
            qdd[d.coordinate] = fdd;
        }
        solve_positions(system, t, &fixed, &mut q, options)?;
        solve_velocities(system, t, &q, &fixed, &mut qd, options)?;
        solve_accelerations(system, t, &q, &qd, &fixed, &mut qdd, options)?;
        out.push(KinematicState {
            t,
            q: q.clone(),
            qd,
            qdd,
        });
    }
    Ok(out)
}
