//! The tangent of the dynamic residual, for implicit integrators (HHT-alpha's Newton).
//!
//! With F(q, q', q'', lambda, t) = M(q) q'' + C(q, q') q' + g(q) - tau(t, q, q') + Phi_q^T lambda,
//! the stiffness K = dF/dq and the damping D = dF/dq' are derived symbolically here, so the
//! Newton iteration of an implicit scheme uses exact Jacobians instead of finite differences.
//! At lambda = 0, F is the inverse dynamics tau_id: K and D are then its derivatives, which
//! control and optimisation read (`mechanics::dynamics_derivatives`).
//! q'' enters through the acceleration symbols `der2(q_i)`, lambda through the symbols
//! `lambda[1]..lambda[m]` (names the declaration grammar cannot produce, so they never clash
//! with a user's).

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::error::DerivationError;
use crate::error::{Error, Result};
use crate::mechanics::dynamics_derivatives::{
    InverseDynamicsDerivatives, inverse_dynamics_jacobians, parameter_jacobian,
};
use crate::mechanics::equations::Equations;
use crate::mechanics::link_route::for_links;
use crate::mechanics::model::Model;
use crate::mechanics::motion_jacobians::{motion_symbols, row_jacobians};

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
    /// with velocity constraints (`Equations::velocity_rows` > 0), or for every model by
    /// [`full_tangent`].
    pub constraints: Option<ConstraintTangent>,
    /// The derivatives of the inverse dynamics tau_id = F at lambda = 0: K and D without
    /// the multipliers' part (the same matrices as K and D without constraint rows), and
    /// dtau_id/dp when derived ([`full_tangent`]).
    pub dynamics: InverseDynamicsDerivatives,
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

/// Derives K = dF/dq and D = dF/dq' of F = M q'' + C q' + g - tau + Phi_q^T lambda: the
/// derivatives of the inverse dynamics tau_id ([`InverseDynamicsDerivatives`], of the form of
/// tau_id with the cheaper derivatives, `mechanics::dynamics_derivatives`) plus
/// d(Phi_q^T lambda)/dq (Phi_q does not depend on q').
///
/// # Errors
/// A differentiation error (a division by a zero constant in a derivative); a
/// [`crate::error::BudgetError`] beyond the arena's budget (for a tree of links, with the
/// remedies that apply to links).
pub fn residual_tangent(model: &mut Model, eqs: &Equations) -> Result<ResidualTangent> {
    tangent(model, eqs, false).map_err(|e| for_links(model, e))
}

/// [`residual_tangent`] with every derivative the macro emits: the constraint rows' tangent
/// for every model (an m x n one, empty without rows) and the inverse dynamics'
/// derivatives by the parameters, dtau_id/dp. What [`crate::compile`] compiles the roles
/// [`crate::Role::ConstraintTangent`], [`crate::Role::InverseDynamicsDerivatives`] and
/// [`crate::Role::ParameterDerivatives`] from ([`crate::Tangents::Derivatives`]).
///
/// # Errors
/// As [`residual_tangent`].
pub fn full_tangent(model: &mut Model, eqs: &Equations) -> Result<ResidualTangent> {
    tangent(model, eqs, true).map_err(|e| for_links(model, e))
}

/// [`residual_tangent`], or with `full` [`full_tangent`].
fn tangent(model: &mut Model, eqs: &Equations, full: bool) -> Result<ResidualTangent> {
    let (n, m) = (eqs.n, eqs.m);
    let parameters = parameter_symbols(model)?;
    let arena = &mut model.arena;
    let lambda = multiplier_symbols(arena, m);
    let lambda_nodes: Vec<Id> = lambda.iter().map(|&s| arena.symbol_node(s)).collect();
    let (q, qd, qdd) = motion_symbols(model)?;
    let mut d = Differentiator::new();
    let (rows, [position, velocity]) =
        inverse_dynamics_jacobians(model, &mut d, eqs, (&q, &qd, &qdd))?;
    let arena = &mut model.arena;
    let stiffness = if m == 0 {
        position.clone()
    } else {
        // (Phi_q^T lambda)_i, differentiated by q.
        let forces: Vec<Id> = (0..n)
            .map(|i| {
                let terms: Vec<Id> = (lambda_nodes.iter().enumerate())
                    .map(|(k, &l)| arena.mul2(eqs.phi_q.get(k, i), l))
                    .collect();
                arena.add(&terms)
            })
            .collect();
        let [reaction] = row_jacobians(arena, &mut d, &forces, [&q])?;
        position.add(arena, &reaction)?
    };
    let constraints = if eqs.velocity_rows > 0 || full {
        Some(rows_tangent(arena, &mut d, eqs, &q, &qd, &qdd)?)
    } else {
        None
    };
    let parameters = if full {
        Some(parameter_jacobian(arena, &mut d, &rows, &parameters)?)
    } else {
        None
    };
    Ok(ResidualTangent {
        stiffness,
        damping: velocity.clone(),
        lambda,
        constraints,
        dynamics: InverseDynamicsDerivatives {
            position,
            velocity,
            parameters,
        },
    })
}

/// The parameter symbols of `model`, in declaration order.
fn parameter_symbols(model: &Model) -> Result<Vec<SymbolId>> {
    (model.parameters.iter())
        .map(|p| {
            model.arena.as_symbol(p.symbol).ok_or_else(|| {
                Error::Derivation(DerivationError::NotASymbol {
                    role: format!("parameter `{}`", p.name),
                })
            })
        })
        .collect()
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
