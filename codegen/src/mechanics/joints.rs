//! Joint helpers: constraint rows Phi(q, t) = 0 from named points and axes.
//!
//! - spherical(P, Q): P - Q = 0 (3 rows);
//! - distance(P, Q, L): (P - Q) . (P - Q) - L^2 = 0 (1 row);
//! - revolute(P, Q, a, b): P - Q = 0 and a parallel to b, written as the 2 independent rows
//!   a . b_1 = 0, a . b_2 = 0 with b_1, b_2 two directions fixed to b's body and
//!   perpendicular to b (5 rows);
//! - prismatic(P, Q, a, b): a parallel to b (a . b_1 = a . b_2 = 0), P - Q along b
//!   ((P - Q) . b_1 = (P - Q) . b_2 = 0) and no rotation about the axis, locked at the
//!   declared pose: with a_1 fixed to a's body, perpendicular to a, and x_k = a_1 . b_k at
//!   the coordinates' guesses and the parameter defaults, the row
//!   (x_1 (a_1 . b_2) - x_2 (a_1 . b_1)) / sqrt(x_1^2 + x_2^2) = 0 holds at the declared pose
//!   and keeps the turn of a_1 about the axis relative to b's body as declared (a_1 . b_2 = 0,
//!   when the pose has x_2 = 0) (5 rows).
//!
//! An [`AxisFrame`] is a body-fixed direction with two body-fixed perpendiculars, all in
//! world components. For a body axis a_0 (body components) of a body with orientation R:
//! direction R a_0, perpendiculars R (a_0 x e_k) and R (a_0 x (a_0 x e_k)), e_k the unit
//! vector along which a_0 is smallest (at the parameter defaults), so neither vanishes.

use crate::algebra::eval::eval;
use crate::algebra::expr::{Arena, Id, SymbolId, Vec3};
use crate::mechanics::bodies::{dot, sub3};

/// A body-fixed direction and two body-fixed directions perpendicular to it and to each
/// other (world components).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AxisFrame {
    /// The direction a.
    pub direction: Vec3,
    /// a_1 and a_2, perpendicular to a and to each other.
    pub perpendicular: [Vec3; 2],
}

/// a x b.
pub(crate) fn cross(arena: &mut Arena, a: &Vec3, b: &Vec3) -> Vec3 {
    let p = |arena: &mut Arena, i: usize, j: usize| {
        let x = arena.mul2(a[i], b[j]);
        let y = arena.mul2(a[j], b[i]);
        arena.sub(x, y)
    };
    [p(arena, 1, 2), p(arena, 2, 0), p(arena, 0, 1)]
}

/// The index k of the smallest |a_k| (a at the parameter defaults): e_k is then far from
/// parallel to a.
pub(crate) fn least_aligned(values: [f64; 3]) -> usize {
    let mut k = 0;
    for i in 1..3 {
        if values[i].abs() < values[k].abs() {
            k = i;
        }
    }
    k
}

/// Two perpendiculars of a (in the same components as a): a x e_k and a x (a x e_k).
pub(crate) fn perpendiculars(arena: &mut Arena, a: &Vec3, k: usize) -> [Vec3; 2] {
    let (zero, one) = (arena.int(0), arena.int(1));
    let mut e = [zero; 3];
    e[k] = one;
    let p1 = cross(arena, a, &e);
    let p2 = cross(arena, a, &p1);
    [p1, p2]
}

/// spherical(P, Q): the rows P_i - Q_i.
pub fn spherical(arena: &mut Arena, p: &Vec3, q: &Vec3) -> Vec<Id> {
    sub3(arena, p, q).to_vec()
}

/// distance(P, Q, L): the row (P - Q) . (P - Q) - L^2.
pub fn distance(arena: &mut Arena, p: &Vec3, q: &Vec3, length: Id) -> Vec<Id> {
    let d = sub3(arena, p, q);
    let dd = dot(arena, &d, &d);
    let l2 = arena.mul2(length, length);
    vec![arena.sub(dd, l2)]
}

/// a parallel to b: the rows a . b_1, a . b_2.
pub fn parallel(arena: &mut Arena, a: &Vec3, b: &AxisFrame) -> Vec<Id> {
    b.perpendicular.iter().map(|p| dot(arena, a, p)).collect()
}

/// revolute(P, Q, a, b): spherical(P, Q) and parallel(a, b) (5 rows).
pub fn revolute(arena: &mut Arena, p: &Vec3, q: &Vec3, a: &Vec3, b: &AxisFrame) -> Vec<Id> {
    let mut rows = spherical(arena, p, q);
    rows.extend(parallel(arena, a, b));
    rows
}

/// prismatic(P, Q, a, b): a . b_1, a . b_2, (P - Q) . b_1, (P - Q) . b_2 and the twist row
/// locked at the pose of `at_guesses` (module docs) (5 rows).
pub fn prismatic(
    arena: &mut Arena,
    p: &Vec3,
    q: &Vec3,
    a: &AxisFrame,
    b: &AxisFrame,
    at_guesses: &[(SymbolId, f64)],
) -> Vec<Id> {
    let mut rows = parallel(arena, &a.direction, b);
    let d = sub3(arena, p, q);
    rows.extend(b.perpendicular.iter().map(|x| dot(arena, &d, x)));
    let along = [
        dot(arena, &a.perpendicular[0], &b.perpendicular[0]),
        dot(arena, &a.perpendicular[0], &b.perpendicular[1]),
    ];
    let env = |s: SymbolId| at_guesses.iter().find(|k| k.0 == s).map(|k| k.1);
    let x = along.map(|e| eval(arena, e, &env).ok());
    let turned = match x {
        // The declared pose turns a_1 off b_1 by more than round-off: the row through it.
        [Some(x1), Some(x2)] if x2.abs() > 1e-12 * x1.abs() && x1.hypot(x2).is_finite() => {
            let n = x1.hypot(x2);
            match (arena.float(x1 / n), arena.float(-x2 / n)) {
                (Ok(c1), Ok(c2)) => {
                    let t1 = arena.mul2(c1, along[1]);
                    let t2 = arena.mul2(c2, along[0]);
                    Some(arena.add2(t1, t2))
                }
                _ => None,
            }
        }
        _ => None,
    };
    // a_1 . b_2 = 0 at the declared pose (or the pose cannot be evaluated): the row as it is.
    rows.push(turned.unwrap_or(along[1]));
    rows
}
