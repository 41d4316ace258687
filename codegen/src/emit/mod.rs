//! Emit: a [`Program`](crate::Program) as Rust tokens.
//!
//! Enters: a program and the caller's [`EmitBindings`](crate::EmitBindings) (the tokens that
//! read each symbol: `self.l1`, `q[2]`) and [`OutputTarget`](crate::OutputTarget)s. Leaves:
//! the statements of a function body in SSA form, one `let` per instruction, nested in
//! blocks so that each register lives only until its last use; no allocation, no panics,
//! clean under `clippy -D warnings`. In bodies with many angles, sines and cosines whose
//! arguments are at hand together are computed side by side ([`lanes`]), by the math
//! module's `sin_cos_lanes` or by an instruction set value in scope
//! ([`EmitBindings::set_isa`](crate::EmitBindings::set_isa): a body generic over
//! `mechanism_math::Isa`). Bodies past [`LEAN_ABOVE`](crate::LEAN_ABOVE) instructions take
//! the form that costs rustc least per instruction (no annotations, each symbol read once,
//! matrices assigned whole: [`OutputTarget::Columns`](crate::OutputTarget::Columns)).

pub(crate) mod bindings;
pub(crate) mod body;
pub(crate) mod lanes;
pub(crate) mod target;
