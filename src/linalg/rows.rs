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
#[derive(Clone, Debug, Default)]
pub struct RowSpans {
    lo: Vec<usize>,
    hi: Vec<usize>,
}

impl RowSpans {
    /// Spans for m rows.
    pub fn new(m: usize) -> Self {
        Self {
            lo: vec![0; m],
            hi: vec![0; m],
        }
    }

    /// Finds the first and last nonzero column of every row of `a` (O(m n), reading `a` in
    /// storage order).
    pub fn scan(&mut self, a: &DMatrix<f64>) {
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
            for q in 0..=r {
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
            tolerance: DEFAULT_RANK_TOLERANCE,
        }
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

    /// The rank found by the last [`RowBasis::factor`].
    pub fn rank(&self) -> usize {
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

    /// The smallest independence among the rows kept in the basis (1 when none): how close
    /// the configuration is to losing rank.
    pub fn weakest(&self) -> f64 {
        (0..self.m)
            .filter(|&r| !self.redundant[r])
            .map(|r| self.independence[r])
            .fold(1.0, f64::min)
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
