//! The rows of a constraint Jacobian A = Phi_q (m x n): where they are nonzero, products
//! with A and A^T that skip the zeros, and which rows are independent.
//!
//! # The independence test
//! Row r of A is **redundant** when its distance to the span of the independent rows before
//! it is at most `tolerance * |a_r|`. Unpivoted Cholesky of the Gram matrix G = A A^T
//! computes exactly these distances: the pivot of row r is d_r = dist(a_r, span)^2, so a row
//! with d_r <= tolerance^2 G_rr is marked redundant and left out of the factor (its column
//! of L is zero). The rows kept are a basis of the row space, chosen in declaration order;
//! the count is the rank. G is formed from the nonzero column span of each row and
//! factored inside its envelope, so a chain costs O(m) (see [`super::Envelope`]).
//!
//! The same factor gives, for each redundant row d, the coefficients of its dependence on
//! the kept rows, a_d = sum_r c_r a_r, and with them the vectors z_d = e_d - sum_r c_r e_r
//! that span the null space of A^T: the directions in which the multipliers lambda are
//! not determined by the forces Phi_q^T lambda. [`RowBasis::min_norm`] removes them.
//!
//! Computing G squares the condition of A, so distances below about 1e-8 |a_r| are not
//! resolved: the tolerance must stay well above that ([`DEFAULT_RANK_TOLERANCE`] = 1e-6).

use nalgebra::DMatrix;

use super::envelope::Envelope;

/// Default relative distance below which a row counts as redundant (see the module docs).
pub const DEFAULT_RANK_TOLERANCE: f64 = 1e-6;

/// Nonzero column span [lo_r, hi_r] of every row of a matrix (lo > hi for a zero row).
///
/// The spans are found by [`RowSpans::scan`] on every matrix, or fixed once from the
/// matrix's structural pattern ([`RowSpans::fix`]): then `scan` does nothing and
/// [`RowSpans::gram`] visits only the pairs of rows whose spans overlap, so that neither
/// reads the dense matrix outside the spans (O(m) for a chain instead of O(m n + m^2)).
#[derive(Clone, Debug, Default)]
pub struct RowSpans {
    lo: Vec<usize>,
    hi: Vec<usize>,
    /// With fixed spans: for each row r, the rows q <= r whose spans overlap its own
    /// (r itself included), CSR over `pairs`.
    pair_start: Vec<usize>,
    pairs: Vec<usize>,
    fixed: bool,
}

impl RowSpans {
    /// Spans for m rows.
    pub fn new(m: usize) -> Self {
        Self {
            lo: vec![0; m],
            hi: vec![0; m],
            pair_start: Vec::new(),
            pairs: Vec::new(),
            fixed: false,
        }
    }

    /// Fixes the spans from the structural nonzeros `pattern` ((row, column) pairs; every
    /// row index below m) of all matrices this will see: each row's span covers its
    /// pattern, [`RowSpans::scan`] becomes a no-op and [`RowSpans::gram`] visits only
    /// overlapping pairs. Allocates (once, outside any step loop).
    pub fn fix(&mut self, pattern: &[(usize, usize)]) {
        let m = self.lo.len();
        self.lo.fill(usize::MAX);
        self.hi.fill(0);
        for &(r, j) in pattern {
            self.lo[r] = self.lo[r].min(j);
            self.hi[r] = self.hi[r].max(j);
        }
        // Rows ordered by where their spans start; a row's overlapping partners start before
        // its end, and their own ends reach past its start.
        self.pair_start = Vec::with_capacity(m + 1);
        self.pairs.clear();
        self.pair_start.push(0);
        for r in 0..m {
            let sr = self.span(r);
            for q in 0..=r {
                let sq = self.span(q);
                if q == r || (sr.start.max(sq.start) < sr.end.min(sq.end)) {
                    self.pairs.push(q);
                }
            }
            self.pair_start.push(self.pairs.len());
        }
        self.fixed = true;
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

    /// The span of row r as a range (empty for a zero row).
    #[inline]
    pub fn span(&self, r: usize) -> std::ops::Range<usize> {
        if self.lo[r] > self.hi[r] {
            0..0
        } else {
            self.lo[r]..self.hi[r] + 1
        }
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

    /// Adds w A^T A to the lower triangle of `env` (n x n), widening its envelope.
    pub fn add_gram_transpose(&self, a: &DMatrix<f64>, w: f64, env: &mut Envelope) {
        let m = a.nrows();
        let s = a.as_slice();
        for r in 0..m {
            let span = self.span(r);
            if span.is_empty() {
                continue;
            }
            for i in span.clone() {
                env.widen(i, span.start);
            }
            for i in span.clone() {
                let ai = s[r + i * m];
                if ai == 0.0 {
                    continue;
                }
                for j in span.start..=i {
                    env.add(i, j, w * ai * s[r + j * m]);
                }
            }
        }
    }

    /// Fills `env` (m x m) with G = A A^T + mu I over the overlapping spans.
    pub fn gram(&self, a: &DMatrix<f64>, mu: f64, env: &mut Envelope) {
        let m = a.nrows();
        let s = a.as_slice();
        env.clear();
        for r in 0..m {
            let sr = self.span(r);
            let partners = if self.fixed {
                &self.pairs[self.pair_start[r]..self.pair_start[r + 1]]
            } else {
                &[][..]
            };
            let all = 0..if self.fixed { 0 } else { r + 1 };
            for q in partners.iter().copied().chain(all) {
                let sq = self.span(q);
                let (lo, hi) = (sr.start.max(sq.start), sr.end.min(sq.end));
                if lo >= hi {
                    continue;
                }
                let mut v = 0.0;
                for j in lo..hi {
                    v += s[r + j * m] * s[q + j * m];
                }
                if v != 0.0 || q == r {
                    env.widen(r, q);
                    env.add(r, q, v);
                }
            }
            env.add(r, r, mu);
        }
    }
}

/// A basis of the row space of A chosen in row order, and the null space of A^T.
/// Allocates nothing after [`RowBasis::new`].
#[derive(Clone, Debug)]
pub struct RowBasis {
    m: usize,
    spans: RowSpans,
    gram: Envelope,
    redundant: Vec<bool>,
    independence: Vec<f64>,
    rank: usize,
    /// Null vectors z_d of A^T, one column per redundant row (m x m storage).
    z: DMatrix<f64>,
    zz: Envelope,
    work: Vec<f64>,
    /// The kept rows in order (the first `rank` entries), for [`RowBasis::min_norm`].
    kept: Vec<usize>,
    /// Rows whose distance to the span of the rows before them is at most this times their
    /// norm are redundant (default [`DEFAULT_RANK_TOLERANCE`]).
    pub tolerance: f64,
}

impl RowBasis {
    /// Workspace for m rows and n columns.
    pub fn new(m: usize, n: usize) -> Self {
        let _ = n;
        Self {
            m,
            spans: RowSpans::new(m),
            gram: Envelope::new(m),
            redundant: vec![false; m],
            independence: vec![1.0; m],
            rank: 0,
            z: DMatrix::zeros(m, m),
            zz: Envelope::new(m),
            work: vec![0.0; m],
            kept: vec![0; m],
            tolerance: DEFAULT_RANK_TOLERANCE,
        }
    }

    /// Fixes the row spans from the structural nonzeros of every A to come
    /// ([`RowSpans::fix`]).
    pub fn fix(&mut self, pattern: &[(usize, usize)]) {
        self.spans.fix(pattern);
    }

    /// Finds the independent rows of `a` (see the module docs); returns the rank.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> usize {
        self.spans.scan(a);
        self.spans.gram(a, 0.0, &mut self.gram);
        let tol2 = self.tolerance * self.tolerance;
        self.rank =
            self.gram
                .factor_semidefinite(tol2, &mut self.redundant, &mut self.independence);
        self.rank
    }

    /// Whether row r was found redundant.
    pub fn is_redundant(&self, r: usize) -> bool {
        self.redundant[r]
    }

    /// Row r's distance to the span of the independent rows before it, relative to |a_r|
    /// (1 for a row orthogonal to them; 0 for an exact repeat or a zero row).
    pub fn independence(&self, r: usize) -> f64 {
        self.independence[r]
    }

    /// Fills the null vectors z_d of A^T (one per redundant row) and factors Z^T Z.
    fn null_space(&mut self) {
        let k = self.m - self.rank;
        let mut col = 0;
        for d in 0..self.m {
            if !self.redundant[d] {
                continue;
            }
            self.gram
                .null_direction_skipping(d, &self.redundant, &mut self.work);
            self.z.column_mut(col).copy_from_slice(&self.work);
            col += 1;
        }
        self.zz.clear();
        for i in 0..k {
            self.zz.widen(i, 0);
            for j in 0..=i {
                let v = self.z.column(i).dot(&self.z.column(j));
                self.zz.add(i, j, v);
            }
        }
        // z_d has z_dd = 1 and zeros on the other redundant rows: Z^T Z >= I is regular.
        let _ = self.zz.factor_prefix(k, 0.0);
    }

    /// Replaces lambda by the minimum-norm multipliers with the same forces A^T lambda: the
    /// component of lambda in the null space of A^T is removed (after [`RowBasis::factor`]
    /// of the same A). No-op at full rank.
    pub fn min_norm(&mut self, lambda: &mut [f64]) {
        let k = self.m - self.rank;
        if k == 0 {
            return;
        }
        if self.rank < k {
            self.min_norm_by_rank(lambda);
            return;
        }
        self.null_space();
        for i in 0..k {
            self.work[i] = self
                .z
                .column(i)
                .iter()
                .zip(lambda.iter())
                .map(|(a, b)| a * b)
                .sum();
        }
        self.zz.solve_prefix(k, &mut self.work[..k]);
        for i in 0..k {
            let c = self.work[i];
            for (l, zv) in lambda.iter_mut().zip(self.z.column(i).iter()) {
                *l -= c * zv;
            }
        }
    }

    /// [`RowBasis::min_norm`] at a cost set by the rank r rather than the nullity k, for
    /// r < k (many redundant rows: 1,000 copies of one row have r = 1). With the kept rows
    /// A_R a basis, A = C A_R where C has the rows e_p for the kept row p and c_d (a_d =
    /// sum_p c_dp a_p) for each redundant row d; range(A) = range(C), so the minimum-norm
    /// multipliers are the projection
    ///
    /// ```text
    /// lambda <- C (C^T C)^-1 C^T lambda,   C^T C = I_r + sum_d c_d c_d^T,   C^T lambda = lambda_R + sum_d c_d lambda_d
    /// ```
    ///
    /// an r x r system instead of the k x k one of the null-space vectors: O(k m + k r^2 +
    /// r^3) (c_d by back-substitution, skipping the redundant rows, over the rows before d).
    fn min_norm_by_rank(&mut self, lambda: &mut [f64]) {
        let (m, r) = (self.m, self.rank);
        let mut p = 0;
        for i in 0..m {
            if !self.redundant[i] {
                self.kept[p] = i;
                p += 1;
            }
        }
        // c_d (on the kept rows, compact) into column col of z: z_d = e_d - sum_p c_dp e_p.
        let mut col = 0;
        for d in 0..m {
            if !self.redundant[d] {
                continue;
            }
            self.gram
                .null_direction_skipping(d, &self.redundant, &mut self.work);
            for p in 0..r {
                self.z[(p, col)] = -self.work[self.kept[p]];
            }
            col += 1;
        }
        // C^T C into the leading r x r block of zz, C^T lambda into work[..r].
        self.zz.clear();
        for i in 0..r {
            self.zz.widen(i, 0);
            self.zz.add(i, i, 1.0);
            self.work[i] = lambda[self.kept[i]];
        }
        let redundant = lambda.iter().zip(&self.redundant).filter(|(_, d)| **d);
        for (col, (&lambda_d, _)) in redundant.enumerate() {
            for i in 0..r {
                let ci = self.z[(i, col)];
                if ci == 0.0 {
                    continue;
                }
                self.work[i] += ci * lambda_d;
                for j in 0..=i {
                    self.zz.add(i, j, ci * self.z[(j, col)]);
                }
            }
        }
        // C^T C >= I is regular.
        let _ = self.zz.factor_prefix(r, 0.0);
        self.zz.solve_prefix(r, &mut self.work[..r]);
        // lambda = C w.
        let redundant = lambda.iter_mut().zip(&self.redundant).filter(|(_, d)| **d);
        for (col, (lambda_d, _)) in redundant.enumerate() {
            *lambda_d = (0..r).map(|i| self.z[(i, col)] * self.work[i]).sum();
        }
        for i in 0..r {
            lambda[self.kept[i]] = self.work[i];
        }
    }

    /// The rows on which the null space of A^T is nonzero: the rows whose multipliers are
    /// not determined by the forces (empty at full rank). Allocates (reporting only).
    pub fn indeterminate_rows(&mut self) -> Vec<usize> {
        let k = self.m - self.rank;
        if k == 0 {
            return Vec::new();
        }
        self.null_space();
        (0..self.m)
            .filter(|&r| (0..k).any(|i| self.z[(r, i)].abs() > 1e-9))
            .collect()
    }

    /// The minimum-norm multipliers lambda with A^T lambda = f (after [`RowBasis::factor`]
    /// of the same A), for f in the range of A^T: the basic solution on the independent rows,
    /// G_RR lambda_R = A_R f, then [`RowBasis::min_norm`]. Accurate to about cond(A)^2 eps
    /// relative.
    pub fn multipliers_for(&mut self, a: &DMatrix<f64>, f: &[f64], lambda: &mut [f64]) {
        self.spans.mul(a, f, lambda);
        self.gram.solve_skipping(&self.redundant, lambda);
        self.min_norm(lambda);
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

    /// The projection of `lambda` onto range(A) by nalgebra's SVD pseudo-inverse: the
    /// minimum-norm multipliers with the same forces A^T lambda.
    fn projected(a: &DMatrix<f64>, lambda: &[f64]) -> Vec<f64> {
        let l = nalgebra::DVector::from_column_slice(lambda);
        let pinv = a.clone().pseudo_inverse(1e-10).unwrap();
        (a * (pinv * l)).iter().copied().collect()
    }

    #[test]
    fn minimum_norm_multipliers_match_the_pseudo_inverse_at_any_rank() {
        // r independent rows in 6 columns, then rows that are random combinations of them
        // (m - r redundant): below, at and above rank = nullity, so both the null-space
        // form (k <= r) and the rank form (r < k) are exercised.
        let mut seed = 0x28_2028u64;
        for (r, m) in [(4, 6), (3, 6), (2, 9), (1, 40)] {
            let n = 6;
            let basis = DMatrix::from_fn(r, n, |_, _| lcg(&mut seed));
            let mut a = DMatrix::zeros(m, n);
            for i in 0..m {
                if i < r {
                    a.row_mut(i).copy_from(&basis.row(i));
                } else {
                    let c = DMatrix::from_fn(1, r, |_, _| lcg(&mut seed));
                    a.row_mut(i).copy_from(&(c * &basis));
                }
            }
            let mut b = RowBasis::new(m, n);
            assert_eq!(b.factor(&a), r, "rank of {m} rows from {r}");
            let lambda: Vec<f64> = (0..m).map(|_| lcg(&mut seed)).collect();
            let mut got = lambda.clone();
            b.min_norm(&mut got);
            let want = projected(&a, &lambda);
            // Random rows of norm ~1 with coefficients below 1/2: A is well conditioned on
            // its range (singular values above ~1e-2 for these seeds); both routes carry a
            // few hundred eps: 1e-10 bounds their difference.
            for i in 0..m {
                assert!(
                    (got[i] - want[i]).abs() < 1e-10,
                    "r {r} m {m}: lambda[{i}] {} vs {}",
                    got[i],
                    want[i]
                );
            }
        }
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
        let (mut scanned, mut fixed) = (RowSpans::new(m), RowSpans::new(m));
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
