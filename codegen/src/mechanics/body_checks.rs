//! What a rigid body's mass and inertia must satisfy to be a body at all.
//!
//! - The mass is not negative.
//! - A rolling wheel's radius is greater than zero.
//! - The inertia tensor (about the centre of mass, in body axes) is symmetric, its principal
//!   moments I1, I2, I3 are not negative and satisfy the triangle inequalities
//!   I1 + I2 >= I3 (and permutations): I_z = integral of (x^2 + y^2) dm is at most
//!   I_x + I_y = integral of (x^2 + y^2 + 2 z^2) dm. Equality is a flat or thin body (a rod
//!   has I1 = 0, I2 = I3), allowed.
//!
//! The checks run on the values at the declared parameter values; an entry that depends on
//! the coordinates or t is not checked (it has no single value). Tolerances are relative to
//! the largest entry: 1e-12 for symmetry (entries are usually the same expression, checked
//! exactly first), 1e-9 for the moments (the eigenvalues carry rounding of a few ulp times
//! the largest moment).

use crate::algebra::eval::eval;
use crate::algebra::expr::{Arena, Id, SymbolId, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::algebra::rotation::{Orientation, RotationFactor};
use crate::error::{DeclarationError, Error, Location, Result};

/// Relative asymmetry of two numeric entries beyond which the tensor is not symmetric.
const SYMMETRY: f64 = 1e-12;
/// Relative tolerance of the conditions on the principal moments.
const MOMENTS: f64 = 1e-9;

/// The value of `id` at the declared parameter values, if it depends on nothing else.
fn value(arena: &Arena, id: Id, known: &[(SymbolId, f64)]) -> Option<f64> {
    let env = |s: SymbolId| known.iter().find(|k| k.0 == s).map(|k| k.1);
    eval(arena, id, &env).ok().filter(|v| v.is_finite())
}

/// A negative mass of body `body` (declared at `at`) is an error.
pub(crate) fn check_mass(
    arena: &Arena,
    body: &str,
    mass: Id,
    known: &[(SymbolId, f64)],
    at: Location,
) -> Result<()> {
    match value(arena, mass, known) {
        Some(m) if m < 0.0 => Err(Error::declaration(
            DeclarationError::NegativeMass {
                body: body.to_string(),
                value: m,
            },
            at,
        )),
        _ => Ok(()),
    }
}

/// A rolling wheel `body` whose radius `radius` (declared at `at`) is zero or negative at
/// the declared values (and the initial guesses, for a radius written with coordinates) is
/// an error, as a negative mass is: the contact point would lie above the centre, and the
/// wheel roll backwards under the ground.
pub(crate) fn check_radius(
    arena: &Arena,
    body: &str,
    radius: Id,
    known: &[(SymbolId, f64)],
    at: Location,
) -> Result<()> {
    match value(arena, radius, known) {
        Some(r) if r <= 0.0 => Err(Error::declaration(
            DeclarationError::WheelRadius {
                body: body.to_string(),
                value: r,
            },
            at,
        )),
        _ => Ok(()),
    }
}

/// The inertia tensor `inertia` (3 x 3) of body `body`, declared at `at`: symmetric, with
/// principal moments that a mass distribution can have (see the module docs).
pub(crate) fn check_inertia(
    arena: &Arena,
    body: &str,
    inertia: &Matrix,
    known: &[(SymbolId, f64)],
    at: Location,
) -> Result<()> {
    let mut a = [[0.0; 3]; 3];
    for (i, row) in a.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            match value(arena, inertia.get(i, j), known) {
                Some(x) => *v = x,
                None => return Ok(()),
            }
        }
    }
    let scale = a.iter().flatten().fold(0.0_f64, |s, v| s.max(v.abs()));
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let same = inertia.get(i, j) == inertia.get(j, i);
        if !same && (a[i][j] - a[j][i]).abs() > SYMMETRY * scale {
            return Err(Error::declaration(
                DeclarationError::InertiaNotSymmetric {
                    body: body.to_string(),
                    row: i + 1,
                    column: j + 1,
                    upper: a[i][j],
                    lower: a[j][i],
                },
                at,
            ));
        }
    }
    let moments = symmetric_eigenvalues(a);
    let tol = MOMENTS * scale;
    let [i1, i2, i3] = moments;
    let negative = moments.iter().any(|&m| m < -tol);
    // Sorted ascending: the binding triangle inequality is i1 + i2 >= i3.
    if negative || i1 + i2 < i3 - tol {
        return Err(Error::declaration(
            DeclarationError::InertiaNotPhysical {
                body: body.to_string(),
                moments,
            },
            at,
        ));
    }
    Ok(())
}

/// Largest |(F^T F - I)_ij| of an explicit orientation factor F that still counts as
/// orthogonal: entries typed with 7 significant digits (0.7071068) deviate by about 1e-7.
const ORTHOGONALITY: f64 = 1e-6;

/// Each explicit factor F of the orientation `orientation` of body `body`, declared at `at`,
/// evaluated at `values` (the declared parameter values, the initial guesses and t = 0) is
/// a rotation: max |(F^T F - I)_ij| <= 1e-6 and det F > 0. An explicit factor is assumed
/// orthogonal by the angular velocity vee(F^T F'); one that is not (the zero matrix, a
/// scaled or sheared one, a reflection) would silently drop or distort the rotational
/// inertia. `rot_x/y/z` factors are rotations by construction. A factor that cannot be
/// evaluated there (it depends on something else) is not checked.
pub(crate) fn check_orientation(
    arena: &Arena,
    body: &str,
    orientation: &Orientation,
    values: &[(SymbolId, f64)],
    at: Location,
) -> Result<()> {
    for factor in &orientation.factors {
        let RotationFactor::Explicit(f) = factor else {
            continue;
        };
        let mut a = [[0.0; 3]; 3];
        for (i, row) in a.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                match value(arena, f.get(i, j), values) {
                    Some(x) => *v = x,
                    None => return Ok(()),
                }
            }
        }
        let mut deviation = 0.0_f64;
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| a[k][i] * a[k][j]).sum();
                let identity = if i == j { 1.0 } else { 0.0 };
                deviation = deviation.max((dot - identity).abs());
            }
        }
        let determinant = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        if deviation > ORTHOGONALITY || determinant <= 0.0 {
            return Err(Error::declaration(
                DeclarationError::OrientationNotRotation {
                    body: body.to_string(),
                    deviation,
                    determinant,
                    state: coordinates_at(arena, &f.data, values),
                },
                at,
            ));
        }
    }
    Ok(())
}

/// `t = 0, x = 0.5`: the coordinates that `entries` use, at their values in `values`
/// (rounded to 6 decimals), as an error shows where it evaluated them.
fn coordinates_at(arena: &Arena, entries: &[Id], values: &[(SymbolId, f64)]) -> String {
    let nodes = arena.nodes();
    let mut used = vec![false; nodes.len()];
    for e in entries {
        used[e.index()] = true;
    }
    // Children precede their parents: one sweep down marks every node the entries use.
    for k in (0..nodes.len()).rev() {
        if used[k] {
            nodes[k].for_each_child(|c| used[c.index()] = true);
        }
    }
    let symbols = arena.symbols();
    let mut parts = vec!["t = 0".to_string()];
    for (s, v) in values {
        let Some(symbol) = symbols.get(s.0 as usize) else {
            continue;
        };
        let node = arena.symbol_node(*s);
        if symbol.kind == SymbolKind::Coordinate && used.get(node.index()) == Some(&true) {
            let shown = format!("{v:.6}");
            let shown = shown.trim_end_matches('0').trim_end_matches('.');
            parts.push(format!("{} = {shown}", symbol.name));
        }
    }
    parts.join(", ")
}

/// The eigenvalues of the symmetric 3 x 3 `a` (its upper triangle read), ascending, by
/// cyclic Jacobi rotations (quadratically convergent; a few sweeps reach round-off).
fn symmetric_eigenvalues(mut a: [[f64; 3]; 3]) -> [f64; 3] {
    (a[1][0], a[2][0], a[2][1]) = (a[0][1], a[0][2], a[1][2]);
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation that zeroes a[p][q] (Golub and Van Loan, sec. 8.5.2).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
        }
    }
    let mut e = [a[0][0], a[1][1], a[2][2]];
    e.sort_by(f64::total_cmp);
    e
}

#[cfg(test)]
mod tests {
    use super::symmetric_eigenvalues;

    #[test]
    fn eigenvalues_of_known_tensors() {
        let close = |a: [f64; 3], b: [f64; 3]| {
            a.iter()
                .zip(&b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * (1.0 + y.abs()))
        };
        let d = symmetric_eigenvalues([[3.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]);
        assert_eq!(d, [1.0, 2.0, 3.0]);
        // [2 1 0; 1 2 0; 0 0 5]: 1, 3, 5.
        let e = symmetric_eigenvalues([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        assert!(close(e, [1.0, 3.0, 5.0]), "{e:?}");
        // The all-ones matrix: 0, 0, 3.
        let o = symmetric_eigenvalues([[1.0; 3]; 3]);
        assert!(close(o, [0.0, 0.0, 3.0]), "{o:?}");
    }
}
