//! Velocity constraints in the equations: the rows A(q, t) q' + a(q, t) = 0 of
//! `velocity_constraints` and of `rolling`, stacked under the position rows.
//!
//! For a row w(q, q', t), linear in q':
//!
//! ```text
//! A_j   = dw/dq_j'                         (must be free of q': else not linear)
//! a     = w at q' = 0
//! gamma = -(dA/dt q' + da/dt) = -(sum_i dw/dq_i q_i' + dw/dt)
//! ```
//!
//! so that A q'' = gamma along every motion. The rows join the position rows as rows of
//! the stacked constraint Jacobian [Phi_q; A], its "Phi_t" [Phi_t; a] and [gamma; gamma_A],
//! with Phi = 0 in their place: the dynamics M q'' + C q' + g + Phi_q^T lambda + A^T mu = tau,
//! the velocity projection [Phi_q; A] q' = -[Phi_t; a] and the acceleration rows then need
//! nothing new. `Equations::velocity_rows` says how many of the m rows are these (the
//! last ones); a position projection leaves them satisfied (its correction has A dq = 0).

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{FxHashMap, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::DerivationError;
use crate::error::{DeclarationError, Error, Result};
use crate::mechanics::equations::Equations;
use crate::mechanics::lagrange::substitute;
use crate::mechanics::model::Model;

/// Appends the velocity rows of `model` to `eqs` (module docs): m grows by their number,
/// `eqs.velocity_rows` is set to it.
///
/// # Errors
/// [`DeclarationError::VelocityNotLinear`] at the row for a row not linear in the rates;
/// [`crate::error::DerivationError::NotASymbol`] for a coordinate or rate that is not a symbol;
/// differentiation errors.
pub(crate) fn append_velocity_rows(model: &mut Model, eqs: &mut Equations) -> Result<()> {
    let k = model.velocity_constraints.len();
    if k == 0 {
        return Ok(());
    }
    let symbol = |id: Id, name: &str| {
        model.arena.as_symbol(id).ok_or_else(|| {
            Error::Derivation(DerivationError::NotASymbol {
                role: format!("the rate of coordinate `{name}`"),
            })
        })
    };
    let qd: Vec<SymbolId> = (model.coordinates.iter())
        .map(|c| symbol(c.qd, &c.name))
        .collect::<Result<_>>()?;
    let arena = &mut model.arena;
    let zero = arena.int(0);
    let at_rest: FxHashMap<SymbolId, Id> = qd.iter().map(|&v| (v, zero)).collect();
    let mut d = Differentiator::new();
    let n = eqs.n;
    let mut a_rows = Vec::with_capacity(k * n);
    let mut biases = Vec::with_capacity(k);
    let mut gammas = Vec::with_capacity(k);
    for (r, c) in model.velocity_constraints.iter().enumerate() {
        for (j, &rate) in qd.iter().enumerate() {
            let a = d.diff(arena, c.expr, rate)?;
            if qd
                .iter()
                .any(|&s| d.depends_on(arena, a, s).unwrap_or(true))
            {
                let kind = DeclarationError::VelocityNotLinear {
                    row: r + 1,
                    rate: format!("der({})", model.coordinates[j].name),
                };
                return Err(Error::declaration(kind, c.location));
            }
            a_rows.push(a);
        }
        biases.push(substitute(arena, &mut d, c.expr, &at_rest)?);
        let convective = d.convective_derivative(arena, c.expr)?;
        gammas.push(arena.neg(convective));
    }
    let m = eqs.m;
    let stack = |top: &Matrix, extra: &[Id], cols: usize| {
        Matrix::from_fn(m + k, cols, |i, j| {
            if i < m {
                top.get(i, j)
            } else {
                extra[(i - m) * cols + j]
            }
        })
    };
    eqs.phi = stack(&eqs.phi, &vec![zero; k], 1);
    eqs.phi_q = stack(&eqs.phi_q, &a_rows, n);
    eqs.phi_t = stack(&eqs.phi_t, &biases, 1);
    eqs.gamma = stack(&eqs.gamma, &gammas, 1);
    eqs.m = m + k;
    eqs.velocity_rows = k;
    Ok(())
}
