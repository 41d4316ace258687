//! Program: symbolic matrices as one straight-line SSA program, its passes, and its
//! interpreter.
//!
//! Enters: matrices of arena expressions (an [`Equations`](crate::Equations)' M, C q', g,
//! ...). Leaves: a [`Program`](crate::Program). The passes, each in its own file, are run in
//! their order by `crate::compile::passes` ([`Program::new`](crate::Program::new)): sums
//! rewritten by their most frequent factors ([`factor`], a greedy Horner scheme in several
//! variables); instructions in topological order with one register per distinct
//! subexpression (common-subexpression elimination is free on a hash-consed DAG:
//! [`builder`] gives each needed node one register, value-numbers identical instructions
//! and folds constants; [`cse`] holds the program type and drops dead registers);
//! scalings by powers of two moved onto the factor that depends on parameters only or is
//! ready first ([`scale`], exact; chain lengths by [`latency`]); products fused with the
//! sums that alone read them ([`fuse`]); the instructions ordered depth first from the
//! outputs ([`schedule`]), so that values die soon after they are made. [`hoist`] moves the
//! values that depend on parameters only out of several programs into one cache program
//! ([`hoist_parameters`](crate::hoist_parameters)). [`liveness`] finds the last use of each
//! register, and a [`Tape`](crate::Tape) is the program as register-file operations for
//! repeated evaluation without allocation, one state at a time or a block of states side by side
//! ([`tape_lanes`]).

pub(crate) mod builder;
pub(crate) mod cse;
pub(crate) mod factor;
pub(crate) mod factor_counts;
pub(crate) mod fuse;
pub(crate) mod hoist;
pub(crate) mod instructions;
pub(crate) mod latency;
pub(crate) mod liveness;
pub(crate) mod scale;
pub(crate) mod schedule;
pub(crate) mod tape;
pub(crate) mod tape_lanes;
pub(crate) mod tape_op;
