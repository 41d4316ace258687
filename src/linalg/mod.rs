//! Linear algebra for the solvers.
//!
//! - [`NullSpace`]: the KKT system by a null-space basis of Phi_q (coordinate
//!   partitioning), the first route of small systems, with a cheap condition indicator;
//! - [`Lu`]: an in-place LU factorisation with partial pivoting on preallocated storage,
//!   with solves by A and A^T and a 1-norm condition estimate (the KKT route of small
//!   systems when the null-space route declines);
//! - [`DenseCholesky`]: Cholesky of a dense symmetric positive semi-definite matrix in
//!   storage allocated once, dropping vanishing pivots (the dynamics' derivatives);
//! - [`Envelope`]: Cholesky of a symmetric positive definite matrix inside its envelope (the
//!   augmented Lagrangian's M + alpha Phi_q^T Phi_q, the projections' Gram matrices), O(n)
//!   for banded chains;
//! - [`BandLu`]: LU with partial pivoting inside a band, and [`BandOrder`], the reverse
//!   Cuthill-McKee order that makes the KKT matrix of a chain banded (the direct solve of
//!   large chains, O(n) for a bounded band);
//! - [`LearntBand`]: the same band LU for a sequence of matrices whose pattern is learnt
//!   from them (the Newton matrices of an implicit integrator on a chain);
//! - [`RowBasis`]: the independent rows of a constraint Jacobian, its rank, and the null
//!   space of its transpose (minimum-norm multipliers);
//! - [`numerical_rank`], [`least_squares`] (both from one SVD: [`rank_and_least_squares`]):
//!   SVD-based, for work outside the step loop; [`conditioned_solve`], the same answer by
//!   LU for a square system whose condition is certainly small;
//! - [`eigenvalues`]: of a state matrix, by its real Schur form after balancing (a diagonal
//!   similarity that evens out its scales), as an error (not a panic or an endless loop) for
//!   an empty, non-finite or non-converging one; [`relative_residual`], how far a number is
//!   from being one of them;
//! - [`inf_norm`], [`max_nan`]: maximum norms that propagate NaN (every convergence test
//!   uses them, so a NaN entry is never read as a small residual).
//!
//! Invariant: everything used inside an integrator step works in storage allocated once.

mod balance;
mod band_lu;
mod band_order;
mod conditioned_solve;
mod dense_cholesky;
mod eigenvalues;
mod envelope;
mod kernels;
mod learnt_band;
mod lu;
mod norm;
mod null_space;
mod row_basis;
mod rows;
mod square_band;
mod svd;

pub use band_lu::BandLu;
pub use band_order::{BandOrder, coordinate_order};
pub use conditioned_solve::{MAX_CERTIFIED_CONDITION, conditioned_solve};
pub use dense_cholesky::DenseCholesky;
pub use eigenvalues::{eigenvalues, relative_residual};
pub use envelope::{Envelope, NotPositiveDefinite};
pub use learnt_band::LearntBand;
pub use lu::Lu;
pub use norm::{inf_norm, max_nan};
pub use null_space::{FixedNullSpace, NullSpace, NullSpaceSolve};
pub use row_basis::RowBasis;
pub use rows::RowSpans;
pub use svd::{least_squares, numerical_rank, rank_and_least_squares};
