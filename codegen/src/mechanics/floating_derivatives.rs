//! The derivatives of a floating-base robot's inverse dynamics by the tangent of its
//! configuration manifold, in Pinocchio's convention (`computeRNEADerivatives` with
//! `JointModelFreeFlyer`):
//!
//! ```text
//! tau_id(q, v, a) = M(q) a + C(q, v) v + g(q) - tau(t, q, v)              (NV entries)
//! dtau_id/dq [:, k] = d/de tau_id(q (+) e e_k, v, a) at e = 0              (NV x NV)
//! dtau_id/dv        = the ordinary partial derivatives                      (NV x NV)
//! ```
//!
//! with q (+) dq Pinocchio's `integrate` (`mechanics::floating`): the root's pose (R, p)
//! moved by the exponential of the body-frame twist dq[0..6], the joints by addition. To
//! first order the root's position moves by R dq[0..3] and its quaternion by
//! 1/2 quaternion (dq[3..6], 0), so by the chain rule through the seven configuration
//! symbols x, y, z, qx, qy, qz, qw:
//!
//! ```text
//! dtau/dq[:, i]     = sum_j dtau/dp_j R[j][i]                   i = 0, 1, 2
//! dtau/dq[:, 3 + i] = sum_k dtau/dquat_k G[k][i],   G = 1/2 [[ w, -z,  y],
//!                                                            [ z,  w, -x],
//!                                                            [-y,  x,  w],
//!                                                            [-x, -y, -z]]
//! dtau/dq[:, 6 + j] = dtau/dq_joint_j
//! ```
//!
//! G's columns are tangent to the unit sphere, where R's formula in the quaternion is exact,
//! so the chain is exact. The root's velocities are in its own axes, so the dynamics do not
//! read p (the first three columns come out zero, as Pinocchio's) and read the quaternion
//! through gravity in the root's axes alone. The two forms of tau_id
//! (`mechanics::dynamics_derivatives`: M a + C v + g - tau, and Newton-Euler's recursion
//! traced into expressions) are differentiated and the one that compiles to fewer
//! operations is kept.

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{DerivationError, Error, Result};
use crate::mechanics::dynamics_derivatives::{
    Form, InverseDynamicsDerivatives, leanest, residual_rows,
};
use crate::mechanics::equations::Equations;
use crate::mechanics::links::quaternion_matrix;
use crate::mechanics::model::Model;
use crate::mechanics::motion_jacobians::{motion_symbols, row_jacobians};
use crate::mechanics::tangent::ResidualTangent;

/// dtau_id/dq (by the manifold's tangent) and dtau_id/dv of a floating-base model (module
/// docs), as a [`ResidualTangent`] without constraint rows (K = dtau_id/dq, D = dtau_id/dv)
/// for the compile stage's [`crate::Role::InverseDynamicsDerivatives`].
///
/// # Errors
/// [`DerivationError::FloatingBase`] for a model without a floating root; a configuration
/// entry that is not a symbol; a differentiation error.
pub fn floating_tangent(model: &mut Model, eqs: &Equations) -> Result<ResidualTangent> {
    let Some(root) = model.floating_root() else {
        return Err(Error::Derivation(DerivationError::FloatingBase {
            mechanism: model.name.clone(),
            what: "(it has none) `floating_tangent`".into(),
            nq: model.configuration_size(),
            nv: eqs.n,
        }));
    };
    let arena = &model.arena;
    let configuration = (root.configuration.iter())
        .map(|&c| {
            arena.as_symbol(c).ok_or_else(|| {
                Error::Derivation(DerivationError::NotASymbol {
                    role: "the floating root's configuration".into(),
                })
            })
        })
        .collect::<Result<Vec<SymbolId>>>()?;
    let (q, qd, qdd) = motion_symbols(model)?;
    // The joints' positions: the coordinates after the root's six velocities.
    let joints: Vec<SymbolId> = (q.iter().enumerate())
        .filter(|(i, _)| model.configuration_index(*i).is_some())
        .map(|(_, &s)| s)
        .collect();
    let arena = &mut model.arena;
    let residual = residual_rows(arena, eqs, &qdd);
    let recursion: Vec<Id> = (0..eqs.n).map(|i| eqs.inverse_dynamics.get(i, 0)).collect();
    let mut d = Differentiator::new();
    let by = [&configuration[..], &joints[..], &qd[..]];
    let mut candidates = vec![("M a + C v + g - tau", residual.clone())];
    if recursion != residual {
        candidates.push(("traced recursion", recursion));
    }
    let mut forms: Vec<Form> = Vec::with_capacity(2);
    for (name, rows) in candidates {
        let [dc, dj, dv] = row_jacobians(arena, &mut d, &rows, by)?;
        let dq = on_manifold(arena, &root.configuration, &dc, &dj)?;
        forms.push((name, [dq, dv]));
    }
    let [position, velocity] = leanest(arena, forms)?;
    Ok(ResidualTangent {
        stiffness: position.clone(),
        damping: velocity.clone(),
        lambda: Vec::new(),
        constraints: None,
        dynamics: InverseDynamicsDerivatives {
            position,
            velocity,
            parameters: None,
        },
    })
}

/// dtau/dq by the tangent (NV x NV) from dtau by the configuration symbols `dc` (NV x 7)
/// and by the joints' positions `dj` (NV x joints), through R and G (module docs).
fn on_manifold(
    arena: &mut Arena,
    configuration: &[Id; 7],
    dc: &Matrix,
    dj: &Matrix,
) -> Result<Matrix> {
    let nv = dc.rows();
    let r = quaternion_matrix(arena, configuration);
    let [x, y, z, w] = [3, 4, 5, 6].map(|k| configuration[k]);
    let half = arena.rational(1, 2)?;
    let minus = |arena: &mut Arena, a: Id| arena.neg(a);
    let (mx, my, mz) = (minus(arena, x), minus(arena, y), minus(arena, z));
    // G without its factor 1/2, rows qx, qy, qz, qw.
    let g = [[w, mz, y], [z, w, mx], [my, x, w], [mx, my, mz]];
    let mut data = Vec::with_capacity(nv * nv);
    for row in 0..nv {
        for i in 0..3 {
            let mut terms = Vec::with_capacity(3);
            for j in 0..3 {
                if !arena.is_zero(dc.get(row, j)) {
                    terms.push(arena.mul2(dc.get(row, j), r.get(j, i)));
                }
            }
            data.push(arena.add(&terms));
        }
        for i in 0..3 {
            let mut terms = Vec::with_capacity(4);
            for (k, gk) in g.iter().enumerate() {
                if !arena.is_zero(dc.get(row, 3 + k)) {
                    terms.push(arena.mul2(dc.get(row, 3 + k), gk[i]));
                }
            }
            let sum = arena.add(&terms);
            data.push(arena.mul2(half, sum));
        }
        for j in 0..dj.cols() {
            data.push(dj.get(row, j));
        }
    }
    Matrix::new(nv, nv, data)
}
