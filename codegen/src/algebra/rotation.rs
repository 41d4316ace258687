//! Orientations as products of rotations, and the body angular velocity.
//!
//! An orientation is a direction-cosine matrix R = F_1 F_2 ... F_k (body axes to world axes),
//! each factor an elementary rotation `rot_x(a)`, `rot_y(a)`, `rot_z(a)` about a body axis,
//! or an explicit 3x3 matrix F(q, t).
//!
//! The body angular velocity w is defined by the skew matrix [w]x = R^T R' (seed eq. 2.5;
//! R' by Theorem 1, R' = (dR/dq)(I_3 kron q') + dR/dt). For a product R = A B the product
//! rule gives R^T R' = B^T (A^T A') B + B^T B', i.e. w_R = B^T w_A + w_B, so w is built
//! factor by factor without ever forming R^T R' (whose entries would carry sin^2 + cos^2
//! pairs the canonical forms do not cancel):
//! - elementary factor rot_e(a): w = e a' (e the unit axis);
//! - explicit factor F: w = vee(F^T F'), vee([w]x) = (w_32, w_13, w_21), with F' by Theorem 1.
//!
//! w is linear in the rates, w = J_w q' + w_t; [`Orientation::angular_jacobian`] returns J_w
//! (3 x n) and w_t.

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::Result;

/// A body axis of an elementary rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// e_x = (1, 0, 0).
    X,
    /// e_y = (0, 1, 0).
    Y,
    /// e_z = (0, 0, 1).
    Z,
}

impl Axis {
    /// 0, 1, 2 for x, y, z.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

/// One factor of an orientation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RotationFactor {
    /// rot_e(angle): rot_x(a) = [[1, 0, 0], [0, c, -s], [0, s, c]],
    /// rot_y(a) = [[c, 0, s], [0, 1, 0], [-s, 0, c]], rot_z(a) = [[c, -s, 0], [s, c, 0],
    /// [0, 0, 1]] with c = cos a, s = sin a.
    Elementary(Axis, Id),
    /// An explicit 3x3 direction-cosine matrix F(q, t) (assumed orthogonal: the angular
    /// velocity is vee(F^T F')).
    Explicit(Matrix),
}

/// A direction-cosine matrix R = F_1 ... F_k (body to world).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Orientation {
    /// The factors, left to right.
    pub factors: Vec<RotationFactor>,
}

/// The elementary rotation matrix rot_e(a) (see [`RotationFactor::Elementary`]).
pub fn elementary_rotation(arena: &mut Arena, axis: Axis, angle: Id) -> Matrix {
    let (c, s) = (arena.cos(angle), arena.sin(angle));
    let ms = arena.neg(s);
    let (zero, one) = (arena.int(0), arena.int(1));
    let data = match axis {
        Axis::X => vec![one, zero, zero, zero, c, ms, zero, s, c],
        Axis::Y => vec![c, zero, s, zero, one, zero, ms, zero, c],
        Axis::Z => vec![c, ms, zero, s, c, zero, zero, zero, one],
    };
    Matrix {
        rows: 3,
        cols: 3,
        data,
    }
}

/// vee of a 3x3 matrix S: (S_32, S_13, S_21), the vector w with [w]x = S when S is skew.
fn vee(s: &Matrix) -> [Id; 3] {
    [s.get(2, 1), s.get(0, 2), s.get(1, 0)]
}

impl Orientation {
    /// R = F_1 F_2 ... F_k (the identity for no factors).
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] when an explicit factor is not 3x3.
    pub fn matrix(&self, arena: &mut Arena) -> Result<Matrix> {
        let mut r = Matrix::identity(arena, 3);
        for f in &self.factors {
            let m = match f {
                RotationFactor::Elementary(axis, a) => elementary_rotation(arena, *axis, *a),
                RotationFactor::Explicit(m) => m.clone(),
            };
            r = r.mul(arena, &m)?;
        }
        Ok(r)
    }

    /// The body angular velocity w = J_w q' + w_t (module docs): J_w (3 x n, column k the
    /// body angular velocity per unit q_k') and w_t (the explicit-time part, zero unless
    /// a factor depends on `time`).
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] when an explicit factor is not 3x3;
    /// differentiation errors.
    pub fn angular_jacobian(
        &self,
        arena: &mut Arena,
        d: &mut Differentiator,
        q: &[SymbolId],
        time: Option<SymbolId>,
    ) -> Result<(Matrix, [Id; 3])> {
        let n = q.len();
        // Columns 0..n: per q_k'; column n: explicit time.
        let vars: Vec<Option<SymbolId>> = q.iter().copied().map(Some).chain([time]).collect();
        let mut w = Matrix::zeros(arena, 3, n + 1);
        for f in &self.factors {
            let (ft, local) = match f {
                RotationFactor::Elementary(axis, a) => {
                    let m = elementary_rotation(arena, *axis, *a);
                    let mut local = Matrix::zeros(arena, 3, n + 1);
                    for (k, v) in vars.iter().enumerate() {
                        if let Some(s) = v {
                            let da = d.diff(arena, *a, *s)?;
                            local.set(axis.index(), k, da);
                        }
                    }
                    (m.transpose()?, local)
                }
                RotationFactor::Explicit(m) => {
                    let ft = m.transpose()?;
                    let mut local = Matrix::zeros(arena, 3, n + 1);
                    for (k, v) in vars.iter().enumerate() {
                        let Some(s) = v else { continue };
                        let mut dm = m.clone();
                        for e in &mut dm.data {
                            *e = d.diff(arena, *e, *s)?;
                        }
                        if dm.is_zero(arena) {
                            continue;
                        }
                        let skew = ft.mul(arena, &dm)?;
                        for (i, x) in vee(&skew).into_iter().enumerate() {
                            local.set(i, k, x);
                        }
                    }
                    (ft, local)
                }
            };
            w = ft.mul(arena, &w)?.add(arena, &local)?;
        }
        let jw = Matrix::from_fn(3, n, |i, j| w.get(i, j));
        Ok((jw, [w.get(0, n), w.get(1, n), w.get(2, n)]))
    }
}
