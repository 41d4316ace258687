//! The algorithms that run on a [`crate::System`], one per file; none of them changes the
//! system (the model is apart from the algorithms, as in Pinocchio's `multibody/` and
//! `algorithm/`).
//!
//! - [`kinematics`]: assembly and kinematic analysis, Phi(q, t) = 0 at the position,
//!   velocity and acceleration levels;
//! - [`dynamics`]: q'' and lambda at one instant from the augmented system, by LU, by a
//!   direct solve inside a band for large chains ([`banded_kkt`]), or by the augmented
//!   Lagrangian iteration ([`augmented_lagrangian`]) where neither applies;
//! - [`dynamics_derivatives`]: the derivatives of q'' and lambda by q, q' and an effort,
//!   through the augmented system's derivative;
//! - [`inverse`]: the driving forces of a prescribed motion, through [`drive`]s, whose
//!   kinks are found between samples ([`kink`]), the positions that velocity rows leave
//!   free integrated between samples ([`rolling_positions`]);
//! - [`linearize`]: the tangent dynamics in the independent coordinates;
//! - [`steady`]: the tangent dynamics about a steady motion in minimal variables (velocity
//!   constraints too), with exact derivatives; [`structural`]: its structural zeros, told
//!   from round-off, and the refusal where round-off hides what decides the motion;
//! - [`stabilization`]: projections onto Phi = 0 and Phi_q q' + Phi_t = 0, and Baumgarte;
//! - [`mobility`]: the rank of Phi_q, the degrees of freedom and the redundant rows;
//! - [`coordinate_singularity`]: an undetermined motion that the coordinates cause (angles
//!   whose axes line up), told from a body without inertia;
//! - [`reach`]: why an assembly stopped: given values out of reach, constraints that
//!   cannot be met, or Newton lost from the guess;
//! - [`velocity_rows`]: velocity rows that repeat or contradict the rows above them;
//! - [`finite`]: which entry of the equations is NaN or infinite, named for the user.
//!
//! Invariant: no file-system or terminal I/O, and nothing allocates inside the functions
//! an integrator step calls ([`dynamics::Dynamics::solve`], the projections).

pub(crate) mod augmented_lagrangian;
pub(crate) mod banded_kkt;
pub(crate) mod coordinate_singularity;
#[cfg(feature = "interpreter")]
pub(crate) mod drive;
pub(crate) mod dynamics;
pub(crate) mod dynamics_derivatives;
pub(crate) mod finite;
pub(crate) mod floating_motion;
#[cfg(feature = "interpreter")]
pub(crate) mod interpreted_floating_motion;
pub(crate) mod inverse;
pub(crate) mod kinematics;
pub(crate) mod kink;
pub(crate) mod linearize;
pub(crate) mod mobility;
pub(crate) mod reach;
pub(crate) mod rolling_positions;
pub(crate) mod stabilization;
pub(crate) mod steady;
pub(crate) mod structural;
pub(crate) mod velocity_rows;
