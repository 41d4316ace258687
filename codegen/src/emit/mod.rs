//! Emit: a [`Program`](crate::Program) as Rust tokens.
//!
//! Enters: a program and the caller's [`EmitBindings`](crate::EmitBindings) (the tokens that
//! read each symbol: `self.l1`, `q[2]`) and [`OutputTarget`](crate::OutputTarget)s. Leaves:
//! the statements of a function body in SSA form, one `let` per instruction, nested in
//! blocks so that each register lives only until its last use; no allocation, no panics,
//! clean under `clippy -D warnings`. In bodies with many angles, sines and cosines whose
//! arguments are at hand together are computed side by side ([`lanes`]).

pub(crate) mod body;
pub(crate) mod lanes;
