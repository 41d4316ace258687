//! The kinematic tree of a declaration's links, as data: each link's frame relative to its
//! parent, its joint and its inertia about its origin (built by `mechanics::links`, read by
//! the recursive route `mechanics::recursive` and by the frames' outputs). Symbols as in
//! `mechanics::links`.

use crate::algebra::expr::{Id, Vec3};
use crate::algebra::matrix::Matrix;
use crate::error::Location;

/// How a link moves relative to its parent.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LinkJoint {
    /// Rigidly attached.
    Fixed,
    /// Turns by q about the unit axis (joint frame).
    Revolute {
        /// Index of q in the model's coordinates.
        coordinate: usize,
        /// The unit axis a, joint frame (= link frame).
        axis: Vec3,
    },
    /// Slides by q along the unit axis (joint frame).
    Prismatic {
        /// Index of q in the model's coordinates.
        coordinate: usize,
        /// The unit axis a, joint frame (= link frame).
        axis: Vec3,
    },
    /// Moves freely relative to the world (a root link only): placed by its configuration,
    /// the origin p = (x, y, z) in the world and the unit quaternion (qx, qy, qz, qw) of
    /// its axes, and moving with the six velocity coordinates from `coordinate` on, the
    /// linear velocity of its origin and its angular velocity, both in its own axes
    /// (`mechanics::floating`).
    Floating {
        /// Index of the first velocity coordinate (vx; then vy, vz, wx, wy, wz).
        coordinate: usize,
        /// The configuration symbols x, y, z, qx, qy, qz, qw.
        configuration: [Id; 7],
    },
}

impl LinkJoint {
    /// The coordinate of a moving joint (the first of a floating joint's six).
    pub fn coordinate(&self) -> Option<usize> {
        match self {
            LinkJoint::Fixed => None,
            LinkJoint::Revolute { coordinate, .. }
            | LinkJoint::Prismatic { coordinate, .. }
            | LinkJoint::Floating { coordinate, .. } => Some(*coordinate),
        }
    }
}

/// One link of the tree: its frame relative to its parent, its joint and its inertia.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// Name, as declared.
    pub name: String,
    /// Index of the parent link; `None`: the world.
    pub parent: Option<usize>,
    /// The joint to the parent.
    pub joint: LinkJoint,
    /// E, the joint frame's axes in the parent frame (3x3, constant).
    pub origin_rotation: Matrix,
    /// xyz, the joint frame's origin in the parent frame.
    pub origin: Vec3,
    /// m (0 for a massless frame).
    pub mass: Id,
    /// h = m c, link frame.
    pub first_moment: Vec3,
    /// I_o, the inertia about the link origin in link axes (3x3).
    pub inertia: Matrix,
    /// R_w: link axes in world axes (3x3).
    pub rotation: Matrix,
    /// p_w: the link origin in the world.
    pub position: Vec3,
    /// `limit = [lower, upper]`, when declared.
    pub limit: Option<[f64; 2]>,
    /// `velocity_limit`, when declared.
    pub velocity_limit: Option<f64>,
    /// `effort_limit`, when declared.
    pub effort_limit: Option<f64>,
    /// Where the link is declared.
    pub location: Location,
}

/// The limits a moving joint declares, by the coordinate it moves (what a run reports
/// against; nothing in the equations enforces them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeclaredLimits {
    /// Index of the coordinate in q.
    pub coordinate: usize,
    /// True for a prismatic joint (q a length in m), false for a revolute one (rad).
    pub linear: bool,
    /// `limit = [lower, upper]`.
    pub position: Option<[f64; 2]>,
    /// `velocity_limit`: the largest |q'|.
    pub velocity: Option<f64>,
    /// `effort_limit`: the largest |tau|.
    pub effort: Option<f64>,
}

/// The declared limits of the moving joints of `links`, one entry per coordinate that has
/// any, in coordinate order.
pub fn declared_limits(links: &[Link]) -> Vec<DeclaredLimits> {
    let mut out: Vec<DeclaredLimits> = links
        .iter()
        .filter(|l| l.limit.is_some() || l.velocity_limit.is_some() || l.effort_limit.is_some())
        .filter_map(|l| {
            let coordinate = l.joint.coordinate()?;
            Some(DeclaredLimits {
                coordinate,
                linear: matches!(l.joint, LinkJoint::Prismatic { .. }),
                position: l.limit,
                velocity: l.velocity_limit,
                effort: l.effort_limit,
            })
        })
        .collect();
    out.sort_by_key(|l| l.coordinate);
    out
}
