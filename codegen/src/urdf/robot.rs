//! The robot as the URDF describes it: links and the joints between them, with the numbers
//! read but nothing yet checked about the tree they form.

use super::error::Place;

/// A URDF `<robot>`: its links and joints in document order.
#[derive(Clone, Debug)]
pub(crate) struct Robot {
    /// The `name` attribute of `<robot>` (may be empty).
    pub name: String,
    /// Where `<robot>` is (options errors point here).
    pub place: Place,
    /// The links, in document order.
    pub links: Vec<Link>,
    /// The joints, in document order.
    pub joints: Vec<Joint>,
}

/// A `<link>`: a rigid body, or a massless frame.
#[derive(Clone, Debug)]
pub(crate) struct Link {
    /// The URDF name.
    pub name: String,
    /// Where the element is.
    pub place: Place,
    /// Mass properties; `None` for a link without `<inertial>`.
    pub inertial: Option<Inertial>,
}

/// An `<inertial>`: mass, centre of mass and rotational inertia of a link.
#[derive(Clone, Debug)]
pub(crate) struct Inertial {
    /// Where `<inertial>` is.
    pub place: Place,
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass in the link frame (`<origin xyz>`), m.
    pub xyz: [f64; 3],
    /// Orientation of the inertia axes (`<origin rpy>`), rad.
    pub rpy: [f64; 3],
    /// `ixx, ixy, ixz, iyy, iyz, izz` about the centre of mass in the `rpy` axes, kg m^2.
    pub inertia: [f64; 6],
    /// Where `<inertia>` is.
    pub inertia_place: Place,
}

/// The joint types imported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JointKind {
    /// Rotation about the axis, between limits.
    Revolute,
    /// Rotation about the axis, without limits.
    Continuous,
    /// Translation along the axis.
    Prismatic,
    /// No motion.
    Fixed,
}

impl JointKind {
    /// The URDF spelling (`revolute`, ...).
    pub fn urdf_name(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Continuous => "continuous",
            JointKind::Prismatic => "prismatic",
            JointKind::Fixed => "fixed",
        }
    }
}

/// A `<joint>`: how a child link moves relative to its parent.
#[derive(Clone, Debug)]
pub(crate) struct Joint {
    /// The URDF name.
    pub name: String,
    /// Where the element is.
    pub place: Place,
    /// The type.
    pub kind: JointKind,
    /// The `link` of `<parent>`.
    pub parent: String,
    /// Where `<parent>` is.
    pub parent_place: Place,
    /// The `link` of `<child>`.
    pub child: String,
    /// Where `<child>` is.
    pub child_place: Place,
    /// Joint origin in the parent frame (`<origin xyz>`), m.
    pub xyz: [f64; 3],
    /// Joint origin orientation (`<origin rpy>`), rad.
    pub rpy: [f64; 3],
    /// The unit axis, in the joint frame (`<axis xyz>`, default 1 0 0, normalised).
    pub axis: [f64; 3],
    /// `<limit>`, when present.
    pub limit: Option<Limit>,
    /// `<mimic>`, when present.
    pub mimic: Option<Mimic>,
    /// `<dynamics>`, when present.
    pub dynamics: Option<JointDynamics>,
    /// Locked at q = 0 by the options: written as a fixed joint.
    pub locked: bool,
}

/// A joint's `<dynamics>`: viscous damping b (N m s/rad, or N s/m for a prismatic joint)
/// and Coulomb friction (N m or N), each 0 when not given.
#[derive(Clone, Debug)]
pub(crate) struct JointDynamics {
    /// b in tau = -b q'.
    pub damping: f64,
    /// The friction's magnitude.
    pub friction: f64,
    /// Where `<dynamics>` is.
    pub place: Place,
}

/// A `<mimic>`: this joint's coordinate follows another's, q = multiplier * q_master +
/// offset (URDF defaults: multiplier 1, offset 0).
#[derive(Clone, Debug)]
pub(crate) struct Mimic {
    /// The URDF name of the joint followed.
    pub joint: String,
    /// The ratio of the two coordinates (rad/rad, m/m, or m/rad between kinds).
    pub multiplier: f64,
    /// The coordinate's value where the master's is 0 (rad or m).
    pub offset: f64,
    /// Where `<mimic>` is.
    pub place: Place,
}

/// A `<limit>`: the joint range and the actuator's bounds, each as given.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Limit {
    /// `lower`, rad or m.
    pub lower: Option<f64>,
    /// `upper`, rad or m.
    pub upper: Option<f64>,
    /// `velocity`, rad/s or m/s.
    pub velocity: Option<f64>,
    /// `effort`, N m or N.
    pub effort: Option<f64>,
}

impl Limit {
    /// The position range `[lower, upper]` when either bound is given (URDF: a missing bound
    /// is 0).
    pub fn range(&self) -> Option<[f64; 2]> {
        if self.lower.is_none() && self.upper.is_none() {
            None
        } else {
            Some([self.lower.unwrap_or(0.0), self.upper.unwrap_or(0.0)])
        }
    }
}
