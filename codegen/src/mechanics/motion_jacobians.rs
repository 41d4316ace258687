//! The symbols a tangent is taken by (each coordinate, its rate and its acceleration) and
//! the partial derivatives of a list of rows by lists of symbols: what the residual's
//! tangent (`tangent.rs`) and the derivatives of the dynamics (`dynamics_derivatives.rs`)
//! both differentiate with.

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, FxHashMap, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{DerivationError, Error, Result};
use crate::mechanics::model::Model;

/// The partial derivatives of each entry of `rows` by each symbol of each list in `by`: one
/// matrix (rows x list length) per list. Each entry is differentiated only by the symbols
/// it reads, so the work follows the nonzeros of the result, not its size. Within an entry,
/// the symbols of the first list come before those of the second (each list in its order),
/// the order in which the derivative expressions are created.
///
/// # Errors
/// A differentiation error.
pub(crate) fn row_jacobians<const K: usize>(
    arena: &mut Arena,
    d: &mut Differentiator,
    rows: &[Id],
    by: [&[SymbolId]; K],
) -> Result<[Matrix; K]> {
    let zero = arena.int(0);
    let mut out: [Vec<Id>; K] = std::array::from_fn(|k| vec![zero; rows.len() * by[k].len()]);
    let mut column: FxHashMap<SymbolId, (usize, usize)> = FxHashMap::default();
    for (kind, list) in by.iter().enumerate() {
        column.extend(list.iter().enumerate().map(|(k, &s)| (s, (kind, k))));
    }
    let mut read: Vec<(usize, usize, SymbolId)> = Vec::new();
    for (i, &f) in rows.iter().enumerate() {
        read.clear();
        for s in d.symbols_of(arena, f)? {
            if let Some(&(kind, k)) = column.get(&s) {
                read.push((kind, k, s));
            }
        }
        read.sort_unstable();
        for &(kind, k, s) in &read {
            out[kind][i * by[kind].len() + k] = d.diff(arena, f, s)?;
        }
    }
    let mut out = out.into_iter();
    Ok(std::array::from_fn(|k| Matrix {
        rows: rows.len(),
        cols: by[k].len(),
        data: out.next().unwrap_or_default(),
    }))
}

/// The coordinate and rate symbols of `model` and its acceleration nodes.
pub(crate) fn motion_symbols(model: &Model) -> Result<(Vec<SymbolId>, Vec<SymbolId>, Vec<Id>)> {
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
