//! The tangent of the dynamic residual, for implicit integrators (HHT-alpha's Newton).
//!
//! With F(q, q', q'', lambda, t) = M(q) q'' + C(q, q') q' + g(q) - tau(t, q, q') + Phi_q^T lambda,
//! the stiffness K = dF/dq and the damping D = dF/dq' are derived symbolically here, so the
//! Newton iteration of an implicit scheme uses exact Jacobians instead of finite differences.
//! q'' enters through the acceleration symbols `der2(q_i)`, lambda through the symbols
//! `lambda[1]..lambda[m]` (names the declaration grammar cannot produce, so they never clash
//! with a user's).

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, FxHashMap, Id, SymbolId, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::error::DerivationError;
use crate::error::{Error, Result};
use crate::mechanics::equations::Equations;
use crate::mechanics::link_route::for_links;
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
    /// The tangents of the constraint rows, for linearisation; derived only for a model
    /// with velocity constraints (`Equations::velocity_rows` > 0).
    pub constraints: Option<ConstraintTangent>,
}

/// The tangents of the stacked constraint rows at the velocity and acceleration levels:
/// with w = Phi_q q' + Phi_t (zero along every motion) and R = Phi_q q'' - gamma (likewise),
/// the linearised constraints are D dq + Phi_q dq' = 0 and
/// R_q dq + R_q' dq' + Phi_q dq'' = 0.
#[derive(Clone, Debug)]
pub struct ConstraintTangent {
    /// D = dw/dq (m x n).
    pub velocity: Matrix,
    /// R_q = dR/dq (m x n).
    pub stiffness: Matrix,
    /// R_q' = dR/dq' (m x n).
    pub damping: Matrix,
}

/// Name of the symbol standing for multiplier k (0-based) in [`ResidualTangent`].
pub fn lambda_symbol_name(k: usize) -> String {
    format!("lambda[{}]", k + 1)
}

/// The multiplier symbols `lambda[1]`..`lambda[m]` of `arena`, created on first use: the
/// ones [`residual_tangent`] differentiates against, and the ones [`crate::compile_interpreted`]
/// gives a source without a tangent too, so that symbol ids agree with or without one.
pub(crate) fn multiplier_symbols(arena: &mut Arena, m: usize) -> Vec<SymbolId> {
    (0..m)
        .map(|k| arena.symbol_id(&lambda_symbol_name(k), SymbolKind::Free))
        .collect()
}

/// Derives K = dF/dq and D = dF/dq' of F = M q'' + C q' + g - tau + Phi_q^T lambda.
///
/// # Errors
/// A differentiation error (a division by a zero constant in a derivative); a
/// [`crate::error::BudgetError`] beyond the arena's budget (for a tree of links, with the
/// remedies that apply to links).
pub fn residual_tangent(model: &mut Model, eqs: &Equations) -> Result<ResidualTangent> {
    derive_tangent(model, eqs).map_err(|e| for_links(model, e))
}

/// [`residual_tangent`] itself.
fn derive_tangent(model: &mut Model, eqs: &Equations) -> Result<ResidualTangent> {
    let (n, m) = (eqs.n, eqs.m);
    let arena = &mut model.arena;
    let lambda = multiplier_symbols(arena, m);
    let lambda_nodes: Vec<Id> = lambda.iter().map(|&s| arena.symbol_node(s)).collect();
    let (q, qd, qdd) = motion_symbols(model)?;
    let arena = &mut model.arena;
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
    let constraints = if eqs.velocity_rows > 0 {
        Some(rows_tangent(arena, &mut d, eqs, &q, &qd, &qdd)?)
    } else {
        None
    };
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
        constraints,
    })
}

/// The coordinate and rate symbols of `model` and its acceleration nodes.
fn motion_symbols(model: &Model) -> Result<(Vec<SymbolId>, Vec<SymbolId>, Vec<Id>)> {
    let arena = &model.arena;
    let symbol = |id, what: &str, name: &str| {
        arena.as_symbol(id).ok_or_else(|| {
            Error::Derivation(DerivationError::NotASymbol {
                role: format!("{what}`{name}`"),
            })
        })
    };
    let q = (model.coordinates.iter())
        .map(|c| symbol(c.q, "coordinate ", &c.name))
        .collect::<Result<Vec<SymbolId>>>()?;
    let qd = (model.coordinates.iter())
        .map(|c| symbol(c.qd, "the rate of coordinate ", &c.name))
        .collect::<Result<Vec<SymbolId>>>()?;
    let qdd: Vec<Id> = model.coordinates.iter().map(|c| c.qdd).collect();
    Ok((q, qd, qdd))
}

/// The [`ConstraintTangent`] of the rows of `eqs`, for a model without velocity rows too
/// (where [`residual_tangent`] leaves it out): put it in `ResidualTangent::constraints` before
/// compiling to have [`crate::Role::ConstraintTangent`] compiled (linearisation).
///
/// # Errors
/// [`crate::error::DerivationError::NotASymbol`] for a coordinate or rate that is not a symbol;
/// differentiation errors.
pub fn constraint_tangent(model: &mut Model, eqs: &Equations) -> Result<ConstraintTangent> {
    let (q, qd, qdd) = motion_symbols(model)?;
    rows_tangent(
        &mut model.arena,
        &mut Differentiator::new(),
        eqs,
        &q,
        &qd,
        &qdd,
    )
}

/// D, R_q and R_q' of [`ConstraintTangent`] for the rows of `eqs`.
fn rows_tangent(
    arena: &mut Arena,
    d: &mut Differentiator,
    eqs: &Equations,
    q: &[SymbolId],
    qd: &[SymbolId],
    qdd: &[Id],
) -> Result<ConstraintTangent> {
    let (n, m) = (eqs.n, eqs.m);
    let mut velocity = Vec::with_capacity(m * n);
    let mut stiffness = Vec::with_capacity(m * n);
    let mut damping = Vec::with_capacity(m * n);
    for r in 0..m {
        let mut w = vec![eqs.phi_t.get(r, 0)];
        let mut acc = vec![arena.neg(eqs.gamma.get(r, 0))];
        for j in 0..n {
            let rate = arena.symbol_node(qd[j]);
            w.push(arena.mul2(eqs.phi_q.get(r, j), rate));
            acc.push(arena.mul2(eqs.phi_q.get(r, j), qdd[j]));
        }
        let (w, acc) = (arena.add(&w), arena.add(&acc));
        for &s in q {
            velocity.push(d.diff(arena, w, s)?);
            stiffness.push(d.diff(arena, acc, s)?);
        }
        for &s in qd {
            damping.push(d.diff(arena, acc, s)?);
        }
    }
    let matrix = |data| Matrix {
        rows: m,
        cols: n,
        data,
    };
    Ok(ConstraintTangent {
        velocity: matrix(velocity),
        stiffness: matrix(stiffness),
        damping: matrix(damping),
    })
}
