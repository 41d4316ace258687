//! One rigid body or point mass as the derivation holds it: its mass, centre of mass,
//! orientation and inertia, each an expression. Declared bodies (`bodies.rs`) and the links'
//! bodies of the recursive route (`Model::link_bodies`) are both of this type.

use crate::algebra::expr::{Id, Vec3};
use crate::algebra::matrix::Matrix;
use crate::algebra::rotation::Orientation;

/// A rigid body or a point mass.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Body {
    /// Name, as declared.
    pub name: String,
    /// Mass m.
    pub mass: Id,
    /// Centre of mass r(q, t), world.
    pub position: Vec3,
    /// Orientation R(q, t) (body to world); `None` for a point mass.
    pub orientation: Option<Orientation>,
    /// Inertia tensor about the centre of mass in body axes (3x3); `None`: zero (a point
    /// mass, or a body that carries points and axes only).
    pub inertia: Option<Matrix>,
}
