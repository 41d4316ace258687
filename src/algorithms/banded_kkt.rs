//! The augmented (KKT) system of constrained dynamics solved directly inside a band: the
//! route of large chains (A02's N four-bar), O(n + m) per solve for a bounded band, no
//! iteration.
//!
//! ```text
//! [ M    A_R^T ] [ x        ]   [ Q         ]        A = Phi_q, Q = tau - C q' - g,
//! [ A_R  0     ] [ lambda_R ] = [ (P gamma)_R ]      P gamma = A w, w = argmin |A w - gamma|
//! ```
//!
//! 1. **Rank.** [`RowBasis`] finds the independent rows R of A (the Gram matrix A A^T
//!    factored inside its envelope, O(m) for a chain); the others (redundant rows, or the
//!    rows a singular position makes dependent: A02's N rocker rows when the rockers lie
//!    flat) are left out, their multipliers zero.
//! 2. **Consistent gamma.** With rows left out, gamma may have a part outside range(A)
//!    (round-off, velocity error, or the instant of a singular position). It is replaced by
//!    its orthogonal projection P gamma onto range(A), as the augmented Lagrangian route
//!    does, but computed on the side of the coordinates: the least-squares w from the
//!    normal equations A^T A w = A^T gamma, A^T A (n x n, banded like M) factored inside its
//!    envelope with its dependent columns left out (semidefinite Cholesky), then P gamma =
//!    A w. O(n) for a chain, where the m x m forms over the null space of A^T cost
//!    O(nullity^3) (A02 flat: N^3).
//! 3. **Band.** The coordinates and the kept rows are ordered by reverse Cuthill-McKee
//!    ([`BandOrder`], fixed once from the structural pattern of M and Phi_q; leaving rows
//!    out never widens its band b), and the matrix above is factored by LU with partial
//!    pivoting inside the band ([`BandLu`]): about 4 (n + r) b^2 flops, backward stable for
//!    this indefinite matrix (its diagonal is zero on the rows), M singular allowed as long
//!    as it is positive definite on the null space of A_R.
//!
//! x = q'' is then exact to the conditioning of the matrix (no penalty, no iteration). lambda
//! solves the system with the rows kept (zero on the others), and with rows left out it is then
//! projected onto range(A) by the same normal equations: the minimum-norm multipliers with the
//! same forces A^T lambda, O(n) too. A pivot below [`PIVOT_TOLERANCE`] times the largest entry
//! (M singular on an allowed motion, or a configuration so close to singular that R still holds
//! a nearly dependent row) fails the solve: the caller falls back to the augmented Lagrangian
//! route, which diagnoses or regularises it.

use nalgebra::DMatrix;

use crate::linalg::{BandLu, BandOrder, Envelope, RowBasis, RowSpans};

/// Relative pivot below which the banded LU declines (about 450 eps: a pivot this small
/// carries no correct digit after the elimination's round-off).
pub const PIVOT_TOLERANCE: f64 = 1e-13;

/// The widest band b this route factors for a matrix of order k: b^2 <= k, so that the
/// LU's 4 k b^2 flops stay below 4 k^2 (the dense LU's k^3 / 3 is larger still from k = 12
/// on).
pub fn widest(k: usize) -> usize {
    k.isqrt()
}

/// The place of a structural nonzero whose row is left out of the order.
const OUT: usize = usize::MAX;

/// Why [`BandedKkt::solve`] declined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Declined {
    /// The coordinates and the rows kept do not order into a band of at most [`widest`].
    TooWide,
    /// The banded LU met a pivot at round-off.
    SingularPivot,
    /// An entry of M or Phi_q is NaN or infinite.
    NonFinite,
}

/// Workspace of the banded direct solve; allocates nothing after [`BandedKkt::new`].
#[derive(Clone, Debug)]
pub struct BandedKkt {
    n: usize,
    mass_pattern: Vec<(usize, usize)>,
    jacobian_pattern: Vec<(usize, usize)>,
    order: BandOrder,
    /// Where each entry of `mass_pattern` and `jacobian_pattern` (and its transpose) goes
    /// in the band storage of the current order ([`OUT`]: not in it), and whether these
    /// places are those of the current order.
    mass_places: Vec<usize>,
    jacobian_places: Vec<(usize, usize)>,
    placed: bool,
    /// The rows left out of the current order.
    dropped: Vec<bool>,
    lu: BandLu,
    basis: RowBasis,
    spans: RowSpans,
    /// A^T A and the columns its semidefinite factor leaves out.
    normal: Envelope,
    dropped_columns: Vec<bool>,
    ratio: Vec<f64>,
    consistent: Vec<f64>,
    w: Vec<f64>,
    dw: Vec<f64>,
    rhs: Vec<f64>,
    x: Vec<f64>,
    lambda: Vec<f64>,
    /// Solves that left rows out (rank below m).
    pub rank_deficient_solves: usize,
    /// Multiply-adds of the rank factorisations (the rank basis's own count) of all solves.
    pub factor_work: u64,
}

impl BandedKkt {
    /// Workspace for n coordinates and m rows whose M and Phi_q are nonzero only at `mass`
    /// and `jacobian` ((row, column) pairs). Allocates (once).
    ///
    /// The rank basis works with its spans in the coordinate order `coordinates` (the
    /// mechanism's `Sparsity::order`, the coordinate at each position; empty for the
    /// declaration's): its factor costs the rows' overlaps in that order.
    pub fn new(
        n: usize,
        m: usize,
        mass: &[(usize, usize)],
        jacobian: &[(usize, usize)],
        coordinates: &[usize],
    ) -> Self {
        let edges: Vec<(usize, usize)> = mass
            .iter()
            .copied()
            .chain(jacobian.iter().map(|&(r, j)| (n + r, j)))
            .collect();
        // Coordinates ranked by their position in `coordinates`, rows after them: the order
        // of the KKT matrix then follows the coordinates' order, not their numbers.
        let mut rank: Vec<usize> = (0..n + m).collect();
        for (p, &j) in coordinates.iter().enumerate() {
            rank[j] = p;
        }
        let order = BandOrder::ranked(n + m, &edges, &rank);
        let band = order.full_band().min(widest(n + m));
        let mut spans = RowSpans::new(m, n);
        spans.fix(jacobian);
        let mut basis = RowBasis::new(m, n);
        if coordinates.is_empty() {
            basis.fix(jacobian);
        } else {
            basis.fix_ordered(jacobian, coordinates);
        }
        let normal = Envelope::with_profile(&spans.normal_profile((0..n).collect()));
        Self {
            n,
            mass_places: vec![OUT; mass.len()],
            jacobian_places: vec![(OUT, OUT); jacobian.len()],
            placed: false,
            mass_pattern: mass.to_vec(),
            jacobian_pattern: jacobian.to_vec(),
            order,
            dropped: vec![false; m],
            lu: BandLu::new(n + m, 2 * band),
            basis,
            spans,
            normal,
            dropped_columns: vec![false; n],
            ratio: vec![0.0; n],
            consistent: vec![0.0; m],
            w: vec![0.0; n],
            dw: vec![0.0; n],
            rhs: vec![0.0; n + m],
            x: vec![0.0; n],
            lambda: vec![0.0; m],
            rank_deficient_solves: 0,
            factor_work: 0,
        }
    }

    /// Band b of the order of all coordinates and rows.
    pub fn band(&self) -> usize {
        self.order.full_band()
    }

    /// Whether the order of all coordinates and rows is narrow: b <= [`widest`]. When it
    /// is not, a solve may still take this route if the rows it keeps are (a redundant
    /// set: 1,000 copies of one row keep one).
    pub fn is_banded(&self) -> bool {
        self.band() <= widest(self.rhs.len())
    }

    /// Solves the system of the module docs. `mass` (n x n) and `a` (m x n) are nonzero at
    /// most on the patterns of [`BandedKkt::new`]; `q` has n entries, `gamma` m.
    ///
    /// Declines (nothing solved) when the rows kept do not order into a narrow band, when
    /// an entry of M or Phi_q is not finite, or when the banded LU meets a pivot below
    /// [`PIVOT_TOLERANCE`] times the matrix's largest entry. Every entry of both patterns
    /// has been read for finiteness unless it declined as [`Declined::TooWide`].
    pub fn solve(
        &mut self,
        mass: &DMatrix<f64>,
        a: &DMatrix<f64>,
        q: &[f64],
        gamma: &[f64],
    ) -> Result<(), Declined> {
        let (n, m) = (self.n, self.dropped.len());
        let rank = self.basis.factor(a);
        self.factor_work += self.basis.work();
        self.consistent.copy_from_slice(gamma);
        if rank < m {
            self.rank_deficient_solves += 1;
            self.factor_normal(a);
            project(
                &self.spans,
                &self.normal,
                &self.dropped_columns,
                a,
                gamma,
                (&mut self.w, &mut self.dw),
                &mut self.consistent,
            );
        }
        if !self.placed || (0..m).any(|r| self.basis.is_redundant(r) != self.dropped[r]) {
            for r in 0..m {
                self.dropped[r] = self.basis.is_redundant(r);
            }
            let dropped = &self.dropped;
            self.order.restrict(|u| u < n || !dropped[u - n]);
            self.placed = false;
        }
        let (size, band) = (self.order.size(), self.order.band());
        if band > widest(n + m) || !self.lu.reset(size, band, band) {
            return Err(Declined::TooWide);
        }
        if !self.placed {
            self.place();
        }
        let scale = self.fill(mass, a)?;
        self.lu
            .factor_scaled(PIVOT_TOLERANCE, scale)
            .map_err(|_| Declined::SingularPivot)?;
        self.solve_factored(q, size);
        if rank < m {
            // The multipliers on the rows kept, zero elsewhere, give the forces A^T lambda;
            // the minimum-norm ones with the same forces are their projection onto
            // range(A) (the null space of A^T is what the forces leave undetermined).
            self.consistent.copy_from_slice(&self.lambda);
            project(
                &self.spans,
                &self.normal,
                &self.dropped_columns,
                a,
                &self.consistent,
                (&mut self.w, &mut self.dw),
                &mut self.lambda,
            );
        }
        Ok(())
    }

    /// Each structural nonzero of M and Phi_q into its place in the band (fixed while the
    /// rows kept stay the same); returns the matrix's largest |entry| (each place is
    /// written once). Every structural nonzero is read, those of the rows left out too, so
    /// that this pass also tells whether M and Phi_q are finite (the caller reads them no
    /// other time).
    fn fill(&mut self, mass: &DMatrix<f64>, a: &DMatrix<f64>) -> Result<f64, Declined> {
        let (n, m) = (self.n, self.dropped.len());
        let (mass_values, a_values) = (mass.as_slice(), a.as_slice());
        let (mut scale, mut finite) = (0.0f64, true);
        for (&(i, j), &k) in self.mass_pattern.iter().zip(&self.mass_places) {
            let v = mass_values[i + j * n];
            finite &= v.is_finite();
            if k != OUT {
                self.lu.set(k, v);
                scale = scale.max(v.abs());
            }
        }
        for (&(r, j), &(k, kt)) in self.jacobian_pattern.iter().zip(&self.jacobian_places) {
            let v = a_values[r + j * m];
            finite &= v.is_finite();
            if k != OUT {
                self.lu.set(k, v);
                self.lu.set(kt, v);
                scale = scale.max(v.abs());
            }
        }
        if finite {
            Ok(scale)
        } else {
            Err(Declined::NonFinite)
        }
    }

    /// [q; gamma consistent] through the factored band (`size` unknowns in the current
    /// order) into the accelerations and the multipliers on the rows kept (zero on the
    /// rows left out).
    fn solve_factored(&mut self, q: &[f64], size: usize) {
        let n = self.n;
        let rhs = &mut self.rhs[..size];
        for (i, &qi) in q.iter().enumerate() {
            if let Some(p) = self.order.position(i) {
                rhs[p] = qi;
            }
        }
        for (r, &g) in self.consistent.iter().enumerate() {
            if let Some(p) = self.order.position(n + r) {
                rhs[p] = g;
            }
        }
        self.lu.solve(rhs);
        for (i, x) in self.x.iter_mut().enumerate() {
            *x = self.order.position(i).map_or(0.0, |p| self.rhs[p]);
        }
        for (r, l) in self.lambda.iter_mut().enumerate() {
            *l = self.order.position(n + r).map_or(0.0, |p| self.rhs[p]);
        }
    }

    /// The storage index in the band of every structural nonzero of M and Phi_q (and of
    /// Phi_q^T) in the current order, [`OUT`] for those of the rows left out.
    fn place(&mut self) {
        let n = self.n;
        let (order, lu) = (&self.order, &self.lu);
        for (&(i, j), k) in self.mass_pattern.iter().zip(&mut self.mass_places) {
            *k = match (order.position(i), order.position(j)) {
                (Some(pi), Some(pj)) => lu.index(pi, pj),
                _ => OUT,
            };
        }
        for (&(r, j), k) in self.jacobian_pattern.iter().zip(&mut self.jacobian_places) {
            *k = match (order.position(n + r), order.position(j)) {
                (Some(pr), Some(pj)) => (lu.index(pr, pj), lu.index(pj, pr)),
                _ => (OUT, OUT),
            };
        }
        self.placed = true;
    }

    /// Factors A^T A (n x n, inside its envelope) with its dependent columns left out.
    fn factor_normal(&mut self, a: &DMatrix<f64>) {
        self.normal.clear();
        self.spans.add_gram_transpose(a, 1.0, &mut self.normal);
        let tol2 = self.basis.tolerance * self.basis.tolerance;
        self.normal
            .factor_semidefinite(tol2, &mut self.dropped_columns, &mut self.ratio);
    }

    /// x (q'') of the last solve.
    pub fn solution(&self) -> &[f64] {
        &self.x
    }

    /// lambda of the last solve: the minimum-norm multipliers (unique at full rank).
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }
}

/// `out` = P v = A w, the orthogonal projection of v onto range(A): w the least-squares
/// solution of A w = v from the normal equations A^T A w = A^T v, `normal` holding the
/// semidefinite factor of A^T A with the columns in `dropped` left out (w is zero there),
/// then one correction from the residual, w += (A^T A)^-1 A^T (v - A w) (Björck's
/// corrected seminormal equations: the normal equations alone lose cond(A)^2 eps, the
/// correction brings the error near cond(A) eps). O(m + n b) for a band b; `dw` is
/// workspace of n entries.
fn project(
    spans: &RowSpans,
    normal: &Envelope,
    dropped: &[bool],
    a: &DMatrix<f64>,
    v: &[f64],
    (w, dw): (&mut [f64], &mut [f64]),
    out: &mut [f64],
) {
    spans.mul_transpose(a, v, w);
    normal.solve_skipping(dropped, w);
    spans.mul(a, w, out);
    for (o, v) in out.iter_mut().zip(v) {
        *o = v - *o;
    }
    spans.mul_transpose(a, out, dw);
    normal.solve_skipping(dropped, dw);
    for (w, d) in w.iter_mut().zip(dw.iter()) {
        *w += d;
    }
    spans.mul(a, w, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The structural pattern of A02 with `loops` couplers: M couples each tip coordinate
    /// with the same coordinate of its neighbours, rocker row i reads tip i, coupler row i
    /// tips i and i + 1 (coordinates x_i = 2 i, y_i = 2 i + 1; rows alternate).
    /// (row, column) pairs.
    type Pattern = Vec<(usize, usize)>;

    fn a02_pattern(loops: usize) -> (usize, usize, Pattern, Pattern) {
        let (n, m) = (2 * (loops + 1), 2 * loops + 1);
        let mut mass = Vec::new();
        for i in 0..n {
            mass.push((i, i));
            if i + 2 < n {
                mass.extend([(i, i + 2), (i + 2, i)]);
            }
        }
        let mut jacobian = Vec::new();
        for tip in 0..=loops {
            jacobian.extend([(2 * tip, 2 * tip), (2 * tip, 2 * tip + 1)]);
            if tip < loops {
                jacobian.extend((2 * tip..2 * tip + 4).map(|j| (2 * tip + 1, j)));
            }
        }
        (n, m, mass, jacobian)
    }

    #[test]
    fn a02_orders_into_a_band_independent_of_its_length() {
        let bands: Vec<usize> = [10, 40, 640]
            .into_iter()
            .map(|loops| {
                let (n, m, mass, jacobian) = a02_pattern(loops);
                let kkt = BandedKkt::new(n, m, &mass, &jacobian, &[]);
                assert!(kkt.is_banded(), "N {loops}: band {}", kkt.band());
                kkt.band()
            })
            .collect();
        println!("A02 band of the reverse Cuthill-McKee order, N = 10, 40, 640: {bands:?}");
        assert!(bands.iter().all(|&b| b == bands[0]), "{bands:?}");
    }
}
