//! The recursive route for kinematic trees declared with links: M by composite bodies
//! (CRBA), C q', g, the bias C q' + g and the inverse dynamics by Newton-Euler (RNEA), and
//! Pi by the static recursion, built symbolically over the links' frames and then shared by
//! CSE like every other output.
//!
//! `bodies.rs` turns the links into moving bodies: a fixed link merged into the nearest
//! moving link above it (or into the world, where it adds a constant to Pi), and each
//! moving link's frame turned so that its joint axis is z. Body k then has, relative to
//! its parent p, the rotation R_k = E_k rot_z(q_k) (k axes to p axes, E_k constant), the
//! origin o_k (in p; o_k + E_k e_z q_k for a prismatic joint) and the axis S_k = e_z, and
//! its inertia about its origin in its axes: mass m_k, first moment h_k = m_k c_k and I_k.
//! `newton_euler.rs` holds the Newton-Euler passes, `composite.rs` the composite bodies
//! and the potential.
//!
//! Each link's velocities, accelerations, forces and composite inertia are named once
//! ([`crate::Node::Named`]): the expressions of the links below read them as operands, so
//! every link adds O(1) nodes to the bias and the inverse dynamics and every entry of M
//! O(1) nodes, whatever the depth of the tree; a numeric factor (a mass, a length) scales
//! a named sum with one multiplication instead of being distributed over its terms.

mod articulated;
mod bodies;
mod composite;
mod newton_euler;
mod vector;

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::Result;
use crate::mechanics::model::Model;
use crate::mechanics::tree::{Link, LinkJoint};
use bodies::tree_bodies;
use composite::{composite_gravity, composite_mass, potential};
use newton_euler::{Motion, newton_euler};
use vector::{cross, mat3, mul};

/// The outputs of the recursive route (module docs), the links' gravity included where a
/// gravity vector is declared.
pub(crate) struct TreeEquations {
    /// M (n x n).
    pub(crate) mass: Matrix,
    /// C q' (n x 1), without gravity.
    pub(crate) coriolis_forces: Matrix,
    /// g (n x 1), the links' gravity forces (zeros without gravity).
    pub(crate) gravity: Matrix,
    /// C q' + g (n x 1) in one Newton-Euler pass.
    pub(crate) bias: Matrix,
    /// M q'' + C q' + g (n x 1) in one Newton-Euler pass.
    pub(crate) inverse_dynamics: Matrix,
    /// Pi of the links' gravity (0 without gravity).
    pub(crate) potential: Id,
}

/// M, C q', g, C q' + g, M q'' + C q' + g and Pi of a model whose links carry all its
/// kinetic energy (module docs).
pub(crate) fn tree_equations(model: &mut Model) -> Result<TreeEquations> {
    let n = model.coordinates.len();
    let qd: Vec<Id> = model.coordinates.iter().map(|c| c.qd).collect();
    let qdd: Vec<Id> = model.coordinates.iter().map(|c| c.qdd).collect();
    let mut arena = std::mem::take(&mut model.arena);
    let result = (|| {
        let a = &mut arena;
        let tree = tree_bodies(a, model)?;
        let g = model.gravity.as_ref();
        let mass = composite_mass(a, &tree, n);
        let pass = |a: &mut Arena, rates, accelerations, gravity| {
            let m = Motion {
                rates,
                accelerations,
                gravity,
            };
            Matrix::column(newton_euler(a, &tree, n, &m))
        };
        let coriolis_forces = pass(a, Some(&qd[..]), None, None);
        let gravity = match g {
            Some(g) => Matrix::column(composite_gravity(a, &tree, n, g)),
            None => Matrix::zeros(a, n, 1),
        };
        let bias = pass(a, Some(&qd[..]), None, g);
        let inverse_dynamics = pass(a, Some(&qd[..]), Some(&qdd[..]), g);
        let potential = match g {
            Some(g) => potential(a, &tree, g),
            None => a.int(0),
        };
        Ok(TreeEquations {
            mass,
            coriolis_forces,
            gravity,
            bias,
            inverse_dynamics,
            potential,
        })
    })();
    model.arena = arena;
    result
}

/// q'' (n x 1) and the pivots (n x 1, the articulated inertias along the axes) of the
/// efforts `effort` (one node per coordinate) by the articulated-body algorithm
/// (`articulated.rs`): M q'' + b = u with the joint forces u + tau - dPi/dq of the
/// declared forces and potential (the links' gravity is the base's acceleration).
///
/// # Errors
/// What differentiating the declared potential reports.
pub(crate) fn articulated_forward_dynamics(
    model: &mut Model,
    effort: &[Id],
) -> Result<(Matrix, Matrix)> {
    let n = model.coordinates.len();
    let qd: Vec<Id> = model.coordinates.iter().map(|c| c.qd).collect();
    let q: Vec<SymbolId> = model
        .coordinates
        .iter()
        .filter_map(|c| model.arena.as_symbol(c.q))
        .collect();
    let mut arena = std::mem::take(&mut model.arena);
    let result = (|| {
        let a = &mut arena;
        let tree = tree_bodies(a, model)?;
        let declared = Differentiator::new().gradient(a, model.potential, &q)?;
        let torques: Vec<Id> = (0..n)
            .map(|k| {
                let t = a.add2(effort[k], model.forces[k]);
                a.sub(t, declared[k])
            })
            .collect();
        let g = model.gravity.as_ref();
        let (qdd, pivots) = articulated::forward_dynamics(a, &tree, n, &qd, &torques, g);
        Ok((Matrix::column(qdd), Matrix::column(pivots)))
    })();
    model.arena = arena;
    result
}

/// The frame Jacobian of link `l` at its origin, world axes (6 x n): rows 0..3 the
/// velocity of the origin, rows 3..6 the angular velocity; column of joint j (an ancestor
/// of l or l itself), with z_j = R_w,j a_j: [z_j x (p_l - p_j); z_j] (revolute),
/// [z_j; 0] (prismatic); the floating root's six, with z_k = R_w,root e_k: [z_k; 0] for
/// its velocity and [z_k x (p_l - p_root); z_k] for its angular velocity (Pinocchio's
/// LOCAL_WORLD_ALIGNED Jacobian).
pub fn frame_jacobian(arena: &mut Arena, links: &[Link], l: usize, n: usize) -> Matrix {
    let mut jac = Matrix::zeros(arena, 6, n);
    let target = links[l].position;
    let mut cur = Some(l);
    while let Some(j) = cur {
        let link = &links[j];
        match &link.joint {
            LinkJoint::Fixed => {}
            LinkJoint::Revolute { coordinate, axis } => {
                let z = mul(arena, &mat3(&link.rotation), axis);
                let d = [0, 1, 2].map(|i| arena.sub(target[i], link.position[i]));
                let v = cross(arena, &z, &d);
                for i in 0..3 {
                    jac.set(i, *coordinate, v[i]);
                    jac.set(3 + i, *coordinate, z[i]);
                }
            }
            LinkJoint::Prismatic { coordinate, axis } => {
                let z = mul(arena, &mat3(&link.rotation), axis);
                for (i, zi) in z.into_iter().enumerate() {
                    jac.set(i, *coordinate, zi);
                }
            }
            LinkJoint::Floating { coordinate, .. } => {
                // Translations and rotations along the root's axes z_k = R e_k.
                let d = [0, 1, 2].map(|i| arena.sub(target[i], link.position[i]));
                for k in 0..3 {
                    let z = [0, 1, 2].map(|i| link.rotation.get(i, k));
                    let v = cross(arena, &z, &d);
                    for i in 0..3 {
                        jac.set(i, coordinate + k, z[i]);
                        jac.set(i, coordinate + 3 + k, v[i]);
                        jac.set(3 + i, coordinate + 3 + k, z[i]);
                    }
                }
            }
        }
        cur = link.parent;
    }
    jac
}

#[cfg(test)]
mod tests;
