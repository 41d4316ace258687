//! What can stop a fixed-size solve.

use core::fmt;

/// Why [`super::kkt_solve`], [`super::kkt_derivatives`] or [`super::FixedStep::step`]
/// failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FixedError {
    /// M is not positive definite on the motions the constraints allow: the accelerations
    /// are not determined (a massless coordinate that no constraint fixes). `coordinate` is
    /// where the factorisation of M + alpha Phi_q^T Phi_q lost its pivot.
    UndeterminedMotion {
        /// Index in q of the coordinate whose pivot vanished.
        coordinate: usize,
        /// Time of the evaluation, s.
        t: f64,
    },
    /// An input of the solve (M, forces, Phi_q, gamma or the state) is NaN or infinite.
    NotFinite {
        /// Time of the evaluation, s.
        t: f64,
    },
    /// The mechanism provides no residual's or constraint rows' tangent (a hand-written
    /// impl of [`crate::Mechanism`]; the code `mechanism!` emits provides both), which the
    /// derivatives of the constrained dynamics need.
    TangentNotProvided {
        /// Time of the evaluation, s.
        t: f64,
    },
    /// Newton's iteration for Phi(q, t) = 0 after the step did not reach the tolerance.
    ProjectionDidNotConverge {
        /// max |Phi_i| after the last iteration.
        residual: f64,
        /// Iterations run.
        iterations: usize,
        /// Time at the end of the step, s.
        t: f64,
    },
}

impl fmt::Display for FixedError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            FixedError::UndeterminedMotion { coordinate, t } => write!(
                f,
                "motion not determined at t = {t}: M is singular on an allowed motion \
                 (pivot of coordinate {coordinate})"
            ),
            FixedError::NotFinite { t } => {
                write!(f, "NaN or infinity in the equations at t = {t}")
            }
            FixedError::TangentNotProvided { t } => write!(
                f,
                "no exact tangent of the equations at t = {t}: the mechanism does not \
                 provide residual_tangent and constraint_tangent"
            ),
            FixedError::ProjectionDidNotConverge {
                residual,
                iterations,
                t,
            } => write!(
                f,
                "projection onto the constraints did not converge at t = {t}: \
                 max |Phi| = {residual:e} after {iterations} iterations"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for FixedError {}
