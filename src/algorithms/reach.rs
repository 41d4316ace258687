//! Why an assembly stopped with Phi != 0: the given values admit no position, the
//! constraints cannot be met near there whatever the given values, or Newton lost its way
//! from the guess while a position exists.
//!
//! At the point q* where the damped Gauss-Newton of `solve_positions` stopped, with the
//! given coordinates u fixed and the dependent ones v free, f(v) = |Phi|^2 / 2 (position
//! rows only: the velocity rows have no residual) and:
//!
//! 1. **A floor of the residual.** The quadratic model of f about q* has the gradient
//!    g = Phi_v^T Phi and the Hessian H = Phi_v^T Phi_v + sum_i Phi_i d2Phi_i/dv2 (the second
//!    derivatives by central differences of Phi_v). f has a minimum with a nonzero floor
//!    there when H has no negative eigenvalue (below -1e-6 of its largest), g has no part
//!    along H's null directions, and the model's least value,
//!    f - 1/2 sum_k (e_k . g)^2 / lambda_k, keeps at least a quarter of f (half of |Phi|):
//!    no v near q* closes the constraints. A negative eigenvalue is a saddle or a maximum
//!    (a guess on the wrong side of a fold, a start on a symmetry line, where Phi_v is
//!    singular and the step is zero): a place where Newton lost its way, which proves
//!    nothing about the reach.
//! 2. **Other given values.** With u freed as well, Gauss-Newton from q* with minimum-norm
//!    steps closes the constraints: positions exist for given values near these, so it is
//!    these values that admit none, and where the iteration lands are the nearest given
//!    values that admit one.
//!
//! 1 and 2: [`Stall::GivenOutOfReach`]. 1 without 2: [`Stall::Unsatisfiable`] (no given
//! value near these helps: a link too short to close the loop). A negative eigenvalue of
//! H: [`Stall::Saddle`], Newton lost its way where the residual still falls (start from a
//! closer guess). Otherwise [`Stall::Undecided`]. The test is local: a minimum at q* does
//! not exclude a position far from it, on another branch.
//!
//! Runs once, after a failed assembly, so it allocates freely.

use nalgebra::{DMatrix, SymmetricEigen};

use crate::linalg::{inf_norm, least_squares};
use crate::system::Kinematic;

/// Relative step of the central differences of Phi_v: truncation (h^2, 1e-10) and
/// rounding (eps / h, 1e-11) both far below the 1e-6 that tells a saddle apart.
const DIFFERENCE_STEP: f64 = 1e-5;
/// A negative eigenvalue of H below this fraction of the largest is a saddle.
const NEGATIVE: f64 = 1e-6;
/// Eigenvalues of H below this fraction of the largest are its null directions.
const NULL: f64 = 1e-9;
/// Iterations of the Gauss-Newton with every coordinate free.
const FREE_ITERATIONS: usize = 50;

/// What stopped an assembly at q* (module docs).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Stall {
    /// No position with the given values; `nearest` is the configuration with the
    /// nearest given values that has one.
    GivenOutOfReach {
        /// A configuration that meets the constraints, reached from q* by moving u too.
        nearest: Vec<f64>,
    },
    /// A minimum of the residual over v that no nearby given value removes.
    Unsatisfiable,
    /// A saddle or a maximum of the residual: Newton lost its way where it still falls.
    Saddle,
    /// Neither test decides (Newton stopped away from a stationary point).
    Undecided,
}

/// What the model of f about q* shows (step 1 of the module docs).
enum Model {
    /// A minimum whose least value keeps at least half of |Phi|.
    Floor,
    /// A negative curvature: the residual still falls along it.
    Saddle,
    /// Neither.
    Undecided,
}

/// Classifies the stall of an assembly at `q` (module docs): `fixed` are the given
/// coordinates, `tolerance` the assembly's on |Phi|_inf.
pub(crate) fn classify(
    system: &dyn Kinematic,
    t: f64,
    q: &[f64],
    fixed: &[usize],
    tolerance: f64,
) -> Stall {
    let info = system.info();
    let rows = info.position_rows();
    let dependent: Vec<usize> = (0..info.n()).filter(|k| !fixed.contains(k)).collect();
    let mut phi = vec![0.0; info.m()];
    system.constraints(t, q, &mut phi);
    phi.truncate(rows);
    let residual = inf_norm(&phi);
    if dependent.is_empty() || !residual.is_finite() || residual <= tolerance {
        return Stall::Undecided;
    }
    match model(system, t, q, &dependent, &phi) {
        Model::Floor => {}
        Model::Saddle => return Stall::Saddle,
        Model::Undecided => return Stall::Undecided,
    }
    match close_freely(system, t, q, tolerance) {
        Some(nearest) if !fixed.is_empty() => Stall::GivenOutOfReach { nearest },
        _ => Stall::Unsatisfiable,
    }
}

/// The position rows of Phi_q at (t, q), columns `columns`.
fn jacobian(system: &dyn Kinematic, t: f64, q: &[f64], columns: &[usize]) -> DMatrix<f64> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    let mut phi_q = DMatrix::zeros(m, n);
    let mut phi_t = vec![0.0; m];
    system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
    DMatrix::from_fn(info.position_rows(), columns.len(), |i, j| {
        phi_q[(i, columns[j])]
    })
}

/// Step 1 of the module docs: whether f has a minimum at q with a floor of at least half of
/// |Phi|, or a negative curvature there.
fn model(system: &dyn Kinematic, t: f64, q: &[f64], dependent: &[usize], phi: &[f64]) -> Model {
    let d = dependent.len();
    let jv = jacobian(system, t, q, dependent);
    let r = nalgebra::DVector::from_column_slice(phi);
    let g = jv.transpose() * &r;
    let mut h = jv.transpose() * &jv;
    // sum_i Phi_i d2Phi_i/(dv_k dv_j), column j from the central difference of Phi_v in v_j.
    let mut shifted = q.to_vec();
    for (j, &k) in dependent.iter().enumerate() {
        let step = DIFFERENCE_STEP * (1.0 + q[k].abs());
        shifted[k] = q[k] + step;
        let plus = jacobian(system, t, &shifted, dependent);
        shifted[k] = q[k] - step;
        let minus = jacobian(system, t, &shifted, dependent);
        shifted[k] = q[k];
        let column = (plus - minus).transpose() * &r / (2.0 * step);
        for i in 0..d {
            h[(i, j)] += column[i];
        }
    }
    let h = (&h + h.transpose()) * 0.5;
    if !h.iter().all(|x| x.is_finite()) {
        return Model::Undecided;
    }
    let eigen = SymmetricEigen::new(h);
    let scale = eigen.eigenvalues.amax();
    if scale == 0.0 {
        return Model::Undecided;
    }
    if eigen.eigenvalues.min() < -NEGATIVE * scale {
        return Model::Saddle;
    }
    let f = 0.5 * r.norm_squared();
    let mut decrease = 0.0;
    for (k, &lambda) in eigen.eigenvalues.iter().enumerate() {
        let along = eigen.eigenvectors.column(k).dot(&g);
        if lambda > NULL * scale {
            decrease += 0.5 * along * along / lambda;
        } else if along.abs() > NULL * scale.sqrt() * r.norm() {
            return Model::Undecided; // the model falls without bound along a null direction
        }
    }
    if f - decrease >= 0.25 * f {
        Model::Floor
    } else {
        Model::Undecided
    }
}

/// Step 2 of the module docs: Gauss-Newton on the position rows over every coordinate from
/// `q`, minimum-norm steps halved until |Phi|_2 decreases; the configuration where
/// |Phi|_inf <= `tolerance`, or `None`.
fn close_freely(system: &dyn Kinematic, t: f64, q: &[f64], tolerance: f64) -> Option<Vec<f64>> {
    let info = system.info();
    let all: Vec<usize> = (0..info.n()).collect();
    let rows = info.position_rows();
    let mut x = q.to_vec();
    let mut phi = vec![0.0; info.m()];
    let residual = |x: &[f64], phi: &mut Vec<f64>| {
        system.constraints(t, x, phi);
        phi[..rows].iter().map(|v| v * v).sum::<f64>()
    };
    let mut r2 = residual(&x, &mut phi);
    for _ in 0..FREE_ITERATIONS {
        if inf_norm(&phi[..rows]) <= tolerance {
            return Some(x);
        }
        let rhs: Vec<f64> = phi[..rows].iter().map(|v| -v).collect();
        let dx = least_squares(&jacobian(system, t, &x, &all), &rhs, 1e-14);
        let mut alpha = 1.0;
        let accepted = loop {
            let trial: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + alpha * b).collect();
            let r2_trial = residual(&trial, &mut phi);
            if r2_trial.is_finite() && r2_trial < r2 {
                r2 = r2_trial;
                x = trial;
                break true;
            }
            alpha *= 0.5;
            if alpha < 1e-9 {
                break false;
            }
        };
        if !accepted {
            return None;
        }
    }
    (inf_norm(&phi[..rows]) <= tolerance).then_some(x)
}
