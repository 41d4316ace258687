//! A floating base: the root link of a tree moving freely relative to the world, in
//! Pinocchio's free-flyer layout.
//!
//! `joint = floating(base);` on a root link gives it a configuration of seven numbers and a
//! velocity of six, so the generated type's q and v differ in size:
//! - q = [p (3), quaternion (x, y, z, w), joint positions]: NQ = 7 + joints, p the root's
//!   origin in the world and the unit quaternion its axes, R(q) in
//!   [`crate::mechanics::links::quaternion_matrix`];
//! - v = [v (3), w (3), joint rates]: NV = 6 + joints, the velocity of the root's origin
//!   and its angular velocity, both in the root's axes; a = dv/dt.
//!
//! So p' = R v and R' = R [w]x: v is not the derivative of q, and the configuration moves
//! on SE(3) x R^joints. The model's coordinates are the NV velocity coordinates (the root's
//! six first: `base_vx`, .., `base_wz`), their q symbols unused; the seven configuration
//! symbols (`base_x`, .., `base_qw`) live in the link's joint
//! ([`crate::mechanics::tree::LinkJoint::Floating`]). The recursive route derives every
//! output in v (`mechanics::recursive`: the root joint's motion subspace is the identity in
//! the root's axes); the energy route, constraint rows, a declared T or Pi, springs and the
//! residual's tangent (all written for v = q') are refused or not compiled.

use crate::algebra::expr::Id;
use crate::error::{DeclarationError, Error, Location, Result};
use crate::mechanics::model::Model;
use crate::mechanics::tree::LinkJoint;

/// The floating root of a model: its link, its first velocity coordinate and its
/// configuration symbols (x, y, z, qx, qy, qz, qw).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FloatingRoot {
    /// The root link's index in `Model::links`.
    pub link: usize,
    /// The index of the first of its six velocity coordinates (0: they come first).
    pub coordinate: usize,
    /// The configuration symbols.
    pub configuration: [Id; 7],
}

impl Model {
    /// The floating root, if a link declares `joint = floating(..)`.
    pub fn floating_root(&self) -> Option<FloatingRoot> {
        self.links
            .iter()
            .enumerate()
            .find_map(|(link, l)| match l.joint {
                LinkJoint::Floating {
                    coordinate,
                    configuration,
                } => Some(FloatingRoot {
                    link,
                    coordinate,
                    configuration,
                }),
                _ => None,
            })
    }

    /// NQ, the size of the configuration: the coordinates plus one (the quaternion's four
    /// numbers stand for three rotations) with a floating root, the coordinates otherwise.
    pub fn configuration_size(&self) -> usize {
        self.coordinates.len() + usize::from(self.floating_root().is_some())
    }

    /// The index in q (of [`Model::configuration_size`] entries) of coordinate i's
    /// position: i itself without a floating root; with one, `None` for the root's six
    /// velocity coordinates and i + 1 for the joints after them.
    pub fn configuration_index(&self, i: usize) -> Option<usize> {
        match self.floating_root() {
            None => Some(i),
            Some(f) if (f.coordinate..f.coordinate + 6).contains(&i) => None,
            Some(_) => Some(i + 1),
        }
    }
}

/// What a floating model must be: its root's velocity coordinates first, and a tree of
/// links carrying all of T and Pi with no constraint rows and no springs, so that the
/// recursive route derives every output in v. `lagrange` asks for the energy route.
pub(crate) fn check_floating(model: &Model, lagrange: bool) -> Result<()> {
    let Some(root) = model.floating_root() else {
        return Ok(());
    };
    let link = &model.links[root.link];
    let refuse = |problem: &str, at: Location| {
        let kind = DeclarationError::Link {
            link: link.name.clone(),
            problem: format!("with a floating base, {problem}"),
        };
        Err(Error::declaration(kind, at))
    };
    if root.coordinate != 0 {
        return refuse("its six velocities come first in q'", link.location);
    }
    if !model.kinetic_from_links || !model.potential_from_links {
        let problem = "the links carry all of T and Pi: no `body`, `kinetic`, `potential` or spring of its own";
        return refuse(problem, model.kinetic_location);
    }
    if let Some(c) = model
        .constraints
        .iter()
        .chain(&model.velocity_constraints)
        .next()
    {
        return refuse(
            "the tree has no constraint rows (v is not the rate of q)",
            c.location,
        );
    }
    if lagrange {
        return refuse(
            "the equations come from the recursive route alone (the energy route's q' is the rate of q)",
            link.location,
        );
    }
    Ok(())
}
