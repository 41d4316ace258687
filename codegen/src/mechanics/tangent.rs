//! The tangent of the dynamic residual, for implicit integrators (HHT-alpha's Newton).
//!
//! With F(q, q', q'', lambda, t) = M(q) q'' + C(q, q') q' + g(q) - tau(t, q, q') + Phi_q^T lambda,
//! the stiffness K = dF/dq and the damping D = dF/dq' are derived symbolically here, so the
//! Newton iteration of an implicit scheme uses exact Jacobians instead of finite differences.
//! q'' enters through the acceleration symbols `der2(q_i)`, lambda through the symbols
//! `lambda[1]..lambda[m]` (names the declaration grammar cannot produce, so they never clash
//! with a user's).

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{FxHashMap, Id, SymbolId, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::error::{Error, Result};
use crate::mechanics::equations::Equations;
use crate::mechanics::model::Model;

/// K = dF/dq and D = dF/dq' of the residual F (module docs), with the multiplier symbols.
#[derive(Clone, Debug)]
pub struct ResidualTangent {
    /// dF/dq (n x n).
    pub stiffness: Matrix,
    /// dF/dq' (n x n).
    pub damping: Matrix,
    /// The symbols `lambda[1]`..`lambda[m]` the matrices read.
    pub lambda: Vec<SymbolId>,
}

/// Name of the symbol standing for multiplier k (0-based) in [`ResidualTangent`].
pub fn lambda_symbol_name(k: usize) -> String {
    format!("lambda[{}]", k + 1)
}

/// Derives K = dF/dq and D = dF/dq' of F = M q'' + C q' + g - tau + Phi_q^T lambda.
///
/// # Errors
/// A differentiation error (a division by a zero constant in a derivative).
pub fn residual_tangent(model: &mut Model, eqs: &Equations) -> Result<ResidualTangent> {
    let (n, m) = (eqs.n, eqs.m);
    let arena = &mut model.arena;
    let lambda: Vec<SymbolId> = (0..m)
        .map(|k| arena.symbol_id(&lambda_symbol_name(k), SymbolKind::Free))
        .collect();
    let lambda_nodes: Vec<Id> = lambda.iter().map(|&s| arena.symbol_node(s)).collect();
    let symbol = |id, what: &str, name: &str| {
        arena.as_symbol(id).ok_or_else(|| Error::NotASymbol {
            role: format!("{what}`{name}`"),
        })
    };
    let q = (model.coordinates.iter())
        .map(|c| symbol(c.q, "coordinate ", &c.name))
        .collect::<Result<Vec<SymbolId>>>()?;
    let qd = (model.coordinates.iter())
        .map(|c| symbol(c.qd, "the rate of coordinate ", &c.name))
        .collect::<Result<Vec<SymbolId>>>()?;
    let qdd: Vec<Id> = model.coordinates.iter().map(|c| c.qdd).collect();
    let mut residual = Vec::with_capacity(n);
    for i in 0..n {
        let mut terms = Vec::with_capacity(2 * n + m + 3);
        for (j, &a) in qdd.iter().enumerate() {
            terms.push(arena.mul2(eqs.mass.get(i, j), a));
        }
        terms.push(eqs.coriolis_forces.get(i, 0));
        terms.push(eqs.gravity.get(i, 0));
        let tau = eqs.forces.get(i, 0);
        terms.push(arena.neg(tau));
        for (k, &l) in lambda_nodes.iter().enumerate() {
            terms.push(arena.mul2(eqs.phi_q.get(k, i), l));
        }
        residual.push(arena.add(&terms));
    }
    let mut d = Differentiator::new();
    let zero = arena.int(0);
    let mut stiffness = vec![zero; n * n];
    let mut damping = vec![zero; n * n];
    // Each row is differentiated only by the symbols it reads: the work follows the
    // nonzeros of K and D, not n^2. Within a row, every q before every q' (each in index
    // order), the order in which the expressions have always been created.
    let mut column: FxHashMap<SymbolId, (usize, usize)> = FxHashMap::default();
    column.extend(q.iter().enumerate().map(|(k, &s)| (s, (0, k))));
    column.extend(qd.iter().enumerate().map(|(k, &s)| (s, (1, k))));
    let mut read: Vec<(usize, usize, SymbolId)> = Vec::new();
    for (i, &f) in residual.iter().enumerate() {
        read.clear();
        for s in d.symbols_of(arena, f)? {
            if let Some(&(kind, k)) = column.get(&s) {
                read.push((kind, k, s));
            }
        }
        read.sort_unstable();
        for &(kind, k, s) in &read {
            let target = if kind == 0 {
                &mut stiffness
            } else {
                &mut damping
            };
            target[i * n + k] = d.diff(arena, f, s)?;
        }
    }
    Ok(ResidualTangent {
        stiffness: Matrix {
            rows: n,
            cols: n,
            data: stiffness,
        },
        damping: Matrix {
            rows: n,
            cols: n,
            data: damping,
        },
        lambda,
    })
}
