//! Linearisation about an equilibrium or a steady motion in minimal variables, with exact
//! derivatives: for mechanisms with position rows Phi(q, t) = 0 and velocity rows
//! A(q, t) q' + a(q, t) = 0 (the last `velocity_rows` rows of the stacked G = [Phi_q; A]).
//!
//! A steady motion has q'' = 0: every coordinate at rest or moving at a constant rate, and
//! each moving coordinate cyclic (the equations do not depend on it), so the linearisation
//! does not change along the motion. About it, with the residual
//! F = M q'' + C q' + g - tau + G^T lambda and the constraint residuals w = G q' + b (b the
//! stacked [Phi_t; a]) and R = G q'' - gamma, the tangent dynamics are
//!
//! ```text
//! [M  G^T] [dq''    ]     [F_q dq + F_q' dq']
//! [G  0  ] [dlambda ] = - [R_q dq + R_q' dq']        (dq'' = Q dq + V dq')
//! ```
//!
//! with F_q, F_q' from [`System::tangent`] and R_q, R_q', D = w_q from
//! [`System::constraint_tangent`], all derived symbolically by codegen (no finite
//! differences). The motion stays on the linearised constraints
//! Phi_q dq = 0 (position rows) and D dq + G dq' = 0 (all rows), so it is parametrised by the
//! minimal variables: independent coordinates dq_i (n - p of them, p the independent position
//! rows) and independent speeds du (n - m, m the independent rows): dq = P dq_i,
//! dq' = V_q dq_i + V_u du, the dependent ones from the pivot columns of Phi_q and of G. The state matrix of z = [dq_i; du] is
//!
//! ```text
//! z' = S z,   S = [ rows i of (V_q, V_u)          ]
//!                 [ rows u of Q (P, 0) + V (V_q, V_u) ]
//! ```
//!
//! A variable whose column of S is zero (a cyclic or ignorable coordinate) or whose row is
//! zero (a conserved speed) contributes a structural zero eigenvalue:
//! det(sI - S) = s det(sI - S') with its row and column removed (expanding along that
//! column or row), and S' may have zero rows or columns of its own (the yaw angle's column
//! holds only the rates of the ground position). Those are reported apart from the rest.
//!
//! S is computed in floating point, so a column that is zero in exact arithmetic (a cyclic
//! coordinate's) holds round-off: eps times the terms its entries were computed from, which
//! grow with the entries of their row (the bicycle's yaw column at v = 1e5 m/s holds 1e-6
//! beside entries of 1e10 that carry v^2). An entry is taken as zero when it is at most
//! [`SteadyOptions::structural_tolerance`] times the largest entry of its row or of its
//! column (or 1), a test that follows each row's own scale instead of the whole matrix's
//! (the lean angle's row, `der(phi)` with coefficient 1, is no zero beside 1e10). Where
//! round-off of the largest terms reaches the entries that decide the motion (the gravity
//! terms, 10 1/s^2, beside 1e18 at v = 1e9 m/s), the two cannot be told apart: every
//! eigenvalue printed is checked to be one of S, and the linearisation is refused where the
//! structural zeros depend on the tolerance or S spans more scales than double precision
//! resolves ([`crate::algorithms::structural`]).
//!
//! Redundant rows of G (a planar loop closed with spatial joints, a row that the others imply
//! on the constraint manifold) are dropped first: the rows independent at the state, position
//! rows before velocity rows, define the same motion, and [M G^T; G 0] is regular with them.

use nalgebra::{Complex, DMatrix};

use crate::algorithms::dynamics::Dynamics;
use crate::algorithms::structural::{check_resolved, kept_variables};
use crate::error::Error;
use crate::linalg::{eigenvalues, inf_norm};
use crate::system::{ConstraintTangent, System, SystemInfo, Tangent};

/// Tolerances of [`linearize_steady`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyOptions {
    /// The state is steady when |q''|_inf <= this * (1 + |q'|_inf^2).
    pub steady_tolerance: f64,
    /// A column of the equations for a moving coordinate is zero when its largest entry is
    /// at most this times (1 + the largest entry of its matrix).
    pub zero_tolerance: f64,
    /// An entry S_ij of the state matrix is zero (round-off) when |S_ij| is at most this
    /// times max(1, max_k |S_ik|, max_k |S_kj|): the largest entry of its row or column
    /// (module docs).
    pub structural_tolerance: f64,
    /// A pivot column is independent when its distance to the span of those before it is
    /// above this times its norm.
    pub rank_tolerance: f64,
}

impl Default for SteadyOptions {
    fn default() -> Self {
        Self {
            steady_tolerance: 1e-9,
            zero_tolerance: 1e-10,
            // Round-off of the row's terms is eps (2.2e-16) times them, magnified by the
            // conditioning of the solves that formed S: 1e-12 leaves a factor 4500.
            structural_tolerance: 1e-12,
            rank_tolerance: 1e-8,
        }
    }
}

/// The linearisation of a steady motion in minimal variables (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyLinearization {
    /// The names of the state variables z: the independent coordinates, then `der(name)`
    /// for the independent speeds.
    pub variables: Vec<String>,
    /// The independent coordinates (indices into q).
    pub coordinates: Vec<usize>,
    /// The independent speeds (indices into q').
    pub speeds: Vec<usize>,
    /// S, with z' = S z.
    pub state: DMatrix<f64>,
    /// The eigenvalues of S.
    pub eigenvalues: Vec<Complex<f64>>,
    /// The variables (indices into `variables`) whose column or row of S is zero: each
    /// gives a structural zero eigenvalue.
    pub structural: Vec<usize>,
    /// The eigenvalues of S without the structural variables (S with their rows and
    /// columns removed): the eigenvalues that are not structural zeros.
    pub reduced: Vec<Complex<f64>>,
}

/// Linearises `system` about the steady state (q, q') at time t (module docs); (q, q') must
/// satisfy the constraints (assembled).
///
/// # Errors
/// [`Error::NotSteady`] when q'' is not zero or a moving coordinate is not cyclic;
/// [`Error::Linearization`] when the system provides no exact tangents (a compiled
/// mechanism without velocity rows: build it with [`crate::Interpreted::for_linearization`]),
/// or has a non-finite state matrix, or an eigenvalue that round-off leaves unresolved
/// (module docs); the errors of [`Dynamics::solve`]. Dependent
/// constraint rows are dropped (only the independent rows enter the tangent dynamics).
pub fn linearize_steady(
    system: &dyn System,
    t: f64,
    q: &[f64],
    qd: &[f64],
    options: &SteadyOptions,
) -> Result<SteadyLinearization, Error> {
    let info = system.info();
    let n = info.n();
    let (qv, rows, g, p) = tangent_dynamics(system, t, q, qd, options)?;
    let minimal = minimal_variables(info, &g, p, &rows.velocity, options)?;
    let (ind_q, ind_u) = (minimal.coordinates, minimal.speeds);
    let (top, bottom) = (minimal.positions, minimal.rates);
    let (ni, d) = (ind_q.len(), ind_q.len() + ind_u.len());
    let accelerations = qv.columns(0, n) * &top + qv.columns(n, n) * &bottom;
    let state = DMatrix::from_fn(d, d, |i, j| {
        if i < ni {
            bottom[(ind_q[i], j)]
        } else {
            accelerations[(ind_u[i - ni], j)]
        }
    });
    let mut variables: Vec<String> = ind_q.iter().map(|&j| info.coordinates[j].clone()).collect();
    variables.extend(
        ind_u
            .iter()
            .map(|&j| format!("der({})", info.coordinates[j])),
    );
    let kept = kept_variables(&state, &variables, options.structural_tolerance)?;
    let structural: Vec<usize> = (0..d).filter(|j| !kept.contains(j)).collect();
    let reduced_matrix = state.select_rows(&kept).select_columns(&kept);
    let lin = SteadyLinearization {
        eigenvalues: eigenvalues(&state, "the state matrix S")?,
        reduced: eigenvalues(&reduced_matrix, "S without its structural zeros")?,
        variables,
        coordinates: ind_q,
        speeds: ind_u,
        state,
        structural,
    };
    check_resolved(
        &lin.state,
        &lin.eigenvalues,
        &lin.reduced,
        !lin.structural.is_empty(),
    )?;
    Ok(lin)
}

/// The tangent dynamics at the steady state (module docs): [Q V] (n x 2n, dq'' = Q dq +
/// V dq') from the linearised augmented system, the constraint rows' tangents and
/// G = Phi_q; checks that the state is steady and every moving coordinate cyclic.
fn tangent_dynamics(
    system: &dyn System,
    t: f64,
    q: &[f64],
    qd: &[f64],
    options: &SteadyOptions,
) -> Result<(DMatrix<f64>, ConstraintTangent, DMatrix<f64>, usize), Error> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    for (what, x) in [("q", q), ("qd", qd)] {
        if x.len() != n {
            return Err(Error::WrongLength {
                what,
                expected: n,
                got: x.len(),
            });
        }
    }
    let mut dynamics = Dynamics::new(info);
    dynamics.solve(system, t, q, qd)?;
    let qdd = dynamics.accelerations().to_vec();
    let lambda = dynamics.multipliers().to_vec();
    let mass = dynamics.evaluation().mass.clone();
    let g = dynamics.evaluation().phi_q.clone();
    let limit = options.steady_tolerance * (1.0 + inf_norm(qd).powi(2));
    if let Some(j) = (0..n).find(|&j| qdd[j].abs() > limit) {
        return Err(Error::NotSteady {
            reason: format!("der2({}) = {:e}, not zero", info.coordinates[j], qdd[j]),
        });
    }
    let mut tangent = Tangent::zeros(n);
    system
        .tangent(t, q, qd, &qdd, &lambda, &mut tangent)
        .ok_or_else(|| no_tangent("the dynamic residual"))?;
    let mut rows = ConstraintTangent::zeros(m, n);
    if m > 0 {
        system
            .constraint_tangent(t, q, qd, &qdd, &mut rows)
            .ok_or_else(|| no_tangent("the constraint rows"))?;
    }
    let (keep, p) = independent_rows(&g, info.position_rows(), options.rank_tolerance);
    let (g, m) = (g.select_rows(&keep), keep.len());
    let rows = ConstraintTangent {
        velocity: rows.velocity.select_rows(&keep),
        stiffness: rows.stiffness.select_rows(&keep),
        damping: rows.damping.select_rows(&keep),
    };
    // [Q V] from the linearised augmented system of the independent rows.
    let kkt = DMatrix::from_fn(n + m, n + m, |i, j| match (i < n, j < n) {
        (true, true) => mass[(i, j)],
        (true, false) => g[(j - n, i)],
        (false, true) => g[(i - n, j)],
        (false, false) => 0.0,
    });
    let rhs = DMatrix::from_fn(n + m, 2 * n, |i, j| -match (i < n, j < n) {
        (true, true) => tangent.stiffness[(i, j)],
        (true, false) => tangent.damping[(i, j - n)],
        (false, true) => rows.stiffness[(i - n, j)],
        (false, false) => rows.damping[(i - n, j - n)],
    });
    let solution = kkt.lu().solve(&rhs).ok_or_else(|| Error::Linearization {
        reason: "the augmented matrix [M G^T; G 0] is singular (no inertia along an allowed \
                 motion)"
            .to_string(),
    })?;
    let qv = solution.rows(0, n).into_owned();
    check_cyclic(info, qd, &qv, &rows.velocity, &g, p, options)?;
    Ok((qv, rows, g, p))
}

/// The minimal variables of the linearised motion: the independent coordinates and
/// speeds (indices into q), dq = P dq_i (`positions`, n x d) and dq' = V_q dq_i + V_u du
/// (`rates`, n x d), d the number of minimal variables.
struct MinimalVariables {
    coordinates: Vec<usize>,
    speeds: Vec<usize>,
    positions: DMatrix<f64>,
    rates: DMatrix<f64>,
}

/// Dependent coordinates from the pivot columns of Phi_q, dependent speeds from those of
/// G (declared independent coordinates kept independent where they can be), and the maps
/// from the minimal variables to dq and dq' (D dq + G dq' = 0, D = `velocity`).
fn minimal_variables(
    info: &SystemInfo,
    g: &DMatrix<f64>,
    p: usize,
    velocity: &DMatrix<f64>,
    options: &SteadyOptions,
) -> Result<MinimalVariables, Error> {
    let (n, m) = (info.n(), g.nrows());
    let declared: Vec<usize> = info.independent.iter().map(|i| i.coordinate).collect();
    let preference = |first: &[usize]| -> Vec<usize> {
        let mut order: Vec<usize> = first.to_vec();
        order.extend((0..n).filter(|j| !first.contains(j) && !declared.contains(j)));
        let rest: Vec<usize> = (0..n).filter(|j| !order.contains(j)).collect();
        order.extend(rest);
        order
    };
    let position_rows = g.rows(0, p).into_owned();
    let dep_q = pivot_columns(&position_rows, &preference(&[]), options.rank_tolerance)?;
    let dep_u = pivot_columns(g, &preference(&dep_q), options.rank_tolerance)?;
    let ind_q: Vec<usize> = (0..n).filter(|j| !dep_q.contains(j)).collect();
    let ind_u: Vec<usize> = (0..n).filter(|j| !dep_u.contains(j)).collect();
    let (ni, nu) = (ind_q.len(), ind_u.len());
    let d = ni + nu;

    // dq = P dq_i.
    let mut top = DMatrix::zeros(n, d);
    for (k, &j) in ind_q.iter().enumerate() {
        top[(j, k)] = 1.0;
    }
    if p > 0 {
        let phi_dep = columns(&position_rows, &dep_q);
        let phi_ind = columns(&position_rows, &ind_q);
        let x = solve(&phi_dep, &(-phi_ind))?;
        for (r, &j) in dep_q.iter().enumerate() {
            for k in 0..ni {
                top[(j, k)] = x[(r, k)];
            }
        }
    }
    // dq' = V_q dq_i + V_u du, from D dq + G dq' = 0.
    let mut bottom = DMatrix::zeros(n, d);
    for (k, &j) in ind_u.iter().enumerate() {
        bottom[(j, ni + k)] = 1.0;
    }
    if m > 0 {
        let known = velocity * &top + columns(g, &ind_u) * bottom.select_rows(&ind_u);
        let x = solve(&columns(g, &dep_u), &(-known))?;
        for (r, &j) in dep_u.iter().enumerate() {
            for k in 0..d {
                bottom[(j, k)] = x[(r, k)];
            }
        }
    }
    Ok(MinimalVariables {
        coordinates: ind_q,
        speeds: ind_u,
        positions: top,
        rates: bottom,
    })
}

fn no_tangent(what: &str) -> Error {
    Error::Linearization {
        reason: format!(
            "the system provides no exact tangent of {what} (build it with Interpreted::for_linearization)"
        ),
    }
}

/// Each coordinate moving at a nonzero rate must be cyclic: its columns of [Q V]'s Q part,
/// of D and of the position rows of G zero.
fn check_cyclic(
    info: &crate::system::SystemInfo,
    qd: &[f64],
    qv: &DMatrix<f64>,
    velocity: &DMatrix<f64>,
    g: &DMatrix<f64>,
    p: usize,
    options: &SteadyOptions,
) -> Result<(), Error> {
    let n = info.n();
    let largest = qv.amax().max(velocity.amax()).max(g.amax());
    let limit = options.zero_tolerance * (1.0 + largest);
    let moving = options.steady_tolerance * (1.0 + inf_norm(qd));
    for j in (0..n).filter(|&j| qd[j].abs() > moving) {
        let column = (0..n)
            .map(|i| qv[(i, j)].abs())
            .chain((0..velocity.nrows()).map(|r| velocity[(r, j)].abs()))
            .chain((0..p).map(|r| g[(r, j)].abs()))
            .fold(0.0, f64::max);
        if column > limit {
            return Err(Error::NotSteady {
                reason: format!(
                    "`{}` moves (rate {:e}) but the equations depend on it (it is not cyclic)",
                    info.coordinates[j], qd[j]
                ),
            });
        }
    }
    Ok(())
}

/// The columns of `a` picked greedily in `order`, each independent of those before it
/// (Gram-Schmidt, twice), until rank(a) = rows of them are found.
fn pivot_columns(a: &DMatrix<f64>, order: &[usize], tolerance: f64) -> Result<Vec<usize>, Error> {
    let rows = a.nrows();
    let mut picked = independent_columns(a, order, tolerance);
    if picked.len() < rows {
        return Err(Error::Linearization {
            reason: format!(
                "the constraint rows have rank {} < {rows} after the dependent rows were \
                 dropped",
                picked.len()
            ),
        });
    }
    picked.sort_unstable();
    Ok(picked)
}

/// The columns of `a` picked greedily in `order`, each at a distance above `tolerance`
/// times its norm from the span of those picked before it (Gram-Schmidt, twice), up to
/// as many as `a` has rows.
fn independent_columns(a: &DMatrix<f64>, order: &[usize], tolerance: f64) -> Vec<usize> {
    let rows = a.nrows();
    let mut basis: Vec<nalgebra::DVector<f64>> = Vec::with_capacity(rows);
    let mut picked = Vec::with_capacity(rows);
    for &j in order {
        if picked.len() == rows {
            break;
        }
        let column = a.column(j).into_owned();
        let norm = column.norm();
        if norm == 0.0 {
            continue;
        }
        let mut r = column;
        for _ in 0..2 {
            for b in &basis {
                let c = b.dot(&r);
                r -= b * c;
            }
        }
        let rn = r.norm();
        if rn > tolerance * norm {
            basis.push(r / rn);
            picked.push(j);
        }
    }
    picked
}

/// The independent rows of G = [Phi_q; A] (`p` position rows first): the position rows
/// independent of those before them, then the velocity rows independent of all kept rows
/// before them. Returns the kept rows in order and how many of them are position rows.
/// Redundant rows (a planar loop written with spatial joints, a row implied by others on
/// the constraint manifold) hold wherever the kept rows do, so the motion and its
/// linearisation are those of the kept rows.
fn independent_rows(g: &DMatrix<f64>, p: usize, tolerance: f64) -> (Vec<usize>, usize) {
    let gt = g.transpose();
    let order: Vec<usize> = (0..g.nrows()).collect();
    let position = independent_columns(&gt.columns(0, p).into_owned(), &order[..p], tolerance);
    let kept_positions = position.len();
    let mut all = position;
    let velocity_order: Vec<usize> = all.iter().copied().chain(p..g.nrows()).collect();
    let velocity = independent_columns(&gt, &velocity_order, tolerance);
    all.extend(velocity.into_iter().filter(|&r| r >= p));
    (all, kept_positions)
}

fn columns(a: &DMatrix<f64>, cols: &[usize]) -> DMatrix<f64> {
    a.select_columns(cols)
}

fn solve(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, Error> {
    a.clone().lu().solve(b).ok_or_else(|| Error::Linearization {
        reason: "the dependent columns of the constraint rows are singular".to_string(),
    })
}
