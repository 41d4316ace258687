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
    check_mass_free_of_rates(arena, d, mass, model)?;
    check_mass_semi_definite(arena, mass, model)
}

/// The degree half of [`check_mass`]: no entry of `mass` depends on a rate.
fn check_mass_free_of_rates(
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
    Ok(())
}

/// The semi-definiteness half of [`check_mass`], at the declared values: all a tree of
/// links needs, whose M (by composite bodies over positions) is free of rates by
/// construction.
pub(crate) fn check_mass_semi_definite(
    arena: &Arena,
    mass: &Matrix,
    model: &ModelView<'_>,
) -> Result<()> {
    let n = model.coordinates.len();
    let names: Vec<&str> = model.coordinates.iter().map(|c| c.name.as_str()).collect();
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
///
/// The pivot's row and column are swapped into place (P A P^T), so each elimination step
/// updates a contiguous trailing block, a_ij -= (a_ik / a_kk) a_kj: n^3 / 3 multiply-adds
/// over rows the compiler vectorises, where reading through a permutation could not be.
fn negative_direction(a: &mut [f64], n: usize) -> Option<(usize, f64)> {
    let a = &mut a[..n * n];
    let scale = a.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    if scale == 0.0 {
        return None;
    }
    let tol = NEGATIVE_PIVOT * scale;
    // order[r]: the coordinate now at row and column r.
    let mut order: Vec<usize> = (0..n).collect();
    for step in 0..n {
        // The remaining diagonal entry of largest magnitude, negative ones first: a negative
        // diagonal is already a negative direction.
        let (p, _) = (step..n).map(|r| (r, a[r * n + r])).min_by(|x, y| {
            let key = |v: f64| if v < -tol { (0, v) } else { (1, -v) };
            key(x.1)
                .partial_cmp(&key(y.1))
                .unwrap_or(std::cmp::Ordering::Equal)
        })?;
        swap_symmetric(a, n, step, p);
        order.swap(step, p);
        let pivot = a[step * n + step];
        if pivot < -tol {
            return Some((order[step], pivot));
        }
        if pivot <= tol {
            // Every remaining diagonal entry is within the tolerance of 0: semi-definite only
            // if the remaining off-diagonal entries are too, else the 2 x 2 block
            // [0 a; a 0] has the eigenvalue -|a|.
            for r in step..n {
                for c in step..n {
                    let v = a[r * n + c];
                    if r != c && v.abs() > tol {
                        return Some((order[r], -v.abs()));
                    }
                }
            }
            return None;
        }
        let (done, rest) = a.split_at_mut((step + 1) * n);
        let pivot_row = &done[step * n + step + 1..step * n + n];
        for row in rest.chunks_exact_mut(n) {
            let l = row[step] / pivot;
            // Rows not coupled to the pivot are unchanged: a banded or block-diagonal M
            // (free particles, chains) costs what its couplings cost, not n^3.
            if l == 0.0 {
                continue;
            }
            for (x, &u) in row[step + 1..].iter_mut().zip(pivot_row) {
                *x -= l * u;
            }
        }
    }
    None
}

/// Swaps rows r and s and columns r and s of the n x n row-major `a` (a symmetric
/// permutation: the diagonal entries trade places, and `a` stays symmetric).
fn swap_symmetric(a: &mut [f64], n: usize, r: usize, s: usize) {
    if r == s {
        return;
    }
    for c in 0..n {
        a.swap(r * n + c, s * n + c);
    }
    for row in a.chunks_exact_mut(n) {
        row.swap(r, s);
    }
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

    /// A xorshift stream in [-1, 1): test matrices without a random-number crate.
    fn stream(mut x: u64) -> impl FnMut() -> f64 {
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// B B^T for a random n x k B (rank k): positive semi-definite.
    fn gram(n: usize, k: usize, next: &mut impl FnMut() -> f64) -> Vec<f64> {
        let b: Vec<f64> = (0..n * k).map(|_| next()).collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] = (0..k).map(|t| b[i * k + t] * b[j * k + t]).sum();
            }
        }
        a
    }

    /// Large matrices, where the pivoting swaps rows and columns many times: B B^T of rank
    /// 40 and 25 in 40 dimensions passes; minus 3 v v^T for a v orthogonal to the range of
    /// B (so v^T A v = -3 |v|^4 < 0) is refused; and a coordinate with a diagonal of -50
    /// among weak couplings is the one named, wherever it sits.
    #[test]
    fn pivoting_finds_negative_directions_in_large_matrices() {
        let n = 40;
        let mut next = stream(0x9E37_79B9_7F4A_7C15);
        for k in [40, 25] {
            let mut a = gram(n, k, &mut next);
            assert_eq!(negative_direction(&mut a, n), None, "rank {k}");
        }
        // v: e_0 with its components along B's columns removed (Gram-Schmidt on B's columns).
        let k = 25;
        let b: Vec<Vec<f64>> = (0..k).map(|_| (0..n).map(|_| next()).collect()).collect();
        let mut basis: Vec<Vec<f64>> = Vec::new();
        for col in &b {
            let mut u = col.clone();
            for e in &basis {
                let d: f64 = u.iter().zip(e).map(|(x, y)| x * y).sum();
                u.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
            }
            let norm = u.iter().map(|x| x * x).sum::<f64>().sqrt();
            basis.push(u.into_iter().map(|x| x / norm).collect());
        }
        let mut v: Vec<f64> = (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect();
        for e in &basis {
            let d: f64 = v.iter().zip(e).map(|(x, y)| x * y).sum();
            v.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
        }
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let bb: f64 = b.iter().map(|col| col[i] * col[j]).sum();
                a[i * n + j] = bb - 3.0 * v[i] * v[j];
            }
        }
        let (_, pivot) = negative_direction(&mut a, n).expect("indefinite");
        assert!(pivot < 0.0);
        for bad in [0, 17, n - 1] {
            let mut a = gram(n, n, &mut next);
            for j in 0..n {
                a[bad * n + j] *= 0.01;
                a[j * n + bad] *= 0.01;
            }
            a[bad * n + bad] = -50.0;
            assert_eq!(negative_direction(&mut a, n), Some((bad, -50.0)));
        }
    }

    /// The coordinate named is the one at the pivot, not its position after the swaps: in
    /// [[1, 2, 0], [2, 1, 0], [0, 0, 5]] the first pivot is coordinate 2 (5, swapped to the
    /// front), the second coordinate 1 (1, the first of two equal diagonals), and the third,
    /// coordinate 0 now at position 2, has the Schur complement 1 - 2 * 2 = -3.
    #[test]
    fn a_late_negative_pivot_names_its_coordinate() {
        let mut a = vec![1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 5.0];
        assert_eq!(negative_direction(&mut a, 3), Some((0, -3.0)));
    }
}
