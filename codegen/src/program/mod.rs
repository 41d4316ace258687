//! Program: symbolic matrices as one straight-line SSA program, and its interpreter.
//!
//! Enters: matrices of arena expressions (an [`Equations`](crate::Equations)' M, C q', g,
//! ...). Leaves: a [`Program`](crate::Program). Its sums are first rewritten by their most
//! frequent factors ([`factor`], a greedy Horner scheme in several variables); then its
//! instructions come in topological order with
//! one register per distinct subexpression (common-subexpression elimination is free on a
//! hash-consed DAG: [`builder`] gives each needed node one register, value-numbers identical
//! instructions and folds constants, [`cse`] collects the outputs and drops dead registers);
//! scalings by powers of two moved onto the factor that depends on parameters only or is
//! ready first ([`scale`], exact; chain lengths by [`latency`]), products fused with the
//! sums that alone read them ([`fuse`]);
//! the instructions ordered depth first from the outputs ([`schedule`]), so that values die
//! soon after they are made; the last use of each register ([`liveness`]); and a [`Tape`](crate::Tape), the program
//! as register-file operations for repeated evaluation without allocation. [`hoist`] moves
//! the values that depend on parameters only out of several programs into one cache
//! program ([`hoist_parameters`](crate::hoist_parameters)).

pub(crate) mod builder;
pub(crate) mod cse;
pub(crate) mod factor;
pub(crate) mod fuse;
pub(crate) mod hoist;
pub(crate) mod instructions;
pub(crate) mod latency;
pub(crate) mod liveness;
pub(crate) mod scale;
pub(crate) mod schedule;
pub(crate) mod tape;
