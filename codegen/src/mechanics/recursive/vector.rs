//! 3-vectors and 3x3 matrices of expressions, as the recursive route combines them: each
//! product and sum canonical in the arena, and [`named`] where a step's result is read by
//! later steps (a sum kept as one operand, see [`crate::Node::Named`]).

use crate::algebra::expr::{Arena, Id, Vec3};

/// A 3x3 matrix of expressions, row by row.
pub(crate) type Mat3 = [[Id; 3]; 3];

/// [0, 0, 0].
pub(crate) fn zero(a: &mut Arena) -> Vec3 {
    let z = a.int(0);
    [z, z, z]
}

/// The 3x3 identity.
pub(crate) fn identity(a: &mut Arena) -> Mat3 {
    let (z, o) = (a.int(0), a.int(1));
    [[o, z, z], [z, o, z], [z, z, o]]
}

/// Each component of `v` named ([`Arena::named`]).
pub(crate) fn named(a: &mut Arena, v: &Vec3) -> Vec3 {
    v.map(|x| a.named(x))
}

/// u x v.
pub(crate) fn cross(a: &mut Arena, u: &Vec3, v: &Vec3) -> Vec3 {
    let t = |a: &mut Arena, i: usize, j: usize| {
        let p = a.mul2(u[i], v[j]);
        let q = a.mul2(u[j], v[i]);
        a.sub(p, q)
    };
    [t(a, 1, 2), t(a, 2, 0), t(a, 0, 1)]
}

/// u . v.
pub(crate) fn dot(a: &mut Arena, u: &Vec3, v: &Vec3) -> Id {
    let t: [Id; 3] = [0, 1, 2].map(|i| a.mul2(u[i], v[i]));
    a.add(&t)
}

/// u + v.
pub(crate) fn add(a: &mut Arena, u: &Vec3, v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| a.add2(u[i], v[i]))
}

/// s u.
pub(crate) fn scale(a: &mut Arena, s: Id, u: &Vec3) -> Vec3 {
    u.map(|x| a.mul2(s, x))
}

/// R v.
pub(crate) fn mul(a: &mut Arena, r: &Mat3, v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: [Id; 3] = [0, 1, 2].map(|k| a.mul2(r[i][k], v[k]));
        a.add(&t)
    })
}

/// R^T v.
pub(crate) fn mul_t(a: &mut Arena, r: &Mat3, v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: [Id; 3] = [0, 1, 2].map(|k| a.mul2(r[k][i], v[k]));
        a.add(&t)
    })
}

/// A B.
pub(crate) fn mat_mul(a: &mut Arena, x: &Mat3, y: &Mat3) -> Mat3 {
    [0, 1, 2].map(|i| {
        [0, 1, 2].map(|j| {
            let t: [Id; 3] = [0, 1, 2].map(|k| a.mul2(x[i][k], y[k][j]));
            a.add(&t)
        })
    })
}

/// A^T.
pub(crate) fn transpose(x: &Mat3) -> Mat3 {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| x[j][i]))
}

/// The matrix of a 3x3 [`crate::Matrix`].
pub(crate) fn mat3(m: &crate::algebra::matrix::Matrix) -> Mat3 {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m.get(i, j)))
}
