//! The rows of a constraint Jacobian A = Phi_q (m x n): where they are nonzero, and
//! products with A and A^T (and its Gram matrices) that skip the zeros. Which rows are
//! independent is [`super::RowBasis`]'s.

use nalgebra::DMatrix;

use super::envelope::Envelope;

/// Nonzero span [lo_r, hi_r] of every row of a matrix (lo > hi for a zero row), in a
/// column order: positions p = 0..n, column `order[p]` at position p.
///
/// The spans are found by [`RowSpans::scan`] on every matrix (in the columns' own order),
/// or fixed once from the matrix's structural pattern ([`RowSpans::fix`], or
/// [`RowSpans::fix_ordered`] in a fill-reducing order of the columns): then `scan` does
/// nothing and [`RowSpans::gram`] visits only the pairs of rows whose spans overlap, so
/// that neither reads the dense matrix outside the spans (O(m) for a chain instead of
/// O(m n + m^2)). A span is a range of positions: with the columns in declaration order a
/// row whose columns lie far apart spans nearly all of them, and every row overlaps every
/// other; in an order that bands the pattern (`Sparsity::order`) it spans a few.
#[derive(Clone, Debug, Default)]
pub struct RowSpans {
    lo: Vec<usize>,
    hi: Vec<usize>,
    /// The column at each position (identity unless fixed in an order).
    order: Vec<usize>,
    /// Multiply-adds of the last [`RowSpans::gram`].
    pub work: u64,
    /// For each row r, the first row q <= r whose span overlaps its own (r itself for an
    /// empty span): no row before it shares a column with r. 0 for every row before the
    /// first [`RowSpans::scan`] or [`RowSpans::fix`].
    first_overlap: Vec<usize>,
    /// Workspace: for each column, the first row whose span holds it.
    cover: Vec<usize>,
    fixed: bool,
}

impl RowSpans {
    /// Spans for m rows of n columns.
    pub fn new(m: usize, n: usize) -> Self {
        Self {
            lo: vec![0; m],
            hi: vec![0; m],
            order: (0..n).collect(),
            work: 0,
            first_overlap: vec![0; m],
            cover: vec![0; n],
            fixed: false,
        }
    }

    /// Fixes the spans from the structural nonzeros `pattern` ((row, column) pairs; every
    /// row index below m) of all matrices this will see: each row's span covers its
    /// pattern, [`RowSpans::scan`] becomes a no-op and [`RowSpans::gram`] visits only
    /// overlapping pairs. Allocates (once, outside any step loop).
    pub fn fix(&mut self, pattern: &[(usize, usize)]) {
        let columns = pattern.iter().map(|&(_, j)| j + 1).max().unwrap_or(0);
        let n = columns.max(self.order.len());
        let order: Vec<usize> = (0..n).collect();
        self.fix_ordered(pattern, &order);
    }

    /// [`RowSpans::fix`] with the columns in `order` (a permutation of 0..n: the column at
    /// each position; covering every column of `pattern`): each row's span is the range of
    /// the positions of its columns. The products below give the same values in any order
    /// up to round-off (sums taken in another order); the work of [`RowSpans::gram`] and of
    /// a row basis over these spans is the sum of the overlaps, small when `order` bands
    /// the pattern. Allocates (once).
    pub fn fix_ordered(&mut self, pattern: &[(usize, usize)], order: &[usize]) {
        let n = order.len();
        let mut place = vec![usize::MAX; n];
        for (p, &j) in order.iter().enumerate() {
            place[j] = p;
        }
        self.order = order.to_vec();
        self.lo.fill(usize::MAX);
        self.hi.fill(0);
        for &(r, j) in pattern {
            let p = place[j];
            self.lo[r] = self.lo[r].min(p);
            self.hi[r] = self.hi[r].max(p);
        }
        if n > self.cover.len() {
            self.cover.resize(n, 0);
        }
        self.find_overlaps();
        self.fixed = true;
    }

    /// Each row's first overlapping row from the spans. cover[j] is the first row whose
    /// span holds column j; a row q < r overlaps row r exactly when it covers one of r's
    /// columns, and row r covers them all itself, so the first overlapping row is the
    /// least cover over r's span: O(m + the spans' lengths), where listing the overlapping
    /// pairs would cost m^2 for identical rows.
    fn find_overlaps(&mut self) {
        let m = self.lo.len();
        self.cover.fill(usize::MAX);
        for r in 0..m {
            for p in self.positions(r) {
                self.cover[p] = self.cover[p].min(r);
            }
        }
        for r in 0..m {
            let cover = &self.cover;
            self.first_overlap[r] = self.positions(r).map(|p| cover[p]).min().unwrap_or(r);
        }
    }

    /// The storage profile of the Gram matrix A A^T that [`RowSpans::gram`] fills from
    /// fixed spans: for each row r, its first overlapping partner (see
    /// [`Envelope::reserve`]). Only after [`RowSpans::fix`].
    pub fn gram_profile(&self) -> Vec<usize> {
        self.first_overlap.clone()
    }

    /// The first row q <= r whose span overlaps row r's (see [`RowSpans::find_overlaps`]);
    /// 0 before the first scan or fix.
    #[inline]
    pub fn first_overlap(&self, r: usize) -> usize {
        self.first_overlap[r]
    }

    /// The storage profile of `base` + A^T A (n x n, indexed by position: entry (p, p') is
    /// that of the columns at positions p and p') that [`RowSpans::add_gram_transpose`]
    /// fills: `lowest[p]` of `base` (each row's first position, p for a diagonal row)
    /// widened to the first position of every span that holds position p.
    pub fn normal_profile(&self, mut lowest: Vec<usize>) -> Vec<usize> {
        for r in 0..self.lo.len() {
            let span = self.positions(r);
            for p in span.clone() {
                lowest[p] = lowest[p].min(span.start);
            }
        }
        lowest
    }

    /// Whether the spans were fixed from a pattern ([`RowSpans::fix`]).
    pub fn is_fixed(&self) -> bool {
        self.fixed
    }

    /// Whether every entry of `a` inside the spans is finite (outside them `a` is zero).
    pub fn all_finite(&self, a: &DMatrix<f64>) -> bool {
        let m = a.nrows();
        let s = a.as_slice();
        let mut ok = true;
        for r in 0..m {
            for j in self.span(r) {
                ok &= s[r + j * m].is_finite();
            }
        }
        ok
    }

    /// Finds the first and last nonzero column of every row of `a` (O(m n), reading `a` in
    /// storage order); nothing when the spans are fixed ([`RowSpans::fix`]).
    pub fn scan(&mut self, a: &DMatrix<f64>) {
        if self.fixed {
            return;
        }
        let (m, n) = a.shape();
        if self.order.len() != n {
            self.order = (0..n).collect();
        }
        self.lo.fill(n);
        self.hi.fill(0);
        for (j, col) in a.as_slice().chunks_exact(m.max(1)).enumerate().take(n) {
            for (r, &v) in col.iter().enumerate() {
                if v != 0.0 {
                    if self.lo[r] == n {
                        self.lo[r] = j;
                    }
                    self.hi[r] = j;
                }
            }
        }
        if n <= self.cover.len() {
            self.find_overlaps();
        } else {
            // Wider than the storage of `new`: every row may overlap every other.
            self.first_overlap.fill(0);
        }
    }

    /// Adds the squared entries of each row to `out[j]` for column j: the diagonal of
    /// A^T A (out must be zeroed by the caller).
    pub fn column_squares(&self, a: &DMatrix<f64>, out: &mut [f64]) {
        let m = a.nrows();
        let s = a.as_slice();
        for r in 0..m {
            for j in self.span(r) {
                out[j] += s[r + j * m] * s[r + j * m];
            }
        }
    }

    /// The span of row r as a range of positions (empty for a zero row).
    #[inline]
    pub fn positions(&self, r: usize) -> std::ops::Range<usize> {
        if self.lo[r] > self.hi[r] {
            0..0
        } else {
            self.lo[r]..self.hi[r] + 1
        }
    }

    /// The column at position p.
    #[inline]
    pub fn column(&self, p: usize) -> usize {
        self.order[p]
    }

    /// The columns inside row r's span, in position order (empty for a zero row).
    #[inline]
    pub fn span(&self, r: usize) -> impl Iterator<Item = usize> + Clone + '_ {
        self.positions(r).map(|p| self.order[p])
    }

    /// out = A x.
    pub fn mul(&self, a: &DMatrix<f64>, x: &[f64], out: &mut [f64]) {
        let m = a.nrows();
        let s = a.as_slice();
        for (r, o) in out.iter_mut().enumerate().take(m) {
            let mut v = 0.0;
            for j in self.span(r) {
                v += s[r + j * m] * x[j];
            }
            *o = v;
        }
    }

    /// out = A^T y.
    pub fn mul_transpose(&self, a: &DMatrix<f64>, y: &[f64], out: &mut [f64]) {
        let m = a.nrows();
        let s = a.as_slice();
        out.fill(0.0);
        for (r, &yr) in y.iter().enumerate().take(m) {
            if yr != 0.0 {
                for j in self.span(r) {
                    out[j] += s[r + j * m] * yr;
                }
            }
        }
    }

    /// Adds w A^T A to the lower triangle of `env` (n x n, indexed by position), widening
    /// its envelope.
    pub fn add_gram_transpose(&self, a: &DMatrix<f64>, w: f64, env: &mut Envelope) {
        let m = a.nrows();
        let s = a.as_slice();
        for r in 0..m {
            let span = self.positions(r);
            if span.is_empty() {
                continue;
            }
            for p in span.clone() {
                env.widen(p, span.start);
            }
            for p in span.clone() {
                let ai = s[r + self.order[p] * m];
                if ai == 0.0 {
                    continue;
                }
                for pj in span.start..=p {
                    env.add(p, pj, w * ai * s[r + self.order[pj] * m]);
                }
            }
        }
    }

    /// Fills `env` (m x m) with G = A A^T + mu I over the overlapping spans.
    pub fn gram(&mut self, a: &DMatrix<f64>, mu: f64, env: &mut Envelope) {
        let m = a.nrows();
        let s = a.as_slice();
        env.clear();
        let mut work = 0;
        for r in 0..m {
            let sr = self.positions(r);
            for q in self.first_overlap[r]..=r {
                let sq = self.positions(q);
                let (lo, hi) = (sr.start.max(sq.start), sr.end.min(sq.end));
                if lo >= hi {
                    continue;
                }
                work += (hi - lo) as u64;
                let mut v = 0.0;
                for &j in &self.order[lo..hi] {
                    v += s[r + j * m] * s[q + j * m];
                }
                if v != 0.0 || q == r {
                    env.widen(r, q);
                    env.add(r, q, v);
                }
            }
            env.add(r, r, mu);
        }
        self.work = work;
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A deterministic generator of values in [-0.5, 0.5).
    pub(in crate::linalg) fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    #[test]
    fn fixed_spans_give_the_scanned_gram() {
        // A banded A with some pattern entries numerically zero: the Gram over fixed spans
        // (pairs from the pattern) equals the Gram over scanned spans.
        let mut seed = 11u64;
        let (m, n) = (12, 14);
        let mut pattern = Vec::new();
        let mut a = DMatrix::zeros(m, n);
        for r in 0..m {
            for j in r..r + 3 {
                pattern.push((r, j));
                a[(r, j)] = if (r + j) % 5 == 0 {
                    0.0
                } else {
                    lcg(&mut seed)
                };
            }
        }
        let (mut scanned, mut fixed) = (RowSpans::new(m, n), RowSpans::new(m, n));
        scanned.scan(&a);
        fixed.fix(&pattern);
        fixed.scan(&a);
        assert!(fixed.is_fixed() && fixed.all_finite(&a));
        let (mut g1, mut g2) = (Envelope::new(m), Envelope::new(m));
        scanned.gram(&a, 0.5, &mut g1);
        fixed.gram(&a, 0.5, &mut g2);
        let want = &a * a.transpose();
        for i in 0..m {
            for j in 0..=i {
                let w = want[(i, j)] + if i == j { 0.5 } else { 0.0 };
                assert!((g1.get(i, j) - w).abs() < 1e-15, "({i}, {j})");
                assert_eq!(g1.get(i, j), g2.get(i, j), "({i}, {j})");
            }
        }
    }
}
