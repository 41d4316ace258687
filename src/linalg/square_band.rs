//! A sparse square matrix with its rows and columns reordered into a narrow band, factored
//! by [`BandLu`]: the constraint Jacobian's square block Phi_v of a large chain at assembly,
//! which dense LU would factor in O(n^3).
//!
//! The order: reverse Cuthill-McKee ([`BandOrder`]) on the bipartite graph of the pattern
//! (a node per row, a node per column, an edge per nonzero A_ij), then the rows sorted by
//! their nodes' positions and the columns by theirs. With row i at position r(i) and
//! column j at c(j), the permuted matrix
//!
//! ```text
//! B = P_r A P_c,    B_{r(i) c(j)} = A_ij,    kl = max (r(i) - c(j)),    ku = max (c(j) - r(i))
//! ```
//!
//! over the nonzeros, is solved by A x = b <=> B y = P_r b, x = P_c y. The order given (the
//! identity) is kept when its band is narrower.

use nalgebra::DMatrix;

use super::band_lu::BandLu;
use super::band_order::BandOrder;

/// Why [`SquareBand::factor`] declined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Declined {
    /// No narrow band (or not a square matrix): dense LU serves.
    Wide,
    /// A pivot was zero or not finite: A is singular or has a non-finite entry.
    Singular,
}

/// A x = b through the banded, permuted B (see the module doc).
#[derive(Clone, Debug)]
pub struct SquareBand {
    /// Position of each row of A in B.
    row_at: Vec<usize>,
    /// Position of each column of A in B.
    column_at: Vec<usize>,
    /// (kl, ku) of B.
    #[cfg(test)]
    band: (usize, usize),
    lu: BandLu,
}

impl SquareBand {
    /// The factors of the square `a` in its narrowest band found, when that band is narrow
    /// enough for band LU to cost less than dense LU: `2 kl + ku + 1 <= n / 4` (the band
    /// storage's width, against the n entries of a dense column).
    ///
    /// # Errors
    /// [`Declined::Wide`] when the band is wider or `a` is not square or empty;
    /// [`Declined::Singular`] when a pivot is zero or not finite (A singular or with a NaN
    /// or infinite entry, where [`super::Lu::factor`] fails too).
    pub fn factor(a: &DMatrix<f64>) -> Result<SquareBand, Declined> {
        let n = a.nrows();
        if a.ncols() != n || n == 0 {
            return Err(Declined::Wide);
        }
        let nonzeros: Vec<(usize, usize)> = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .filter(|&(i, j)| a[(i, j)] != 0.0)
            .collect();
        let natural: Vec<usize> = (0..n).collect();
        let (mut row_at, mut column_at) = (natural.clone(), natural);
        let mut band = widths(&nonzeros, &row_at, &column_at);
        let (rows, columns) = bipartite_order(n, &nonzeros);
        let reordered = widths(&nonzeros, &rows, &columns);
        if reordered.0 + reordered.1 < band.0 + band.1 {
            (row_at, column_at, band) = (rows, columns, reordered);
        }
        let (kl, ku) = band;
        if 4 * (2 * kl + ku + 1) > n {
            return Err(Declined::Wide);
        }
        let mut lu = BandLu::new(n, kl + ku);
        lu.reset(n, kl, ku);
        for &(i, j) in &nonzeros {
            let v = a[(i, j)];
            let k = lu.index(row_at[i], column_at[j]);
            lu.set(k, v);
        }
        // Tolerance 0 (so the scale is irrelevant): a pivot fails only when it is exactly
        // zero or not finite, as in dense LU.
        lu.factor_scaled(0.0, 0.0).map_err(|_| Declined::Singular)?;
        Ok(SquareBand {
            row_at,
            column_at,
            #[cfg(test)]
            band,
            lu,
        })
    }

    /// (kl, ku): the sub- and superdiagonals of B.
    #[cfg(test)]
    pub fn band(&self) -> (usize, usize) {
        self.band
    }

    /// Solves A x = b in place (b becomes x); `scratch` has length n.
    pub fn solve(&self, b: &mut [f64], scratch: &mut [f64]) {
        for (i, &r) in self.row_at.iter().enumerate() {
            scratch[r] = b[i];
        }
        self.lu.solve(scratch);
        for (j, &c) in self.column_at.iter().enumerate() {
            b[j] = scratch[c];
        }
    }
}

/// (kl, ku) of the nonzeros (i, j) placed at (row_at[i], column_at[j]).
fn widths(nonzeros: &[(usize, usize)], row_at: &[usize], column_at: &[usize]) -> (usize, usize) {
    nonzeros.iter().fold((0, 0), |(kl, ku), &(i, j)| {
        let (r, c) = (row_at[i], column_at[j]);
        (kl.max(r.saturating_sub(c)), ku.max(c.saturating_sub(r)))
    })
}

/// Row and column positions from the reverse Cuthill-McKee order of the bipartite graph
/// (rows are nodes 0..n, columns n..2n): each side sorted by its nodes' positions.
fn bipartite_order(n: usize, nonzeros: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>) {
    let edges: Vec<(usize, usize)> = nonzeros.iter().map(|&(i, j)| (i, n + j)).collect();
    let order = BandOrder::new(2 * n, &edges);
    let side = |offset: usize| {
        let mut nodes: Vec<usize> = (0..n).collect();
        nodes.sort_by_key(|&u| order.position(offset + u));
        let mut at = vec![0; n];
        for (p, &u) in nodes.iter().enumerate() {
            at[u] = p;
        }
        at
    };
    (side(0), side(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Lu;

    /// A chain-like square matrix (each row couples a few neighbouring unknowns, like a
    /// closed chain's loop rows) with its rows and columns scrambled by two permutations.
    fn scrambled_chain(n: usize) -> DMatrix<f64> {
        let row = |i: usize| (i * 37 + 11) % n;
        let column = |j: usize| (j * 53 + 5) % n;
        let mut a = DMatrix::zeros(n, n);
        for i in 0..n {
            a[(row(i), column(i))] = 3.0 + (i as f64 * 0.7).sin();
            if i + 1 < n {
                a[(row(i), column(i + 1))] = -1.0 + 0.1 * (i % 3) as f64;
            }
            if i >= 2 {
                a[(row(i), column(i - 2))] = 0.5;
            }
        }
        a
    }

    /// The scrambled chain is factored in a band of a few diagonals (the order recovers
    /// the chain); its solution agrees with dense LU's to round-off.
    #[test]
    fn a_scrambled_chain_is_solved_in_a_narrow_band() {
        let n = 97; // prime to both multipliers: the maps are permutations
        let a = scrambled_chain(n);
        let band = SquareBand::factor(&a).expect("narrow band");
        let (kl, ku) = band.band();
        assert!(kl + ku <= 4, "band ({kl}, {ku})");
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.31).cos()).collect();
        let (mut x, mut scratch) = (b.clone(), vec![0.0; n]);
        band.solve(&mut x, &mut scratch);
        let mut lu = Lu::new(n);
        lu.matrix_mut().copy_from(&a);
        assert!(lu.factor());
        let mut y = b.clone();
        lu.solve(&mut y);
        for (u, v) in x.iter().zip(&y) {
            assert!((u - v).abs() <= 1e-14 * (1.0 + v.abs()), "{u} vs {v}");
        }
    }

    /// Declined: a dense matrix (its band is the whole matrix), a rectangular one, and a
    /// singular or non-finite banded one.
    #[test]
    fn declines_wide_rectangular_singular_and_non_finite_matrices() {
        let dense = DMatrix::from_fn(40, 40, |i, j| 1.0 / (1.0 + i as f64 + j as f64));
        assert_eq!(SquareBand::factor(&dense).err(), Some(Declined::Wide));
        let wide = SquareBand::factor(&DMatrix::zeros(40, 39));
        assert_eq!(wide.err(), Some(Declined::Wide));
        let mut singular = scrambled_chain(97);
        let r = (5 * 37 + 11) % 97; // row 5 of the chain, emptied
        singular.row_mut(r).fill(0.0);
        assert_eq!(
            SquareBand::factor(&singular).err(),
            Some(Declined::Singular)
        );
        let mut nan = scrambled_chain(97);
        nan[(r, (5 * 53 + 5) % 97)] = f64::NAN;
        assert_eq!(SquareBand::factor(&nan).err(), Some(Declined::Singular));
    }
}
