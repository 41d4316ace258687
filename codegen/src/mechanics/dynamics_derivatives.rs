//! The derivatives of the inverse dynamics, for control and optimisation (iLQR, DDP, MPC,
//! identification): with
//!
//! ```text
//! tau_id(t, q, q', q'') = M(q) q'' + C(q, q') q' + g(q) - tau(t, q, q'),
//! ```
//!
//! dtau_id/dq and dtau_id/dq' (n x n each; dtau_id/dq'' is M) and dtau_id/dp (n x p, the
//! declared parameters in declaration order), derived symbolically: each entry of tau_id
//! differentiated by the memoised differentiator, so the derivatives share the
//! subexpressions of the dynamics they differentiate (and the multipliers' part of the
//! residual's tangent, [`crate::residual_tangent`], is added to the same matrices).
//!
//! Three forms are differentiated, equal in value: M q'' + C q' + g - tau (M by composite
//! bodies), [`Equations::inverse_dynamics`] where it is another expression (for a tree of
//! links, Newton-Euler's recursion traced into expressions, q'' inside it: the traced
//! program's derivative), and for a tree of links Newton-Euler's analytical derivatives
//! (`mechanics::tree_derivatives`). The forms whose estimate ([`graph_ops`]) is within
//! [`CLOSE`] of the least are compiled and the one with the fewest operations per call is
//! kept (measured by `cargo run --release -p mechanism-codegen --example derivative_ops`):
//!
//! | robot | M q'' + C q' + g | traced recursion | analytical recursion | kept |
//! |---|---:|---:|---:|---|
//! | Panda (7) | 9,477 | 7,349 | 3,812 | analytical recursion |
//! | UR5 (6) | 3,105 | 2,336 | 2,212 | analytical recursion |
//! | Solo12, base fixed (12) | 2,984 | 3,162 | 2,998 | M q'' + C q' + g |

use crate::algebra::cost::graph_ops;
use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::Result;
use crate::mechanics::equations::Equations;
use crate::mechanics::model::Model;
use crate::mechanics::motion_jacobians::{motion_symbols, row_jacobians};
use crate::mechanics::tree_derivatives::{TreeDynamics, tree_derivatives, tree_dynamics};
use crate::program::cse::Program;

/// The derivatives of the inverse dynamics tau_id (module docs).
#[derive(Clone, Debug)]
pub struct InverseDynamicsDerivatives {
    /// dtau_id/dq (n x n).
    pub position: Matrix,
    /// dtau_id/dq' (n x n).
    pub velocity: Matrix,
    /// dtau_id/dp (n x p, p the declared parameters in declaration order); derived only on
    /// request ([`crate::full_tangent`]).
    pub parameters: Option<Matrix>,
}

/// The entries of tau_id whose derivatives by the parameters are taken (the recursion's or
/// the other form, whichever had the cheaper derivatives by the motion), and the Jacobians
/// of tau_id by the coordinates `q` and the rates `qd` of the form kept (module docs); `qdd`
/// are the acceleration nodes.
///
/// # Errors
/// A differentiation error.
pub(crate) fn inverse_dynamics_jacobians(
    model: &mut Model,
    d: &mut Differentiator,
    eqs: &Equations,
    motion: (&[SymbolId], &[SymbolId], &[Id]),
) -> Result<(Vec<Id>, [Matrix; 2])> {
    let (recursion, forms) = forms(model, d, eqs, motion)?;
    Ok((recursion, leanest(&model.arena, forms)?))
}

/// The pair of `forms` with the fewest operations per call once compiled (module docs).
///
/// # Errors
/// A compile error of a form's program.
pub(crate) fn leanest(arena: &Arena, forms: Vec<Form>) -> Result<[Matrix; 2]> {
    let estimates: Vec<usize> = (forms.iter())
        .map(|(_, m)| graph_ops(arena, &[&m[0], &m[1]]))
        .collect();
    let least = estimates.iter().copied().min().unwrap_or(0);
    // The forms the estimate does not rule out (within CLOSE of the least) are compiled and
    // counted: the estimate overcounts by a factor that differs between forms (CLOSE). A form alone in the running is kept uncompiled (the compile stage
    // lowers it once). The first of equal counts wins: M q'' + C q' + g - tau, then the
    // traced recursion, then the analytical one.
    let mut running: Vec<[Matrix; 2]> = (forms.into_iter().zip(estimates))
        .filter(|(_, e)| e.saturating_mul(CLOSE.1) <= least.saturating_mul(CLOSE.0))
        .map(|((_, m), _)| m)
        .collect();
    let mut best = 0;
    if running.len() > 1 {
        let mut fewest = usize::MAX;
        for (k, m) in running.iter().enumerate() {
            let count = Program::new(arena, &[&m[0], &m[1]])?.ops_per_call(arena);
            if count < fewest {
                (best, fewest) = (k, count);
            }
        }
    }
    Ok(running.swap_remove(best))
}

/// Forms whose estimate is within this ratio of the least are compiled and counted; the
/// others are ruled out by the estimate alone. Wider than the 5/4 with which the compile
/// stage trusts its estimates between a derived and a factored program
/// (`compile::passes`): the forms here differ in kind, and the estimate has ranked a form
/// first by a factor of 1.39 that compiled to more operations than another (Solo12's
/// analytical recursion against M q'' + C q' + g, before the recursive route's emission).
const CLOSE: (usize, usize) = (3, 2);

/// One form of dtau_id/dq, dtau_id/dq': its name and the two matrices.
pub(crate) type Form = (&'static str, [Matrix; 2]);

/// The recursion's entries of tau_id, and each form's Jacobians by `q` and `qd` with its
/// name: M q'' + C q' + g - tau, the traced recursion where it is another expression, and
/// the analytical recursion for a tree of links.
fn forms(
    model: &mut Model,
    d: &mut Differentiator,
    eqs: &Equations,
    (q, qd, qdd): (&[SymbolId], &[SymbolId], &[Id]),
) -> Result<(Vec<Id>, Vec<Form>)> {
    let arena = &mut model.arena;
    let residual = residual_rows(arena, eqs, qdd);
    let recursion: Vec<Id> = (0..eqs.n).map(|i| eqs.inverse_dynamics.get(i, 0)).collect();
    let mut forms = vec![(
        "M q'' + C q' + g - tau",
        row_jacobians(arena, d, &residual, [q, qd])?,
    )];
    if recursion != residual {
        forms.push((
            "traced recursion",
            row_jacobians(arena, d, &recursion, [q, qd])?,
        ));
    }
    if model.kinetic_from_links {
        forms.push((
            "analytical recursion",
            recursion_derivatives(model, d, eqs, (q, qd))?,
        ));
    }
    Ok((recursion, forms))
}

/// The entries of M q'' + C q' + g - tau, `qdd` the acceleration nodes.
pub(crate) fn residual_rows(arena: &mut Arena, eqs: &Equations, qdd: &[Id]) -> Vec<Id> {
    let n = eqs.n;
    (0..n)
        .map(|i| {
            let mut terms = Vec::with_capacity(n + 3);
            for (j, &a) in qdd.iter().enumerate() {
                terms.push(arena.mul2(eqs.mass.get(i, j), a));
            }
            terms.push(eqs.coriolis_forces.get(i, 0));
            terms.push(eqs.gravity.get(i, 0));
            let tau = eqs.forces.get(i, 0);
            terms.push(arena.neg(tau));
            arena.add(&terms)
        })
        .collect()
}

/// Each form of dtau_id/dq and dtau_id/dq' the compile stage chooses among (module docs),
/// named, for measuring which is leaner once compiled (the benchmarks' `derivative_ops`):
/// `Program::new` on each pair gives its operations per call.
///
/// # Errors
/// A coordinate or rate that is not a symbol; a differentiation error.
pub fn inverse_dynamics_derivative_forms(model: &mut Model, eqs: &Equations) -> Result<Vec<Form>> {
    let (q, qd, qdd) = motion_symbols(model)?;
    let mut d = Differentiator::new();
    Ok(forms(model, &mut d, eqs, (&q, &qd, &qdd))?.1)
}

/// The derivatives of tau_id by the analytical recursion of `mechanics::tree_derivatives`
/// (the links' gravity inside it where they carry the potential), plus those of the rest of
/// tau_id (g otherwise, and the declared forces) by the differentiator.
fn recursion_derivatives(
    model: &mut Model,
    d: &mut Differentiator,
    eqs: &Equations,
    motion: (&[SymbolId], &[SymbolId]),
) -> Result<[Matrix; 2]> {
    Ok(recursion_with(model, d, eqs, motion, false)?.derivatives)
}

/// The analytical recursion's dtau_id/dq and dtau_id/dq' (in the acceleration symbols) with
/// M and the bias b = C q' + g - tau from the same recursion (`tree_derivatives::tree_dynamics`):
/// what the forward dynamics' derivatives read when q'' is to share the derivatives'
/// kinematics (`mechanics::forward_derivatives`). For a model whose links carry all of T.
///
/// # Errors
/// A coordinate or rate that is not a symbol; a differentiation error.
pub(crate) fn recursion_dynamics(model: &mut Model, eqs: &Equations) -> Result<TreeDynamics> {
    let (q, qd, _) = motion_symbols(model)?;
    let mut d = Differentiator::new();
    recursion_with(model, &mut d, eqs, (&q, &qd), true)
}

/// [`recursion_derivatives`], with M and the bias `with_dynamics` ([`recursion_dynamics`]).
fn recursion_with(
    model: &mut Model,
    d: &mut Differentiator,
    eqs: &Equations,
    (q, qd): (&[SymbolId], &[SymbolId]),
    with_dynamics: bool,
) -> Result<TreeDynamics> {
    let gravity = model.gravity.filter(|_| model.potential_from_links);
    let tree = if with_dynamics {
        tree_dynamics(model, gravity)?
    } else {
        let derivatives = tree_derivatives(model, gravity)?;
        let zero = Matrix::zeros(&mut model.arena, 0, 0);
        TreeDynamics {
            derivatives,
            mass: zero.clone(),
            bias: zero,
        }
    };
    let arena = &mut model.arena;
    let rest: Vec<Id> = (0..eqs.n)
        .map(|i| {
            let tau = eqs.forces.get(i, 0);
            let minus = arena.neg(tau);
            match gravity {
                Some(_) => minus,
                None => arena.add2(eqs.gravity.get(i, 0), minus),
            }
        })
        .collect();
    let [rq, rqd] = row_jacobians(arena, d, &rest, [q, qd])?;
    let [dq, dqd] = &tree.derivatives;
    let bias = if with_dynamics {
        tree.bias.add(arena, &Matrix::column(rest))?
    } else {
        tree.bias
    };
    Ok(TreeDynamics {
        derivatives: [dq.add(arena, &rq)?, dqd.add(arena, &rqd)?],
        mass: tree.mass,
        bias,
    })
}

/// dtau_id/dp of the entries `rows` of tau_id (n x p) by the `parameters` symbols.
///
/// # Errors
/// A differentiation error.
pub(crate) fn parameter_jacobian(
    arena: &mut Arena,
    d: &mut Differentiator,
    rows: &[Id],
    parameters: &[SymbolId],
) -> Result<Matrix> {
    let [dp] = row_jacobians(arena, d, rows, [parameters])?;
    Ok(dp)
}
