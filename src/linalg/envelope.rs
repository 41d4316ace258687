//! Cholesky factorisation of a symmetric positive definite matrix inside its envelope.
//!
//! The matrices the solvers factor (M + alpha Phi_q^T Phi_q, Phi_q Phi_q^T + mu I) are
//! banded for chains declared in order: row i of the lower triangle is zero left of a first
//! column f_i, and the Cholesky factor L keeps that envelope (no fill outside it; George &
//! Liu, Computer Solution of Large Sparse Positive Definite Systems, 1981, ch. 4). Factoring
//! inside the envelope costs sum_i (i - f_i)^2 instead of n^3 / 3, which is what makes a
//! chain of 40 four-bar loops (n = 82) cheap, and costs nothing extra for a dense matrix.
//!
//! Storage is column-major with column i holding row i of L (L^T in the upper triangle), so
//! every inner product runs over contiguous memory. Nothing allocates after [`Envelope::new`].

// Comparisons are written `!(x > 0.0)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// A symmetric matrix and, after [`Envelope::factor`], its Cholesky factor N = L L^T.
#[derive(Clone, Debug)]
pub struct Envelope {
    n: usize,
    /// Row i of the lower triangle (input), then of L: entry (i, j) at
    /// `values[start[i] + j - lowest[i]]` for lowest[i] <= j <= i, contiguous in j.
    values: Vec<f64>,
    start: Vec<usize>,
    /// The first column row i's storage holds (0 for every row of [`Envelope::new`]; the
    /// structural profile after [`Envelope::reserve`]).
    lowest: Vec<usize>,
    /// The first column of row i's current envelope (lowest[i] <= first[i] <= i).
    first: Vec<usize>,
    /// 1 / L_ii after a factorisation (0 for dropped rows).
    inverse: Vec<f64>,
}

/// Why [`Envelope::factor`] failed: the pivot of row `row` was not positive (relative to the
/// row's diagonal), so the matrix is not positive definite (to working precision).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NotPositiveDefinite {
    /// The row whose pivot failed.
    pub row: usize,
    /// The pivot divided by the original diagonal entry (at most the tolerance).
    pub ratio: f64,
}

impl Envelope {
    /// Storage for an n x n matrix with any envelope (n (n + 1) / 2 entries).
    pub fn new(n: usize) -> Self {
        Self::with_profile(&vec![0; n])
    }

    /// Storage for an n x n matrix (n = `lowest.len()`) whose row i is nonzero from
    /// column `lowest[i]` on at most (see [`Envelope::reserve`]).
    pub fn with_profile(lowest: &[usize]) -> Self {
        let n = lowest.len();
        let mut env = Self {
            n,
            values: Vec::new(),
            start: Vec::new(),
            lowest: Vec::new(),
            first: Vec::new(),
            inverse: vec![0.0; n],
        };
        env.reserve(lowest);
        env
    }

    /// Replaces the storage by one that holds row i from column `lowest[i]` on (lowest[i]
    /// <= i): sum_i (i - lowest[i] + 1) entries instead of n (n + 1) / 2, each row
    /// contiguous, so that a banded matrix of order n occupies O(n) memory. Every later
    /// [`Envelope::widen`] must stay within it. Allocates (once, outside any step loop);
    /// the matrix is zero afterwards.
    pub fn reserve(&mut self, lowest: &[usize]) {
        assert_eq!(lowest.len(), self.n, "one lowest column per row");
        self.start.clear();
        let mut total = 0;
        for (i, &lo) in lowest.iter().enumerate() {
            assert!(lo <= i, "row {i}: lowest column {lo} right of the diagonal");
            self.start.push(total);
            total += i - lo + 1;
        }
        self.lowest = lowest.to_vec();
        self.values = vec![0.0; total];
        self.first = (0..self.n).collect();
    }

    /// Index of entry (i, j) in `values` (lowest[i] <= j <= i).
    #[inline]
    fn at(&self, i: usize, j: usize) -> usize {
        self.start[i] + j - self.lowest[i]
    }

    /// Row i from column j to the diagonal, as a slice (entry j first).
    #[inline]
    fn row(&self, i: usize, j: usize) -> &[f64] {
        &self.values[self.at(i, j)..=self.at(i, i)]
    }

    /// Sets every entry to zero and every envelope to the diagonal only. Only the entries
    /// inside the current envelope can be nonzero, so only those are cleared.
    pub fn clear(&mut self) {
        for i in 0..self.n {
            let (lo, hi) = (self.at(i, self.first[i]), self.at(i, i));
            self.values[lo..=hi].fill(0.0);
            self.first[i] = i;
        }
    }

    /// The order n of the matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Widens row i's envelope to start at column `col` (col <= i), which the storage
    /// must hold ([`Envelope::reserve`]).
    #[inline]
    pub fn widen(&mut self, i: usize, col: usize) {
        assert!(
            col >= self.lowest[i],
            "row {i}: column {col} outside the storage"
        );
        if col < self.first[i] {
            self.first[i] = col;
        }
    }

    /// Entries below the diagonal inside the envelope, sum_i (i - f_i).
    #[cfg(test)]
    pub fn profile(&self) -> usize {
        self.first.iter().enumerate().map(|(i, f)| i - f).sum()
    }

    /// First column of row i's envelope.
    #[inline]
    pub fn first(&self, i: usize) -> usize {
        self.first[i]
    }

    /// Adds `v` to the lower-triangle entry (i, j), j <= i, which must lie in the envelope.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(j <= i && j >= self.first[i]);
        let k = self.at(i, j);
        self.values[k] += v;
    }

    /// The lower-triangle entry (i, j), j <= i (zero outside the envelope).
    #[inline]
    #[cfg(test)]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if j < self.first[i] {
            0.0
        } else {
            self.values[self.at(i, j)]
        }
    }

    /// Factors in place: N = L L^T. A pivot d_i with d_i <= `tolerance` N_ii (or N_ii <= 0)
    /// is reported as [`NotPositiveDefinite`] and leaves the factor unusable.
    pub fn factor(&mut self, tolerance: f64) -> Result<(), NotPositiveDefinite> {
        self.factor_prefix(self.n, tolerance)
    }

    /// [`Envelope::factor`] of the leading k x k block only.
    pub fn factor_prefix(&mut self, k: usize, tolerance: f64) -> Result<(), NotPositiveDefinite> {
        for i in 0..k {
            let (diag, d) = self.eliminate_row(i, &[]);
            // `!(d > ..)` so that NaN fails too.
            if !(diag > 0.0) || !(d > tolerance * diag) {
                return Err(NotPositiveDefinite {
                    row: i,
                    ratio: if diag > 0.0 { d / diag } else { d },
                });
            }
            let l = d.sqrt();
            let ii = self.at(i, i);
            self.values[ii] = l;
            self.inverse[i] = 1.0 / l;
        }
        Ok(())
    }

    /// Cholesky of a positive semidefinite matrix with rows dropped: a row whose pivot is
    /// d_i <= `tolerance` N_ii (or whose diagonal is not positive) is marked in `dropped`
    /// and left out (its column of L is zero). `ratio[i]` gets sqrt(d_i / N_ii), clamped to
    /// [0, 1]. For a Gram matrix N = A A^T this is row i's distance to the span of the kept
    /// rows before it, relative to |a_i|. Returns the number of rows kept.
    pub fn factor_semidefinite(
        &mut self,
        tolerance: f64,
        dropped: &mut [bool],
        ratio: &mut [f64],
    ) -> usize {
        let mut kept = 0;
        for i in 0..self.n {
            let (diag, d) = self.eliminate_row(i, &dropped[..i]);
            let ii = self.at(i, i);
            ratio[i] = if diag > 0.0 && d > 0.0 {
                (d / diag).sqrt().min(1.0)
            } else {
                0.0
            };
            if !(diag > 0.0) || !(d > tolerance * diag) {
                dropped[i] = true;
                self.values[ii] = 0.0;
                self.inverse[i] = 0.0;
            } else {
                dropped[i] = false;
                let l = d.sqrt();
                self.values[ii] = l;
                self.inverse[i] = 1.0 / l;
                kept += 1;
            }
        }
        kept
    }

    /// Row i of L left of the diagonal (in place, over the envelope; columns of rows marked
    /// in `dropped` are zero; `dropped` may be empty: none), and the pivot: returns (N_ii,
    /// d_i = N_ii - sum_k L_ik^2).
    fn eliminate_row(&mut self, i: usize, dropped: &[bool]) -> (f64, f64) {
        let fi = self.first[i];
        let base_i = self.at(i, fi);
        let len = i - fi;
        // Row i of L is written in place; the rows j < i it reads lie before it in
        // `values` (rows are stored in order), so split there.
        let (before, row_i) = self.values.split_at_mut(base_i);
        for (c, j) in (fi..i).enumerate() {
            if dropped.get(j).copied().unwrap_or(false) {
                row_i[c] = 0.0;
                continue;
            }
            let fj = self.first[j].max(fi);
            let base_j = self.start[j] - self.lowest[j];
            let lj = &before[base_j + fj..=base_j + j];
            let li = &row_i[fj - fi..c];
            let dot: f64 = li.iter().zip(lj).map(|(x, y)| x * y).sum();
            // The diagonal of row j holds L_jj (0 when dropped, handled above).
            row_i[c] = (row_i[c] - dot) * self.inverse[j];
        }
        let diag = row_i[len];
        let d = diag - row_i[..len].iter().map(|x| x * x).sum::<f64>();
        (diag, d)
    }

    /// Solves N x = b in place after a successful [`Envelope::factor`].
    pub fn solve(&self, b: &mut [f64]) {
        self.solve_prefix(self.n, b);
    }

    /// Solves with the leading k x k block after [`Envelope::factor_prefix`] of k.
    pub fn solve_prefix(&self, k: usize, b: &mut [f64]) {
        self.substitute(k, &[], b);
    }

    /// Solves with the factor of [`Envelope::factor_semidefinite`] restricted to the kept
    /// rows: b_i = 0 on dropped rows, N_RR x_R = b_R on the others.
    pub fn solve_skipping(&self, dropped: &[bool], b: &mut [f64]) {
        self.substitute(self.n, dropped, b);
    }

    /// L L^T x = b over the leading k rows, in place, the rows marked in `dropped` (empty:
    /// none) left out with x_i = 0.
    fn substitute(&self, k: usize, dropped: &[bool], b: &mut [f64]) {
        let is_dropped = |i: usize| dropped.get(i).copied().unwrap_or(false);
        for i in 0..k {
            if is_dropped(i) {
                b[i] = 0.0;
                continue;
            }
            let fi = self.first[i];
            let row = self.row(i, fi);
            let dot: f64 = row[..i - fi]
                .iter()
                .zip(&b[fi..i])
                .map(|(l, x)| l * x)
                .sum();
            b[i] = (b[i] - dot) * self.inverse[i];
        }
        for i in (0..k).rev() {
            if is_dropped(i) {
                continue;
            }
            let fi = self.first[i];
            let x = b[i] * self.inverse[i];
            b[i] = x;
            let row = self.row(i, fi);
            for (bp, l) in b[fi..i].iter_mut().zip(row) {
                *bp -= l * x;
            }
        }
    }

    /// After a failed factorisation at `row`: a vector z with z_row = 1 and N z ~ 0 on rows
    /// 0..=row (the direction in which the matrix is not positive definite), written into
    /// `z` (length n, zero beyond `row`). Uses the rows of L computed before the failure.
    pub fn null_direction(&self, row: usize, z: &mut [f64]) {
        self.back_substitute(row, z);
    }

    /// z_row = 1, z_k = -L_row,k (k < row), then z <- L^-T z over the rows before `row`.
    fn back_substitute(&self, row: usize, z: &mut [f64]) {
        z.fill(0.0);
        z[row] = 1.0;
        let fr = self.first[row];
        for (zp, l) in z[fr..row].iter_mut().zip(self.row(row, fr)) {
            *zp = -l;
        }
        for i in (0..row).rev() {
            let fi = self.first[i];
            let x = z[i] * self.inverse[i];
            z[i] = x;
            for (zp, l) in z[fi..i].iter_mut().zip(self.row(i, fi)) {
                *zp -= l * x;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    fn fill(env: &mut Envelope, a: &DMatrix<f64>) {
        env.clear();
        let n = a.nrows();
        for i in 0..n {
            for j in 0..=i {
                if a[(i, j)] != 0.0 {
                    env.widen(i, j);
                }
            }
            for j in env.first(i)..=i {
                env.add(i, j, a[(i, j)]);
            }
        }
    }

    #[test]
    fn banded_and_dense_solves_match_nalgebra() {
        for (n, band) in [(1, 0), (5, 1), (9, 2), (12, 11), (30, 3)] {
            let a = DMatrix::from_fn(n, n, |i, j| {
                let d = i.abs_diff(j);
                if d > band {
                    0.0
                } else if d == 0 {
                    4.0 + i as f64 * 0.1
                } else {
                    0.5 / d as f64 + 0.01 * ((i + j) % 3) as f64
                }
            });
            let mut env = Envelope::new(n);
            fill(&mut env, &a);
            env.factor(1e-14).unwrap();
            let x: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
            let b = &a * nalgebra::DVector::from_column_slice(&x);
            let mut y: Vec<f64> = b.iter().copied().collect();
            env.solve(&mut y);
            for i in 0..n {
                assert!(
                    (y[i] - x[i]).abs() < 1e-13,
                    "n {n} band {band}: {} vs {}",
                    y[i],
                    x[i]
                );
            }
        }
    }

    #[test]
    fn tree_matrices_match_nalgebra_cholesky() {
        // Random trees (each node's parent declared before it, as links and bodies are),
        // the matrix nonzero on the diagonal and on each (child, parent) pair: the pattern
        // of M and of A^T A for an open tree. The diagonal is d_i = 1 + 2 o_i with o_i the
        // row's off-diagonal sum, so by Gershgorin every eigenvalue lies in
        // [1, 1 + 3 max o_i]: SPD, and with entries below 1/2 and a few children per node
        // the condition stays below about 20.
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [2, 7, 30, 120] {
            let parent: Vec<usize> = (0..n).map(|i| (next() * i as f64) as usize).collect();
            let mut a = DMatrix::<f64>::zeros(n, n);
            for i in 1..n {
                let v = next() - 0.5;
                a[(i, parent[i])] = v;
                a[(parent[i], i)] = v;
            }
            for i in 0..n {
                let off: f64 = (0..n).filter(|&j| j != i).map(|j| a[(i, j)].abs()).sum();
                a[(i, i)] = 1.0 + 2.0 * off;
            }
            let mut env = Envelope::new(n);
            fill(&mut env, &a);
            env.factor(1e-14).unwrap();
            let b: Vec<f64> = (0..n).map(|_| next() * 2.0 - 1.0).collect();
            let mut x = b.clone();
            env.solve(&mut x);
            let want = a
                .clone()
                .cholesky()
                .unwrap()
                .solve(&nalgebra::DVector::from_column_slice(&b));
            // Both solutions are within cond n eps |x| of the truth (cond <= 20, n <= 120,
            // |x| <= |b| <= 1): 5e-13, so 1e-12 bounds their difference.
            for i in 0..n {
                assert!(
                    (x[i] - want[i]).abs() < 1e-12,
                    "n {n}: {} vs {}",
                    x[i],
                    want[i]
                );
            }
        }
    }

    #[test]
    fn indefinite_is_reported_with_its_null_direction() {
        // [2 1 0; 1 0.5 0; 0 0 1] is singular: (1, -2, 0) is a null vector.
        let a = DMatrix::from_row_slice(3, 3, &[2.0, 1.0, 0.0, 1.0, 0.5, 0.0, 0.0, 0.0, 1.0]);
        let mut env = Envelope::new(3);
        fill(&mut env, &a);
        let err = env.factor(1e-13).unwrap_err();
        assert_eq!(err.row, 1);
        let mut z = [0.0; 3];
        env.null_direction(err.row, &mut z);
        let r = &a * nalgebra::DVector::from_column_slice(&z);
        assert!(r.amax() < 1e-14 && (z[0] + 0.5).abs() < 1e-15, "{z:?}");
    }
}
