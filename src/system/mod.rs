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

mod compiled;
mod dynamic;
mod info;
mod interpreted;
mod mechanism;
mod registers;
pub(crate) mod routine;

pub use compiled::Compiled;
pub use dynamic::{Evaluation, System, Tangent};
pub use info::{ConstraintRow, SystemInfo};
pub use interpreted::Interpreted;
pub use mechanism::{Independent, Mechanism, StaticEvaluation};
