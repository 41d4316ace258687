//! The structural pattern of M and Phi_q, known when the mechanism is built, and the
//! evaluation that writes these two matrices at their pattern only.
//!
//! An entry outside the pattern is zero at every (t, q, q') and every parameter value
//! (codegen's `Sparsity`: the compiled program writes the constant 0 there). A chain of N
//! four-bar loops (A02) has n = 2 (N + 1) coordinates and m = 2 N + 1 rows, but M has at
//! most 4 nonzeros per row and Phi_q at most 4: writing and reading the pattern only makes
//! an evaluation, and the large-system solves that read it, cost O(n) instead of O(n^2).
//!
//! - [`StaticSparsity`] is what `mechanism!` emits into `impl Mechanism` (`SPARSITY`),
//!   [`EvaluationSlices`] the run-time buffers `Mechanism::evaluate_sparse_into` writes.
//! - [`Sparsity`] (std) is the run-time copy a [`crate::System`] hands the solvers.

/// The structural nonzeros of M (n x n) and Phi_q (m x n) of a compiled mechanism, as
/// (row, column) pairs in row-major order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StaticSparsity {
    /// The entries of M that can be nonzero.
    pub mass: &'static [(u32, u32)],
    /// The entries of Phi_q that can be nonzero.
    pub jacobian: &'static [(u32, u32)],
}

/// Run-time buffers for one evaluation (what [`crate::Evaluation`] holds, as slices): M and
/// Phi_q column-major (n n and m n entries), the vectors and the two energies.
/// `Mechanism::evaluate_sparse_into` writes M and Phi_q at their structural pattern only:
/// the caller keeps the other entries at zero (a buffer made zero once and always written
/// by the same mechanism stays so), and every entry of the vectors.
#[derive(Debug)]
pub struct EvaluationSlices<'a> {
    /// M, column-major, n n entries.
    pub mass: &'a mut [f64],
    /// C(q, q') q', n entries.
    pub coriolis: &'a mut [f64],
    /// g(q), n entries.
    pub gravity: &'a mut [f64],
    /// tau(t, q, q'), n entries.
    pub forces: &'a mut [f64],
    /// Phi(q, t), m entries.
    pub phi: &'a mut [f64],
    /// Phi_q, column-major, m n entries.
    pub phi_q: &'a mut [f64],
    /// Phi_t, m entries.
    pub phi_t: &'a mut [f64],
    /// gamma, m entries.
    pub gamma: &'a mut [f64],
    /// T(q, q').
    pub kinetic: &'a mut f64,
    /// Pi(q).
    pub potential: &'a mut f64,
}

impl EvaluationSlices<'_> {
    /// Whether every slice has the length of a mechanism with n coordinates and m rows.
    pub fn fits(&self, n: usize, m: usize) -> bool {
        self.mass.len() == n * n
            && self.coriolis.len() == n
            && self.gravity.len() == n
            && self.forces.len() == n
            && self.phi.len() == m
            && self.phi_q.len() == m * n
            && self.phi_t.len() == m
            && self.gamma.len() == m
    }
}

#[cfg(feature = "std")]
pub use runtime::Sparsity;

#[cfg(feature = "std")]
mod runtime {
    use super::{EvaluationSlices, StaticSparsity};
    use crate::system::Evaluation;

    /// The structural pattern of M and Phi_q at run time (see the module docs): (row,
    /// column) pairs, row-major, each list sorted.
    #[derive(Clone, Debug, PartialEq, Eq)]
    pub struct Sparsity {
        /// Coordinates n.
        pub n: usize,
        /// Constraint rows m.
        pub m: usize,
        /// The entries of M (n x n) that can be nonzero.
        pub mass: Vec<(usize, usize)>,
        /// The entries of Phi_q (m x n) that can be nonzero.
        pub jacobian: Vec<(usize, usize)>,
        /// The solvers' order of the coordinates: the coordinate at each position, a
        /// fill-reducing order of the pattern of M + Phi_q^T Phi_q
        /// (the reverse Cuthill-McKee order of `linalg::band_order`), computed once with the pattern. Every
        /// run-time structure that works on ranges of coordinates (row spans, the rank
        /// basis, the projections' Gram matrices) works in this order; inputs and outputs
        /// stay in the declaration's.
        pub order: Vec<usize>,
    }

    impl Sparsity {
        /// The pattern of M and Phi_q with its coordinate order.
        pub fn new(
            n: usize,
            m: usize,
            mass: Vec<(usize, usize)>,
            jacobian: Vec<(usize, usize)>,
        ) -> Self {
            let order = crate::linalg::coordinate_order(n, &mass, &jacobian);
            Self {
                n,
                m,
                mass,
                jacobian,
                order,
            }
        }

        /// The run-time copy of a compiled mechanism's pattern.
        pub fn from_static(n: usize, m: usize, s: &StaticSparsity) -> Self {
            let wide =
                |p: &[(u32, u32)]| p.iter().map(|&(i, j)| (i as usize, j as usize)).collect();
            Self::new(n, m, wide(s.mass), wide(s.jacobian))
        }

        /// Whether every M and Phi_q entry is finite, reading the pattern only (the other
        /// entries are zero).
        pub fn all_finite(&self, e: &Evaluation) -> bool {
            let (mass, phi_q) = (e.mass.as_slice(), e.phi_q.as_slice());
            let (n, m) = (self.n, self.m);
            let mut ok = true;
            for &(i, j) in &self.mass {
                ok &= mass[i + j * n].is_finite();
            }
            for &(r, j) in &self.jacobian {
                ok &= phi_q[r + j * m].is_finite();
            }
            ok
        }
    }

    impl Evaluation {
        /// The buffers as [`EvaluationSlices`] (M and Phi_q column-major).
        pub fn slices(&mut self) -> EvaluationSlices<'_> {
            EvaluationSlices {
                mass: self.mass.as_mut_slice(),
                coriolis: self.coriolis.as_mut_slice(),
                gravity: self.gravity.as_mut_slice(),
                forces: self.forces.as_mut_slice(),
                phi: self.phi.as_mut_slice(),
                phi_q: self.phi_q.as_mut_slice(),
                phi_t: self.phi_t.as_mut_slice(),
                gamma: self.gamma.as_mut_slice(),
                kinetic: &mut self.kinetic,
                potential: &mut self.potential,
            }
        }
    }
}
