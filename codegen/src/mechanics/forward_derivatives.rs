//! The forward dynamics' derivatives as one straight-line program: q'', dq''/dq, dq''/dq'
//! and M^-1 through the factorisation M = L^T D L that follows M's pattern
//! ([`super::forward_dynamics`]), with no dense factorisation at run time.
//!
//! Differentiating M q'' + b = u at the q'' it gives (Carpentier & Mansard 2018):
//!
//! ```text
//! q'' = M^-1 (u - b),   dq''/dq = -M^-1 dtau_id/dq,   dq''/dq' = -M^-1 dtau_id/dq',
//! dq''/du = M^-1,
//! ```
//!
//! with tau_id = M q'' + C q' + g - tau the inverse dynamics and its derivatives
//! ([`super::dynamics_derivatives`]) taken at that q'': the acceleration symbols of
//! dtau_id/dq are replaced by q'''s expressions, so that the kinematics, M, b and the
//! derivatives are one program and share their subexpressions. M^-1 comes from
//! L M^-1 = D^-1 L^-T, its lower triangle alone (about n^3 / 6 multiply-adds for a chain,
//! block diagonal for a forest). Each column of -M^-1 B (B = dtau_id/dq, dtau_id/dq') is
//! then either n dot products with M^-1's rows, one multiply-add per structural nonzero of
//! M^-1, or one solve by the factor (the sign taken at the pivots), two multiply-adds per
//! entry of L below the diagonal and n multiplications. The product is taken where it needs
//! no more multiplications (counted on the structure: the nonzeros of M^-1 against the
//! solve's): on a chain whose M is dense and on a forest of such chains (Solo12's
//! fixed-base legs) the two tie, and compiled, the product's independent dot products
//! count fewer operations (measured when this rule was set: the Panda 10,100 against 10,550
//! by the solves, Solo12 4,390 against 4,408). Where M has structural zeros L is sparser than
//! M^-1 (a branching tree; the UR5, whose M has structural zeros) and the solves are
//! kept, a rule on the structure that needs no second compilation.
//!
//! Two routes to M, b and dtau_id, compiled both where the second applies and the one with
//! fewer operations per call kept (the first on a tie):
//!
//! - *apart*: M and b of the dynamics ([`Equations`], for a tree of links the recursive
//!   route's composite bodies and Newton-Euler, in frames turned so that each axis is z)
//!   and the form of dtau_id the inverse dynamics' derivatives kept;
//! - *shared*, for a tree of links with one-coordinate joints: M, b and dtau_id all from
//!   the analytical recursion (`tree_derivatives::tree_dynamics`): M_ij = S_i . alpha_j
//!   from the alpha_j = Ic_j S_j the derivatives carry up anyway, b = S . F0 from a
//!   Newton-Euler pass at q'' = 0 over the derivatives' own velocities and psi, so q'' and
//!   its derivatives share the bodies' kinematics, subtree inertias and momenta.
//!
//! | robot | apart | shared | kept |
//! |---|---:|---:|---|
//! | Panda (7) | 6,702 | 6,340 | shared |
//! | UR5 (6) | 3,813 | 3,838 | apart |
//! | Solo12, base fixed (12) | 4,390 | 4,420 | apart |
//!
//! (the whole program's operations per call, `cargo run --release -p mechanism-codegen
//! --example derivative_ops`). On the Panda the shared q'' costs 919 operations beyond the
//! derivatives it feeds, the separate one 1,283.
use super::forward_dynamics::Factor;
use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{FxHashMap, Id};
use crate::algebra::matrix::Matrix;
use crate::error::Result;
use crate::mechanics::dynamics_derivatives::{InverseDynamicsDerivatives, recursion_dynamics};
use crate::mechanics::equations::Equations;
use crate::mechanics::lagrange::substitute_all;
use crate::mechanics::model::Model;
use crate::program::cse::Program;

/// dq''/dq, dq''/dq', M^-1 (n x n each, by coordinate), the pivots D (elimination order)
/// and M's diagonal in the same order (module docs), for the efforts `effort` and the
/// elimination order `order` (parents before children): by whichever of the two routes
/// (module docs) counts fewer operations once compiled.
pub(crate) fn forward_dynamics_derivatives(
    model: &mut Model,
    eqs: &Equations,
    dynamics: &InverseDynamicsDerivatives,
    effort: &[Id],
    order: &[usize],
) -> Result<Vec<Matrix>> {
    let separate = Parts {
        mass: &eqs.mass,
        bias: &eqs.bias,
        position: &dynamics.position,
        velocity: &dynamics.velocity,
    };
    let apart = outputs(model, separate, effort, order)?;
    // The shared route is written for one-coordinate joints of a tree of links.
    if !model.kinetic_from_links || model.floating_root().is_some() {
        return Ok(apart);
    }
    let tree = recursion_dynamics(model, eqs)?;
    let [position, velocity] = &tree.derivatives;
    let shared = Parts {
        mass: &tree.mass,
        bias: &tree.bias,
        position,
        velocity,
    };
    let shared = outputs(model, shared, effort, order)?;
    let ops = |outputs: &[Matrix]| -> Result<usize> {
        let outputs: Vec<&Matrix> = outputs.iter().collect();
        Ok(Program::new(&model.arena, &outputs)?.ops_per_call(&model.arena))
    };
    // The first of equal counts wins: the route by M and b of the dynamics.
    Ok(if ops(&shared)? < ops(&apart)? {
        shared
    } else {
        apart
    })
}

/// What one route reads: M, the bias b = C q' + g - tau, dtau_id/dq (in the acceleration
/// symbols) and dtau_id/dq'.
#[derive(Clone, Copy)]
struct Parts<'a> {
    mass: &'a Matrix,
    bias: &'a Matrix,
    position: &'a Matrix,
    velocity: &'a Matrix,
}

/// [`forward_dynamics_derivatives`]' outputs from one route's `parts`.
fn outputs(
    model: &mut Model,
    parts: Parts<'_>,
    effort: &[Id],
    order: &[usize],
) -> Result<Vec<Matrix>> {
    let n = order.len();
    let a = &mut model.arena;
    let factor = Factor::new(a, parts.mass, order)?;
    let rhs: Vec<Id> = order
        .iter()
        .map(|&c| {
            let d = a.sub(effort[c], parts.bias.get(c, 0));
            a.named(d)
        })
        .collect();
    let qdd = factor.solve(a, rhs, false);
    // q''_c's symbol -> its expression, in every entry of dtau_id/dq (dtau_id/dq' does not
    // read q'').
    let mut map = FxHashMap::default();
    for (k, &c) in order.iter().enumerate() {
        if let Some(s) = a.as_symbol(model.coordinates[c].qdd) {
            map.insert(s, qdd[k]);
        }
    }
    let entries = substitute_all(a, &mut Differentiator::new(), parts.position.data(), &map)?;
    let position = Matrix::new(n, n, entries)?;
    let inverse = factor.inverse(a);
    // The product where M^-1 has no more structural nonzeros than a solve's multiplications
    // (module docs).
    let nonzeros = inverse.data().iter().filter(|&&x| !a.is_zero(x)).count();
    let by_product = nonzeros <= factor.solve_multiplications();
    let mut solved = |b: &Matrix| -> Result<Matrix> {
        if by_product {
            // -M^-1 B entry by entry: n independent dot products per column.
            let mut out = Matrix::zeros(a, n, n);
            for i in 0..n {
                for c in 0..n {
                    let terms: Vec<Id> = (0..n)
                        .map(|k| {
                            let t = a.mul2(inverse.get(i, k), b.get(k, c));
                            a.neg(t)
                        })
                        .collect();
                    let s = a.add(&terms);
                    out.set(i, c, s);
                }
            }
            return Ok(out);
        }
        let mut out = Matrix::zeros(a, n, n);
        for c in 0..n {
            let column: Vec<Id> = order
                .iter()
                .map(|&r| {
                    let e = b.get(r, c);
                    a.named(e)
                })
                .collect();
            for (k, x) in factor.solve(a, column, true).into_iter().enumerate() {
                out.set(order[k], c, x);
            }
        }
        Ok(out)
    };
    let dq = solved(&position)?;
    let dqd = solved(parts.velocity)?;
    let diagonal = order.iter().map(|&c| parts.mass.get(c, c)).collect();
    Ok(vec![
        dq,
        dqd,
        inverse,
        factor.pivots(),
        Matrix::column(diagonal),
    ])
}
