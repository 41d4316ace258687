//! The mechanism as the solvers see it.
//!
//! What enters: a declaration, either compiled by `mechanism!` into a type implementing
//! [`Mechanism`] (static sizes N, M; straight-line, allocation-free code) or derived at run
//! time from its text by the interpreter route ([`Interpreted`], codegen's tape). What
//! leaves: the object-safe [`System`] that every algorithm consumes, which evaluates at one
//! (t, q, q') everything the equations of motion need,
//!
//! ```text
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q(q, t)^T lambda = tau(t, q, q'),   Phi(q, t) = 0
//! Phi_q q'' = gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt
//! ```
//!
//! into caller-owned buffers ([`Evaluation`]), plus the names and declared data
//! ([`SystemInfo`]). Invariant: nothing here solves anything; the algorithms only read.

#[cfg(feature = "std")]
mod compiled;
#[cfg(feature = "interpreter")]
mod constraint_rows;
#[cfg(feature = "std")]
mod drawing;
#[cfg(feature = "std")]
mod dynamic;
pub(crate) mod floating;
mod floating_derivatives;
#[cfg(feature = "interpreter")]
mod forward_routine;
pub(crate) mod free_flyer;
#[cfg(feature = "std")]
mod info;
#[cfg(feature = "interpreter")]
mod interpreted;
#[cfg(feature = "interpreter")]
mod interpreted_constraints;
#[cfg(feature = "interpreter")]
mod interpreted_floating;
#[cfg(feature = "interpreter")]
mod interpreted_floating_derivatives;
mod joint_limits;
mod mechanism;
#[cfg(feature = "interpreter")]
mod model_info;
mod parameter_range;
#[cfg(feature = "interpreter")]
mod parameters;
#[cfg(feature = "interpreter")]
mod registers;
#[cfg(feature = "interpreter")]
mod robotics;
mod rotation_factor;
#[cfg(feature = "interpreter")]
pub(crate) mod routine;
#[cfg(feature = "interpreter")]
mod scatter;
mod sparsity;

#[cfg(feature = "std")]
pub use compiled::Compiled;
#[cfg(feature = "std")]
pub use drawing::{Drawing, DrawnPoint};
#[cfg(feature = "std")]
pub(crate) use dynamic::SolverKey;
#[cfg(feature = "std")]
pub use dynamic::{ConstraintTangent, Evaluation, Kinematic, System, Tangent};
pub use floating::FloatingBase;
#[cfg(feature = "std")]
pub use info::{BodyOrientation, ConstraintRow, SystemInfo};
#[cfg(feature = "interpreter")]
pub use interpreted::Interpreted;
#[cfg(feature = "interpreter")]
pub use interpreted_constraints::InterpretedConstraints;
#[cfg(feature = "interpreter")]
pub use interpreted_floating::{InterpretedFloating, Momentum};
#[cfg(feature = "interpreter")]
pub use interpreted_floating_derivatives::FloatingDerivatives;
pub use joint_limits::JointLimits;
pub use mechanism::{
    Accelerations, Coordinates, Independent, Mechanism, Multipliers, StaticEvaluation, Velocities,
};
pub use parameter_range::{ParameterError, ParameterRange, check_parameter};
pub use rotation_factor::RotationFactor;
#[cfg(feature = "std")]
pub use sparsity::Sparsity;
pub use sparsity::{EvaluationSlices, StaticSparsity};
