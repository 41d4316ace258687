//! Algebra: the expression arena and everything that computes with it symbolically or
//! numerically, knowing nothing of mechanisms.
//!
//! Enters: expressions built through [`Arena`](crate::Arena)'s canonical constructors.
//! Leaves: canonical expressions, derivatives, symbolic matrices and numbers. Imports only
//! the shared leaves `error` and `number` (exact rationals while they fit in i64, floats
//! otherwise), which the syntax stage uses too.
//!
//! - [`expr`]: a hash-consed DAG, children before parents, so increasing id order is
//!   topological; sums and products are flat, sorted and constant-folded, like terms collect.
//! - [`diff`]: d e/d x memoised per (node, symbol), and the total time derivative
//!   de/dt = (de/dq) q' + de/dt|_q (Van Khang's Theorem 1).
//! - [`matrix`]: Van Khang's matrix derivative, (dA/dx)[i, j n + k] = d a_ij / d x_k, and his
//!   Theorem 2 with Kronecker products, d(A B)/dx = (dA/dx)(B kron I_n) + A (dB/dx).
//! - [`rotation`]: orientations R = F_1 ... F_k and the body angular velocity
//!   \[w\]x = R^T R', factor by factor: w_(AB) = B^T w_A + w_B.
//! - [`eval`]: numeric evaluation of a DAG in id order, every intermediate
//!   value checked to be finite (sin and cos from `mechanism_math::sin_cos`, as every route).

pub(crate) mod budget;
pub(crate) mod cost;
pub(crate) mod dependencies;
pub(crate) mod diff;
pub(crate) mod eval;
pub(crate) mod expr;
pub(crate) mod matrix;
pub(crate) mod memo_table;
pub(crate) mod probe_table;
pub(crate) mod rotation;
pub(crate) mod visit_marks;
pub(crate) mod wide_children;
