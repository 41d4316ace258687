//! LU of a sequence of square matrices of one sparsity pattern (an implicit integrator's
//! Newton matrices, given dense), inside the band of a reverse Cuthill-McKee order of that
//! pattern: O(n b^2) per factorisation where dense LU is O(n^3), and O(n b) per solve.
//!
//! The pattern is seeded with the entries known to be structurally nonzero and widened
//! whenever a matrix has a nonzero outside the band: the order is then recomputed, the only
//! allocation after [`LearntBand::new`]. Every entry of each matrix factored lies inside the
//! band, so the factors are those of the matrix itself, whatever the seed. The same
//! symmetric permutation P orders rows and columns:
//!
//! ```text
//! B = P A P^T,    A x = b  <=>  B (P x) = P b
//! ```

use nalgebra::DMatrix;

use super::band_lu::{BandLu, SingularPivot};
use super::band_order::BandOrder;

/// The band, its order and the factors of the last matrix factored in it.
#[derive(Clone, Debug)]
pub struct LearntBand {
    n: usize,
    /// The pattern so far, as edges (i, j) of the graph on the n rows and columns.
    edges: Vec<(usize, usize)>,
    /// Position of each row and column in the band order, and the node at each position.
    position: Vec<usize>,
    node: Vec<usize>,
    /// max |position(i) - position(j)| over the pattern's edges.
    band: usize,
    lu: BandLu,
    scratch: Vec<f64>,
}

impl LearntBand {
    /// The band of the reverse Cuthill-McKee order of the pattern `seed` (entries (i, j) of
    /// n x n matrices that can be nonzero; either triangle, repeats allowed).
    pub fn new(n: usize, seed: Vec<(usize, usize)>) -> Self {
        let mut this = Self {
            n,
            edges: seed,
            position: vec![0; n],
            node: vec![0; n],
            band: 0,
            lu: BandLu::new(0, 0),
            scratch: vec![0.0; n],
        };
        this.reorder();
        this
    }

    /// Whether band LU costs less than dense LU: the band storage's width, 3 b + 1, at most a
    /// quarter of the order.
    pub fn is_narrow(&self) -> bool {
        4 * (3 * self.band + 1) <= self.n
    }

    /// Factors the n x n matrix `a` in the band, first widening the band to any nonzero of
    /// `a` outside it. `Ok(false)` when the band is (or has become) too wide to pay
    /// ([`LearntBand::is_narrow`]): the caller factors `a` densely.
    ///
    /// # Errors
    /// [`SingularPivot`] when a pivot is exactly zero or not finite (as dense LU with
    /// partial pivoting fails on `a`).
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<bool, SingularPivot> {
        let n = self.n;
        let before = self.edges.len();
        for j in 0..n {
            let pj = self.position[j];
            for (i, &v) in a.column(j).iter().enumerate() {
                if v != 0.0 && self.position[i].abs_diff(pj) > self.band {
                    self.edges.push((i, j));
                }
            }
        }
        if self.edges.len() > before {
            self.reorder();
        }
        if !self.is_narrow() {
            return Ok(false);
        }
        let b = self.band;
        self.lu.reset(n, b, b);
        for c in 0..n {
            let j = self.node[c];
            for r in c.saturating_sub(b)..(c + b + 1).min(n) {
                let v = a[(self.node[r], j)];
                let k = self.lu.index(r, c);
                self.lu.set(k, v);
            }
        }
        // Tolerance 0 (so the scale is irrelevant): a pivot fails only when it is exactly
        // zero or not finite, as in dense LU.
        self.lu.factor_scaled(0.0, 0.0)?;
        Ok(true)
    }

    /// Solves A x = b in place after a successful [`LearntBand::factor`] that returned true.
    pub fn solve(&mut self, b: &mut [f64]) {
        for (i, &p) in self.position.iter().enumerate() {
            self.scratch[p] = b[i];
        }
        self.lu.solve(&mut self.scratch);
        for (i, &p) in self.position.iter().enumerate() {
            b[i] = self.scratch[p];
        }
    }

    /// The reverse Cuthill-McKee order of the pattern, its band, and band storage for it
    /// (allocates).
    fn reorder(&mut self) {
        let order = BandOrder::new(self.n, &self.edges);
        for u in 0..self.n {
            let p = order.position(u).unwrap_or(u);
            self.position[u] = p;
            self.node[p] = u;
        }
        self.band = order.full_band();
        if self.is_narrow() {
            self.lu = BandLu::new(self.n, 2 * self.band);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Lu;

    /// A KKT-like matrix of a scrambled chain: diagonal blocks coupled to their neighbours
    /// and a zero diagonal on the constraint half (pivoting needed), its rows and columns
    /// numbered in a scrambled order.
    fn chain_kkt(n: usize, extra: Option<(usize, usize)>) -> DMatrix<f64> {
        let label = |i: usize| (i * 41 + 3) % n;
        let mut a = DMatrix::zeros(n, n);
        for i in 0..n {
            let d = if i % 2 == 0 {
                2.0 + (i as f64 * 0.1).sin()
            } else {
                0.0
            };
            a[(label(i), label(i))] = d;
            if i + 1 < n {
                let v = 1.0 + 0.1 * (i % 5) as f64;
                a[(label(i), label(i + 1))] = v;
                a[(label(i + 1), label(i))] = v;
            }
        }
        if let Some((i, j)) = extra {
            a[(label(i), label(j))] = 0.5;
            a[(label(j), label(i))] = 0.5;
        }
        a
    }

    fn dense_solve(a: &DMatrix<f64>, b: &[f64]) -> Vec<f64> {
        let mut lu = Lu::new(a.nrows());
        lu.matrix_mut().copy_from(a);
        assert!(lu.factor());
        let mut x = b.to_vec();
        lu.solve(&mut x);
        x
    }

    /// Learnt from nothing, the band of a scrambled chain is its own (1), and the solution
    /// is dense LU's; an entry far outside the band widens it and is then factored too.
    #[test]
    fn learns_the_pattern_and_solves_as_dense_lu() {
        let n = 101; // prime to 41: the labels are a permutation
        let mut band = LearntBand::new(n, Vec::new());
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.23).cos()).collect();
        for (a, width) in [(chain_kkt(n, None), 1), (chain_kkt(n, Some((10, 14))), 4)] {
            assert_eq!(band.factor(&a), Ok(true));
            assert!(band.band <= width, "band {} > {width}", band.band);
            let mut x = b.clone();
            band.solve(&mut x);
            for (u, v) in x.iter().zip(dense_solve(&a, &b)) {
                assert!((u - v).abs() <= 1e-13 * (1.0 + v.abs()), "{u} vs {v}");
            }
        }
    }

    /// A dense matrix makes the band too wide (the caller factors densely); a singular
    /// chain fails at a pivot.
    #[test]
    fn a_dense_matrix_is_declined_and_a_singular_one_fails() {
        let n = 41;
        let dense = DMatrix::from_fn(n, n, |i, j| 1.0 / (1.0 + i as f64 + j as f64));
        assert_eq!(LearntBand::new(n, Vec::new()).factor(&dense), Ok(false));
        let mut singular = chain_kkt(101, None);
        singular.column_mut(7).fill(0.0);
        singular.row_mut(7).fill(0.0);
        let mut band = LearntBand::new(101, Vec::new());
        assert!(band.factor(&singular).is_err());
    }
}
