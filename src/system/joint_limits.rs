//! The limits a moving joint of a link tree declares (`limit`, `velocity_limit` and
//! `effort_limit`, as URDF gives them), by the coordinate the joint moves.
//!
//! The equations and the solvers do not enforce them: a joint limit is a unilateral
//! constraint (a contact with a stop), which the model of bilateral rows does not hold. The
//! runs report where a motion passed them instead (`output::LimitExcursion`).

/// The declared limits of one coordinate: positions within [lower, upper], |q'| at most
/// `velocity`, |tau| at most `effort` (each `None` when not declared). Units: rad, rad/s and
/// N m for a revolute joint; m, m/s and N for a prismatic one ([`JointLimits::linear`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Index of the coordinate in q.
    pub coordinate: usize,
    /// True for a prismatic joint (a length), false for a revolute one (an angle).
    pub linear: bool,
    /// [lower, upper] of q, lower <= upper.
    pub position: Option<[f64; 2]>,
    /// The largest |q'|.
    pub velocity: Option<f64>,
    /// The largest |tau| the joint's actuator gives.
    pub effort: Option<f64>,
}
