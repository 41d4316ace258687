//! Forward dynamics as straight-line expressions: q'' = M^-1 (u - b) for an effort u along
//! the coordinates and the bias b = C q' + g - tau, by the factorisation M = L^T D L whose
//! fill-in follows the tree (Featherstone's LTDL, "Rigid Body Dynamics Algorithms", 2008,
//! section 6.5, tables 6.3 and 6.4), written out over M's structural pattern.
//!
//! The coordinates are taken in an order where a link's coordinate comes after its
//! parent's (the links' declaration order; for a model without links, the declared order).
//! Eliminating from the last coordinate to the first, coordinate k's lower neighbours (the
//! j < k with M_kj not identically 0, and the fill-in that eliminating the later ones
//! brought) all lie on the chain of its elimination parent lambda(k), the largest of them:
//! for a tree of links that chain is k's ancestors, and a branch never fills another.
//! Then, for k = n..1 and each i on k's chain, a = H_ki / H_kk and H_ij -= a H_kj for the
//! j on i's chain from i down; H_ki = a. D = diag(H) (the pivots), L the unit lower
//! triangle of H below it. The solve: z = L^-T (u - b) (for i = n..1, z_j -= L_ij z_i along
//! i's chain), z_i /= D_ii, q'' = L^-1 z (for i = 1..n, q''_i -= L_ij q''_j along i's
//! chain). Every entry is named once ([`crate::Node::Named`]).
//!
//! M is positive definite exactly when every pivot D_kk is: the pivots are an output, and
//! the caller refuses q'' (it is then not finite, or meaningless) when one is not > 0.

use crate::algebra::expr::{Arena, Id};
use crate::algebra::matrix::Matrix;
use crate::error::Result;

/// q'' (n x 1, by coordinate) and the pivots D (n x 1, in elimination order).
pub(crate) struct ForwardDynamics {
    pub(crate) accelerations: Matrix,
    pub(crate) pivots: Matrix,
}

/// The elimination parent of each position of the pattern `lower` (for position k, the
/// positions j < k with H_kj not identically 0): the largest lower neighbour once the
/// fill-in of the later positions is added, `None` for a root.
fn elimination_parents(lower: &[Vec<usize>]) -> Vec<Option<usize>> {
    let n = lower.len();
    let mut sets: Vec<Vec<usize>> = lower.to_vec();
    let mut parent = vec![None; n];
    for k in (0..n).rev() {
        let mut s = std::mem::take(&mut sets[k]);
        s.sort_unstable();
        s.dedup();
        if let Some(&p) = s.last() {
            parent[k] = Some(p);
            // Eliminating k connects its other lower neighbours to p.
            sets[p].extend(s.iter().copied().filter(|&j| j != p));
        }
    }
    parent
}

/// M = L^T D L over M's pattern (module docs), in elimination order: what a solve with M
/// and M^-1 read.
pub(crate) struct Factor {
    /// Coordinate of each position.
    order: Vec<usize>,
    /// Elimination parent of each position (`None` for a root).
    parent: Vec<Option<usize>>,
    /// Row k: L_kj for j on k's chain below k (0 elsewhere below), D_kk at j = k.
    h: Vec<Vec<Id>>,
    /// 1/D_kk, or 0 where D_kk is identically 0.
    inverse: Vec<Id>,
}

impl Factor {
    /// The factorisation of `mass` with the coordinates taken in `order` (a permutation of
    /// 0..n, parents before children).
    pub(crate) fn new(a: &mut Arena, mass: &Matrix, order: &[usize]) -> Result<Factor> {
        let n = order.len();
        // H in elimination order, lower triangle (row >= column).
        let mut h: Vec<Vec<Id>> = (0..n)
            .map(|k| (0..=k).map(|j| mass.get(order[k], order[j])).collect())
            .collect();
        let lower: Vec<Vec<usize>> = (0..n)
            .map(|k| (0..k).filter(|&j| !a.is_zero(h[k][j])).collect())
            .collect();
        let parent = elimination_parents(&lower);
        let mut factor = Factor {
            order: order.to_vec(),
            parent,
            h: Vec::new(),
            inverse: vec![a.int(0); n],
        };
        // 1/D_kk, or 0 where D_kk is identically 0 (M singular at every q: the pivot, an
        // output, makes the caller refuse q'').
        for k in (0..n).rev() {
            if !a.is_zero(h[k][k]) {
                factor.inverse[k] = a.powi(h[k][k], -1)?;
            }
            let inverse = factor.inverse[k];
            for i in factor.chain(factor.parent[k]) {
                let hki = a.mul2(h[k][i], inverse);
                let l = a.named(hki);
                for j in factor.chain(Some(i)) {
                    let t = a.mul2(l, h[k][j]);
                    let d = a.sub(h[i][j], t);
                    h[i][j] = a.named(d);
                }
                h[k][i] = l;
            }
        }
        factor.h = h;
        Ok(factor)
    }

    /// The positions from `i` down its elimination chain (empty for `None`).
    fn chain(&self, mut i: Option<usize>) -> Vec<usize> {
        let mut out = Vec::new();
        while let Some(x) = i {
            out.push(x);
            i = self.parent[x];
        }
        out
    }

    /// The pivots D_kk, in elimination order.
    pub(crate) fn pivots(&self) -> Matrix {
        Matrix::column((0..self.order.len()).map(|k| self.h[k][k]).collect())
    }

    /// The multiplications of one [`Factor::solve`]: two per entry of L below the diagonal
    /// (one per sweep), one per pivot.
    pub(crate) fn solve_multiplications(&self) -> usize {
        let below: usize = (0..self.order.len())
            .map(|k| self.chain(self.parent[k]).len())
            .sum();
        2 * below + self.order.len()
    }

    /// M^-1 x for `x` in elimination order (the result too), by the sweeps of the module
    /// docs; -M^-1 x with `negate` (the sign taken at the pivots' scaling, which costs no
    /// operation there).
    pub(crate) fn solve(&self, a: &mut Arena, mut x: Vec<Id>, negate: bool) -> Vec<Id> {
        let n = x.len();
        for i in (0..n).rev() {
            for j in self.chain(self.parent[i]) {
                let t = a.mul2(self.h[i][j], x[i]);
                let d = a.sub(x[j], t);
                x[j] = a.named(d);
            }
        }
        // Made only when asked: a new node here would renumber the q'' program's.
        let minus_one = negate.then(|| a.int(-1));
        for (xi, &inverse) in x.iter_mut().zip(&self.inverse) {
            *xi = match minus_one {
                Some(m) => a.mul(&[m, *xi, inverse]),
                None => a.mul2(*xi, inverse),
            };
        }
        for i in 0..n {
            let mut terms = vec![x[i]];
            for j in self.chain(self.parent[i]) {
                let t = a.mul2(self.h[i][j], x[j]);
                terms.push(a.neg(t));
            }
            let s = a.add(&terms);
            x[i] = a.named(s);
        }
        x
    }

    /// 1/D (in elimination order; 0 where D is identically 0).
    pub(crate) fn inverse_pivots(&self) -> &[Id] {
        &self.inverse
    }

    /// w = L^-T r for `r` by coordinate, w in elimination order: for i = n..1,
    /// w_j -= L_ij w_i along i's chain. A right-hand side that is zero outside a few
    /// coordinates (a constraint row) fills only their chains.
    pub(crate) fn upward(&self, a: &mut Arena, r: &[Id]) -> Vec<Id> {
        let mut x: Vec<Id> = self.order.iter().map(|&c| r[c]).collect();
        for i in (0..x.len()).rev() {
            if a.is_zero(x[i]) {
                continue;
            }
            for j in self.chain(self.parent[i]) {
                let t = a.mul2(self.h[i][j], x[i]);
                let d = a.sub(x[j], t);
                x[j] = a.named(d);
            }
        }
        x
    }

    /// x = L^-1 D^-1 w for `w` in elimination order, x by coordinate: w_i /= D_ii, then for
    /// i = 1..n, x_i -= L_ij x_j along i's chain.
    pub(crate) fn downward(&self, a: &mut Arena, w: &[Id]) -> Vec<Id> {
        let mut x: Vec<Id> = w
            .iter()
            .zip(&self.inverse)
            .map(|(&w, &inverse)| a.mul2(w, inverse))
            .collect();
        for i in 0..x.len() {
            let mut terms = vec![x[i]];
            for j in self.chain(self.parent[i]) {
                let t = a.mul2(self.h[i][j], x[j]);
                terms.push(a.neg(t));
            }
            let s = a.add(&terms);
            x[i] = a.named(s);
        }
        let mut out = vec![a.int(0); x.len()];
        for (k, &c) in self.order.iter().enumerate() {
            out[c] = x[k];
        }
        out
    }

    /// M^-1 (n x n, by coordinate), its lower triangle in elimination order from
    /// L M^-1 = D^-1 L^-T: for i >= j, (M^-1)_ij = [i = j] / D_ii - sum_k L_ik (M^-1)_kj
    /// over k on i's chain, where (M^-1)_kj for k < j is the entry (j, k) found before
    /// (M^-1 is symmetric); the upper triangle mirrored. Entries where i's and j's chains
    /// never meet are 0 (no operation): M^-1 of a forest is block diagonal as M is.
    #[allow(clippy::needless_range_loop)] // (i, j) index two triangles, read both ways.
    pub(crate) fn inverse(&self, a: &mut Arena) -> Matrix {
        let n = self.order.len();
        let mut lower: Vec<Vec<Id>> = (0..n).map(|i| vec![a.int(0); i + 1]).collect();
        for j in 0..n {
            for i in j..n {
                let mut terms = Vec::new();
                if i == j {
                    terms.push(self.inverse[i]);
                }
                for k in self.chain(self.parent[i]) {
                    let x = if k >= j { lower[k][j] } else { lower[j][k] };
                    let t = a.mul2(self.h[i][k], x);
                    terms.push(a.neg(t));
                }
                let s = a.add(&terms);
                lower[i][j] = a.named(s);
            }
        }
        let mut out = Matrix::zeros(a, n, n);
        for (row, &r) in lower.iter().zip(&self.order) {
            for (&x, &c) in row.iter().zip(&self.order) {
                out.set(r, c, x);
                out.set(c, r, x);
            }
        }
        out
    }
}

/// The updates H_ij -= L_ki H_kj that [`forward_dynamics`] writes for `mass` with the
/// coordinates in `order`, counted without building them over the pattern of M's entries
/// that are not numbers: the sum over k of, for each i on k's elimination chain, the length
/// of i's chain. Each such update multiplies and subtracts entries that are not numbers,
/// at least one operation of the compiled program (fused), so the count bounds the
/// factorisation's cost from below (up to a cancellation to an exact zero); entries that
/// are numbers fold at build time and are left out. On a chain of n links it is about
/// n^3 / 6, which the caller compares with the articulated-body recursion's operations
/// before writing the factorisation out.
pub(crate) fn factorisation_updates(a: &Arena, mass: &Matrix, order: &[usize]) -> usize {
    let n = order.len();
    let lower: Vec<Vec<usize>> = (0..n)
        .map(|k| {
            (0..k)
                .filter(|&j| a.as_number(mass.get(order[k], order[j])).is_none())
                .collect()
        })
        .collect();
    let parent = elimination_parents(&lower);
    // depth[i]: the length of i's chain (i and its elimination ancestors); parents come
    // before children, so one pass from the first position fills it.
    let mut depth = vec![0usize; n];
    for i in 0..n {
        depth[i] = 1 + parent[i].map_or(0, |p| depth[p]);
    }
    // above[i]: the sum of depth over i's chain (i and its elimination ancestors).
    let mut above = vec![0usize; n];
    for i in 0..n {
        above[i] = depth[i] + parent[i].map_or(0, |p| above[p]);
    }
    (0..n).map(|k| parent[k].map_or(0, |p| above[p])).sum()
}

/// q'' = M^-1 (u - b) and the pivots of M = L^T D L (module docs), with the coordinates
/// taken in `order` (a permutation of 0..n, parents before children).
pub(crate) fn forward_dynamics(
    a: &mut Arena,
    mass: &Matrix,
    bias: &Matrix,
    effort: &[Id],
    order: &[usize],
) -> Result<ForwardDynamics> {
    let factor = Factor::new(a, mass, order)?;
    let x: Vec<Id> = order
        .iter()
        .map(|&c| {
            let d = a.sub(effort[c], bias.get(c, 0));
            a.named(d)
        })
        .collect();
    let x = factor.solve(a, x, false);
    let n = order.len();
    let mut accelerations = vec![a.int(0); n];
    for (k, &c) in order.iter().enumerate() {
        accelerations[c] = x[k];
    }
    Ok(ForwardDynamics {
        accelerations: Matrix::column(accelerations),
        pivots: factor.pivots(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tree's pattern has no fill-in: each position's parent is its nearest lower
    /// neighbour, and a branch's positions do not gain the other branch's.
    #[test]
    fn the_elimination_parents_of_a_tree_are_its_parents() {
        // 0 - 1 - 2 and 0 - 3 - 4: lower neighbours are the ancestors.
        let lower = vec![vec![], vec![0], vec![0, 1], vec![0], vec![0, 3]];
        let parent = elimination_parents(&lower);
        assert_eq!(parent, [None, Some(0), Some(1), Some(0), Some(3)]);
        // A pattern with fill: 2's neighbours 0 and 1, 1 not connected to 0 before.
        let lower = vec![vec![], vec![], vec![0, 1]];
        assert_eq!(elimination_parents(&lower), [None, Some(0), Some(1)]);
    }

    /// The counted updates equal those [`forward_dynamics`] performs, counted by hand: a
    /// full 4 x 4 pattern (a chain of four links) eliminates k = 3 over i = 2, 1, 0 with
    /// chains of 3, 2, 1 (6), k = 2 over i = 1, 0 (3), k = 1 over i = 0 (1): 10 = sum of j (j + 1) / 2.
    /// A diagonal pattern has none, nor one whose off-diagonal entries are numbers.
    #[test]
    fn the_counted_updates_follow_the_elimination_chains() {
        let mut a = Arena::new();
        let x = a.symbol("x", crate::algebra::expr::SymbolKind::Free);
        let full = Matrix::from_fn(4, 4, |_, _| x);
        assert_eq!(factorisation_updates(&a, &full, &[0, 1, 2, 3]), 10);
        let zero = a.int(0);
        let diagonal = Matrix::from_fn(4, 4, |i, j| if i == j { x } else { zero });
        assert_eq!(factorisation_updates(&a, &diagonal, &[0, 1, 2, 3]), 0);
        // Entries that are numbers fold when built: no operation, not counted.
        let two = a.int(2);
        let numbers = Matrix::from_fn(4, 4, |i, j| if i == j { x } else { two });
        assert_eq!(factorisation_updates(&a, &numbers, &[0, 1, 2, 3]), 0);
    }
}
