//! Test crate for `mechanism-codegen`'s emitter: `build.rs` generates a few hundred random
//! expressions with a fixed seed ([`random`]), emits them as Rust with the codegen crate, and
//! this crate compiles them ([`generated`]). The tests rebuild the same expressions and
//! compare the compiled functions with the interpreter and the tape, and count allocations.
//!
//! `cargo clippy -p mechanism-emit-check -- -D warnings` lints the emitted code as a user's
//! crate would.

pub mod random;

/// The emitted functions (see `build.rs`).
pub mod generated {
    include!(concat!(env!("OUT_DIR"), "/generated.rs"));
}

/// The generated expressions as text (codegen's `to_text`), one a line, in generation order.
pub const EXPRS: &str = include_str!(concat!(env!("OUT_DIR"), "/exprs.txt"));

/// Operation counts of each emitted function (`e{k}`, `m{k}`, `all`), one a line.
pub const OP_COUNTS: &str = include_str!(concat!(env!("OUT_DIR"), "/op_counts.txt"));
