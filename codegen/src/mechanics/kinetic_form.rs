//! The kinetic energy as a quadratic form in the rates: T = 1/2 q'^T M(q, t) q' + b(q, t)^T
//! q' + T0(q, t), with M symmetric positive semi-definite.
//!
//! A T of higher degree in the rates (`der(x)^4`), or not polynomial in them
//! (`cos(der(x))`), has no mass matrix: M = d2T/dq'^2 then depends on the rates and the
//! equations of motion are not linear in q''. A T that can be negative (`-3*der(x)^2`, a
//! negative mass) gives an M with a negative direction, and motion along it runs away (an
//! integrator's step size then underflows). The derivation, which forms M anyway, refuses
//! both with a declaration error at `kinetic`.
//!
//! The degree test is exact: no entry of M may depend on a rate. Positive semi-definiteness
//! is tested numerically at the declared parameter values and initial guesses (t = 0) by
//! L D L^T with diagonal pivoting: a pivot below -1e-9 times the largest |M_ij| is a
//! negative direction, named by the coordinate of that pivot. Semi-definite, not definite:
//! redundant coordinates without mass (the seed's M is singular) are allowed; whether M is
//! positive definite on the motions the constraints allow is decided at run time.

use crate::algebra::diff::Differentiator;
use crate::algebra::eval::eval_matrix;
use crate::algebra::expr::{Arena, FxHashMap, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{DeclarationError, Error, Location, Result};
use crate::mechanics::model::{Coordinate, Parameter};

/// Relative size of a negative pivot that counts as a negative direction of M (rounding
/// in the elimination is of order n eps max|M_ij|, far below it).
const NEGATIVE_PIVOT: f64 = 1e-9;

/// Checks `mass` = d2T/dq'^2 (n x n, from the derivation): no entry depends on a rate, and
/// M is positive semi-definite at the declared values (see the module docs). Errors at
/// `model.kinetic_location`.
pub(crate) fn check_mass(
    arena: &Arena,
    d: &mut Differentiator,
    mass: &Matrix,
    model: &ModelView<'_>,
) -> Result<()> {
    let n = model.coordinates.len();
    let names: Vec<&str> = model.coordinates.iter().map(|c| c.name.as_str()).collect();
    let rates: Vec<Option<SymbolId>> = model
        .coordinates
        .iter()
        .map(|c| arena.as_symbol(c.qd))
        .collect();
    // Which coordinate each rate symbol belongs to: one look-up per symbol of an entry
    // (constant entries have none), not a scan of every rate per entry.
    let mut rate_of: Vec<Option<usize>> = vec![None; arena.symbols().len()];
    for (k, r) in rates.iter().enumerate() {
        if let Some(r) = r {
            rate_of[r.index()] = Some(k);
        }
    }
    for i in 0..n {
        for j in 0..=i {
            let e = mass.get(i, j);
            if arena.as_number(e).is_some() {
                continue;
            }
            let symbols = d.symbols_of(arena, e)?;
            if let Some(k) = symbols.iter().filter_map(|s| rate_of[s.index()]).min() {
                return Err(Error::declaration(
                    DeclarationError::KineticNotQuadratic {
                        row: names[i].to_string(),
                        column: names[j].to_string(),
                        rate: names[k].to_string(),
                    },
                    model.at,
                ));
            }
        }
    }
    let values: FxHashMap<SymbolId, f64> = model
        .parameters
        .iter()
        .filter_map(|p| arena.as_symbol(p.symbol).map(|s| (s, p.default)))
        .chain(
            model
                .coordinates
                .iter()
                .filter_map(|c| arena.as_symbol(c.q).map(|s| (s, c.guess))),
        )
        .chain(arena.as_symbol(model.time).map(|s| (s, 0.0)))
        .collect();
    let env = |s: SymbolId| values.get(&s).copied();
    let mut m = match eval_matrix(arena, mass, &env) {
        Ok(m) if m.iter().all(|v| v.is_finite()) => m,
        // Undefined at the guesses (a singular position): nothing to test there.
        _ => return Ok(()),
    };
    let diagonal: Vec<f64> = (0..n).map(|i| m[i * n + i]).collect();
    match negative_direction(&mut m, n) {
        None => Ok(()),
        Some((k, pivot)) => Err(Error::declaration(
            DeclarationError::KineticNotPositive {
                coordinate: names[k].to_string(),
                pivot,
                diagonal: diagonal[k],
            },
            model.at,
        )),
    }
}

/// What [`check_mass`] reads of the model besides its arena.
pub(crate) struct ModelView<'a> {
    /// The coordinates (names, symbols, initial guesses).
    pub coordinates: &'a [Coordinate],
    /// The parameters (symbols, declared values).
    pub parameters: &'a [Parameter],
    /// The time symbol.
    pub time: Id,
    /// Where T is declared.
    pub at: Location,
}

/// L D L^T of the symmetric n x n `a` (row-major, overwritten) with diagonal pivoting;
/// the coordinate and value of the first pivot below -NEGATIVE_PIVOT max|a_ij|, or `None`
/// when every pivot is above it (positive semi-definite to that tolerance).
fn negative_direction(a: &mut [f64], n: usize) -> Option<(usize, f64)> {
    let scale = a[..n * n].iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    if scale == 0.0 {
        return None;
    }
    let tol = NEGATIVE_PIVOT * scale;
    let mut order: Vec<usize> = (0..n).collect();
    for step in 0..n {
        // The remaining diagonal entry of largest magnitude, negative ones first: a negative
        // diagonal is already a negative direction.
        let (p, _) = (step..n)
            .map(|r| (r, a[order[r] * n + order[r]]))
            .min_by(|x, y| {
                let key = |v: f64| if v < -tol { (0, v) } else { (1, -v) };
                key(x.1)
                    .partial_cmp(&key(y.1))
                    .unwrap_or(std::cmp::Ordering::Equal)
            })?;
        order.swap(step, p);
        let k = order[step];
        let pivot = a[k * n + k];
        if pivot < -tol {
            return Some((k, pivot));
        }
        if pivot <= tol {
            // Every remaining diagonal entry is within the tolerance of 0: semi-definite only
            // if the remaining off-diagonal entries are too, else the 2 x 2 block
            // [0 a; a 0] has the eigenvalue -|a|.
            for r in step..n {
                for c in step..n {
                    let v = a[order[r] * n + order[c]];
                    if r != c && v.abs() > tol {
                        return Some((order[r], -v.abs()));
                    }
                }
            }
            return None;
        }
        for r in step + 1..n {
            let i = order[r];
            let l = a[i * n + k] / pivot;
            // Rows not coupled to the pivot are unchanged: a banded or block-diagonal M
            // (free particles, chains) costs what its couplings cost, not n^3.
            if l == 0.0 {
                continue;
            }
            for &j in &order[step + 1..n] {
                a[i * n + j] -= l * a[k * n + j];
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::negative_direction;

    #[test]
    fn semi_definite_matrices_pass_and_indefinite_ones_are_named() {
        // Positive definite.
        let mut a = vec![2.0, 1.0, 1.0, 2.0];
        assert_eq!(negative_direction(&mut a, 2), None);
        // Singular, semi-definite (the seed's kind: a coordinate without mass).
        let mut a = vec![1.0, 0.0, 0.0, 0.0];
        assert_eq!(negative_direction(&mut a, 2), None);
        // Rank one: [1 1; 1 1].
        let mut a = vec![1.0, 1.0, 1.0, 1.0];
        assert_eq!(negative_direction(&mut a, 2), None);
        // A negative diagonal entry.
        let mut a = vec![1.0, 0.0, 0.0, -6.0];
        assert_eq!(negative_direction(&mut a, 2), Some((1, -6.0)));
        // Positive diagonal, indefinite: [1 2; 2 1] has eigenvalues 3 and -1; the second
        // pivot is 1 - 4 = -3.
        let mut a = vec![1.0, 2.0, 2.0, 1.0];
        let (_, pivot) = negative_direction(&mut a, 2).unwrap();
        assert_eq!(pivot, -3.0);
        // Zero diagonal, nonzero coupling: [0 1; 1 0], eigenvalues 1 and -1.
        let mut a = vec![0.0, 1.0, 1.0, 0.0];
        assert_eq!(negative_direction(&mut a, 2), Some((0, -1.0)));
    }
}
