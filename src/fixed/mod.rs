//! Fixed-size solvers for the code `mechanism!` emits: no allocation, no std, sizes known
//! at compile time (`N` coordinates, `M` constraint rows). What a controller, a real-time
//! loop or a microcontroller calls.
//!
//! What enters: a [`crate::Mechanism`] (or one [`crate::StaticEvaluation`] of it). What
//! leaves:
//! - [`kkt_solve`]: q'' and lambda from the augmented (KKT) system
//!
//!   ```text
//!   [ M(q)   Phi_q^T ] [ q''    ]   [ Q = tau - C(q, q') q' - g(q) ]
//!   [ Phi_q  0       ] [ lambda ] = [ gamma                        ]
//!   ```
//!
//!   by the augmented-Lagrangian Schur complement (see [`kkt`](self::kkt_solve)), which
//!   needs M positive definite only on the allowed motions (the seed's M is singular) and
//!   accepts redundant rows;
//! - [`kkt_tree_solve`]: the m x m finish of the same system where `mechanism!` factored
//!   M = L^T D L over M's pattern in straight-line code (S lambda = Phi_q u - gamma,
//!   q'' = u - Y lambda, S = Phi_q M^-1 Phi_q^T): what the emitted
//!   [`crate::Mechanism::constrained_dynamics`] calls where M is positive definite and the
//!   route counts fewer operations, with `kkt_solve`'s redundant-row handling and its
//!   errors (it falls back to `kkt_solve` otherwise);
//! - [`forward_dynamics_derivatives`] and [`kkt_derivatives`]: the derivatives of q'' (and
//!   lambda) by q, q' and the effort, without and with constraint rows, through the same
//!   factorisation (what [`crate::Mechanism::forward_dynamics_derivatives`] and
//!   [`crate::Mechanism::constrained_dynamics_derivatives`] return);
//! - [`FixedStep`]: one classical Runge–Kutta step of the index-1 equations (q'' from
//!   [`crate::Mechanism::constrained_dynamics`]) followed by the
//!   projection of q onto Phi(q, t) = 0 and of q' onto Phi_q q' + Phi_t = 0.
//!
//! The run-time library (feature `std`) has the adaptive integrators, the events and the
//! diagnostics; these are the parts small enough to live without an allocator.

pub(crate) mod cholesky;
pub(crate) mod derivatives;
mod error;
mod kkt;
mod step;

pub use derivatives::{KktDerivatives, forward_dynamics_derivatives, kkt_derivatives};
pub use error::FixedError;
pub use kkt::{KktSolution, kkt_solve, kkt_tree_solve};
pub use step::{FixedStep, State};
