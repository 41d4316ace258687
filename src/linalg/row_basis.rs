//! Which rows of a constraint Jacobian A = Phi_q (m x n) are independent, and the
//! minimum-norm multipliers that the redundant ones leave open.
//!
//! # The independence test
//! Row i of A is **redundant** when its distance to the span of the independent rows before
//! it is at most `tolerance * |a_i|`. With the rows kept so far, A_R, and the Cholesky
//! factor L of their Gram matrix G_RR = A_R A_R^T = L L^T, that distance is
//!
//! ```text
//! d_i = |a_i|^2 - |l_i|^2,    L l_i = A_R a_i     (d_i = dist(a_i, span A_R)^2)
//! ```
//!
//! and a row with d_i > tolerance^2 |a_i|^2 is kept: l_i and sqrt(d_i) become the next row
//! of L. This is the semidefinite Cholesky factor of the whole Gram matrix A A^T with the
//! redundant rows' columns left out, formed against the kept rows only: row i costs its
//! products with the kept rows whose spans overlap its own and a forward substitution over
//! them, so a chain costs O(m) and m copies of one row O(m) too (rank 1), where the whole
//! Gram matrix would cost m^2. The rows kept are a basis of the row space, chosen in
//! declaration order; their count is the rank.
//!
//! For each redundant row d the same factor gives the coefficients of its dependence on the
//! kept rows, a_d = sum_p c_dp a_p (L^T c_d = l_d), and with them the vectors z_d = e_d -
//! sum_p c_dp e_p that span the null space of A^T: the directions in which the multipliers
//! lambda are not determined by the forces Phi_q^T lambda. [`RowBasis::min_norm`] removes
//! them.
//!
//! Forming A_R a_i squares the condition of A, so distances below about 1e-8 |a_i| are not
//! resolved: the tolerance must stay well above that ([`DEFAULT_RANK_TOLERANCE`] = 1e-6).

use nalgebra::DMatrix;

use super::envelope::Envelope;
use super::rows::RowSpans;

/// Default relative distance below which a row counts as redundant (see the module docs).
pub const DEFAULT_RANK_TOLERANCE: f64 = 1e-6;

/// A basis of the row space of A chosen in row order, and the null space of A^T.
/// Allocates nothing after [`RowBasis::new`] and [`RowBasis::fix`].
#[derive(Clone, Debug)]
pub struct RowBasis {
    m: usize,
    spans: RowSpans,
    redundant: Vec<bool>,
    independence: Vec<f64>,
    rank: usize,
    /// The kept rows in order (the first `rank` entries).
    kept: Vec<usize>,
    /// For each row i: the kept rows before it (`before[i]`), the first kept position its
    /// span can overlap (`from[i]`), and where l_i (entries for the kept positions
    /// from[i]..before[i]) starts in `coefficients`.
    before: Vec<usize>,
    from: Vec<usize>,
    start: Vec<usize>,
    coefficients: Vec<f64>,
    /// L_pp and 1 / L_pp of the kept position p.
    diagonal: Vec<f64>,
    inverse: Vec<f64>,
    /// c_d of the redundant rows, `rank` entries each (one after the other), for
    /// [`RowBasis::min_norm`]; and the smaller of the two Gram forms it factors.
    dependence: Vec<f64>,
    small: Envelope,
    work: Vec<f64>,
    /// Multiply-adds of the last factor.
    work_done: u64,
    /// Rows whose distance to the span of the independent rows before them is at most this
    /// times their norm are redundant (default [`DEFAULT_RANK_TOLERANCE`]).
    pub tolerance: f64,
}

impl RowBasis {
    /// Workspace for m rows and n columns: storage for min(m, n) kept rows, whatever the
    /// spans (see [`RowBasis::fix`] for less).
    pub fn new(m: usize, n: usize) -> Self {
        let most = m.min(n);
        let mut basis = Self {
            m,
            spans: RowSpans::new(m, n),
            redundant: vec![false; m],
            independence: vec![1.0; m],
            rank: 0,
            kept: vec![0; most],
            before: vec![0; m],
            from: vec![0; m],
            start: vec![0; m],
            coefficients: Vec::new(),
            diagonal: vec![0.0; most],
            inverse: vec![0.0; most],
            dependence: vec![0.0; m * most],
            small: Envelope::new(most),
            work: vec![0.0; m.max(n)],
            work_done: 0,
            tolerance: DEFAULT_RANK_TOLERANCE,
        };
        basis.reserve();
        basis
    }

    /// Storage for the l_i of every row: at most min(i - first overlap, min(m, n)) entries
    /// each (no more kept rows overlap it, and no more rows can be kept).
    fn reserve(&mut self) {
        let most = self.kept.len();
        let total: usize = (0..self.m)
            .map(|i| (i - self.spans.first_overlap(i)).min(most))
            .sum();
        self.coefficients = vec![0.0; total];
    }

    /// Fixes the row spans from the structural nonzeros of every A to come
    /// ([`RowSpans::fix`]): each row is then compared with the kept rows its span
    /// overlaps only, and the storage shrinks to match. Allocates (once).
    pub fn fix(&mut self, pattern: &[(usize, usize)]) {
        self.spans.fix(pattern);
        self.reserve();
    }

    /// [`RowBasis::fix`] with the spans in the column order `order`
    /// ([`RowSpans::fix_ordered`]): the same rows kept and the same multipliers up to
    /// round-off, at the cost of the overlaps in that order. Allocates (once).
    pub fn fix_ordered(&mut self, pattern: &[(usize, usize)], order: &[usize]) {
        self.spans.fix_ordered(pattern, order);
        self.reserve();
    }

    /// Finds the independent rows of `a` (see the module docs); returns the rank.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> usize {
        self.spans.scan(a);
        let m = self.m;
        let s = a.as_slice();
        let tol2 = self.tolerance * self.tolerance;
        let mut rank = 0;
        let mut used = 0;
        let mut work = 0u64;
        for i in 0..m {
            let span = self.spans.positions(i);
            let norm2: f64 = self
                .spans
                .span(i)
                .map(|j| s[i + j * m] * s[i + j * m])
                .sum();
            self.before[i] = rank;
            let from = self.before[self.spans.first_overlap(i)];
            self.from[i] = from;
            self.start[i] = used;
            let (done, rest) = self.coefficients.split_at_mut(used);
            let row = &mut rest[..rank - from];
            // A_R a_i over the kept rows that can overlap row i, then L^-1 of it.
            for (c, p) in (from..rank).enumerate() {
                let k = self.kept[p];
                let other = self.spans.positions(k);
                let (lo, hi) = (span.start.max(other.start), span.end.min(other.end));
                work += hi.saturating_sub(lo) as u64;
                let columns = (lo..hi).map(|p| self.spans.column(p));
                row[c] = columns.map(|j| s[i + j * m] * s[k + j * m]).sum();
            }
            for c in 0..row.len() {
                let p = from + c;
                let fp = self.from[self.kept[p]].max(from);
                let lp = &done[self.start[self.kept[p]] + fp - self.from[self.kept[p]]..];
                let dot: f64 = row[fp - from..c].iter().zip(lp).map(|(x, y)| x * y).sum();
                row[c] = (row[c] - dot) * self.inverse[p];
                work += (c - (fp - from)) as u64;
            }
            let d = norm2 - row.iter().map(|x| x * x).sum::<f64>();
            used += row.len();
            self.independence[i] = if norm2 > 0.0 && d > 0.0 {
                (d / norm2).sqrt().min(1.0)
            } else {
                0.0
            };
            // `!(d > ..)` so that NaN counts as redundant. Once min(m, n) rows are kept
            // they span every row: a further row that passes the test (round-off in d when
            // the kept rows are nearly dependent) is redundant all the same.
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            let redundant = rank == self.kept.len() || !(norm2 > 0.0) || !(d > tol2 * norm2);
            self.redundant[i] = redundant;
            if !redundant {
                self.kept[rank] = i;
                self.diagonal[rank] = d.sqrt();
                self.inverse[rank] = 1.0 / self.diagonal[rank];
                rank += 1;
            }
        }
        self.rank = rank;
        self.work_done = work;
        rank
    }

    /// Multiply-adds of the last [`RowBasis::factor`]: the products of each row with the
    /// kept rows its span overlaps and the forward substitutions (the counted cost of the
    /// factor, which depends on the column order of the spans, not on the values).
    pub fn work(&self) -> u64 {
        self.work_done
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

    /// Row i's l_i (the kept positions from[i]..before[i]).
    fn l(&self, i: usize) -> &[f64] {
        let len = self.before[i] - self.from[i];
        &self.coefficients[self.start[i]..self.start[i] + len]
    }

    /// Solves L^T c = y in place over the kept positions (y: `rank` entries).
    fn back_substitute(&self, y: &mut [f64]) {
        for p in (0..self.rank).rev() {
            let c = y[p] * self.inverse[p];
            y[p] = c;
            let k = self.kept[p];
            let from = self.from[k];
            for (yq, l) in y[from..p].iter_mut().zip(self.l(k)) {
                *yq -= l * c;
            }
        }
    }

    /// Solves L y' = y in place over the kept positions.
    fn forward_substitute(&self, y: &mut [f64]) {
        for p in 0..self.rank {
            let k = self.kept[p];
            let from = self.from[k];
            let dot: f64 = self.l(k).iter().zip(&y[from..p]).map(|(l, x)| l * x).sum();
            y[p] = (y[p] - dot) * self.inverse[p];
        }
    }

    /// c_d of every redundant row d into `dependence` (row j of the k x r matrix C_D for
    /// the j-th redundant row): O(k r b) for a band b of L.
    fn dependences(&mut self) {
        let r = self.rank;
        let mut dependence = std::mem::take(&mut self.dependence);
        let redundant = (0..self.m).filter(|&d| self.redundant[d]);
        for (j, d) in redundant.enumerate() {
            let c = &mut dependence[j * r..(j + 1) * r];
            c.fill(0.0);
            let from = self.from[d];
            c[from..self.before[d]].copy_from_slice(self.l(d));
            self.back_substitute(c);
        }
        self.dependence = dependence;
    }

    /// Replaces lambda by the minimum-norm multipliers with the same forces A^T lambda: the
    /// component of lambda in the null space of A^T is removed (after [`RowBasis::factor`]
    /// of the same A). No-op at full rank. With Z = [z_d] (k = m - r null vectors) and
    /// A = C A_R (C: the rows e_p for the kept row p and c_d for each redundant row d),
    ///
    /// ```text
    /// k <= r:  lambda <- lambda - Z (Z^T Z)^-1 Z^T lambda,   Z^T Z = I_k + C_D C_D^T
    /// k >  r:  lambda <- C (C^T C)^-1 C^T lambda,            C^T C = I_r + C_D^T C_D
    /// ```
    ///
    /// whichever system is smaller: O(k r min(k, r) + min(k, r)^3), linear in m for a
    /// bounded rank.
    pub fn min_norm(&mut self, lambda: &mut [f64]) {
        let (m, r) = (self.m, self.rank);
        let k = m - r;
        if k == 0 {
            return;
        }
        self.dependences();
        let cd = &self.dependence;
        let row = |j: usize| &cd[j * r..(j + 1) * r];
        let small = &mut self.small;
        small.clear();
        let size = k.min(r);
        for i in 0..size {
            small.widen(i, 0);
            small.add(i, i, 1.0);
        }
        let work = &mut self.work[..size];
        let lambda_r = |lambda: &[f64], p: usize| lambda[self.kept[p]];
        // (j, d): the j-th redundant row is row d.
        let redundant = || {
            let rows = self.redundant.iter().enumerate();
            rows.filter(|(_, r)| **r).map(|(d, _)| d).enumerate()
        };
        if k <= r {
            // Z^T Z and Z^T lambda = lambda_D - C_D lambda_R.
            for (j, d) in redundant() {
                let cj = row(j);
                for (i, ci) in (0..j + 1).map(|i| (i, row(i))) {
                    small.add(j, i, cj.iter().zip(ci).map(|(x, y)| x * y).sum());
                }
                work[j] = lambda[d] - (0..r).map(|p| cj[p] * lambda_r(lambda, p)).sum::<f64>();
            }
            // Z^T Z >= I is regular.
            let _ = small.factor_prefix(size, 0.0);
            small.solve_prefix(size, work);
            for (j, d) in redundant() {
                lambda[d] -= work[j];
                for (p, c) in row(j).iter().enumerate() {
                    lambda[self.kept[p]] += c * work[j];
                }
            }
        } else {
            // C^T C and C^T lambda = lambda_R + C_D^T lambda_D.
            for (p, w) in work.iter_mut().enumerate() {
                *w = lambda_r(lambda, p);
            }
            for (j, d) in redundant() {
                let cj = row(j);
                for (p, &cp) in cj.iter().enumerate() {
                    if cp == 0.0 {
                        continue;
                    }
                    work[p] += cp * lambda[d];
                    for (q, &cq) in cj[..=p].iter().enumerate() {
                        small.add(p, q, cp * cq);
                    }
                }
            }
            // C^T C >= I is regular.
            let _ = small.factor_prefix(size, 0.0);
            small.solve_prefix(size, work);
            for (j, d) in redundant() {
                lambda[d] = row(j).iter().zip(work.iter()).map(|(c, w)| c * w).sum();
            }
            for (p, w) in work.iter().enumerate() {
                lambda[self.kept[p]] = *w;
            }
        }
    }

    /// The rows on which the null space of A^T is nonzero: the rows whose multipliers are
    /// not determined by the forces (empty at full rank). Allocates (reporting only).
    pub fn indeterminate_rows(&mut self) -> Vec<usize> {
        let r = self.rank;
        if r == self.m {
            return Vec::new();
        }
        self.dependences();
        let mut involved = self.redundant.clone();
        for c in self.dependence[..(self.m - r) * r].chunks_exact(r.max(1)) {
            for (p, v) in c.iter().enumerate().take(r) {
                if v.abs() > 1e-9 {
                    involved[self.kept[p]] = true;
                }
            }
        }
        (0..self.m).filter(|&i| involved[i]).collect()
    }

    /// The minimum-norm multipliers lambda with A^T lambda = f (after [`RowBasis::factor`]
    /// of the same A), for f in the range of A^T: the basic solution on the independent rows,
    /// G_RR lambda_R = A_R f, then [`RowBasis::min_norm`]. Accurate to about cond(A)^2 eps
    /// relative.
    pub fn multipliers_for(&mut self, a: &DMatrix<f64>, f: &[f64], lambda: &mut [f64]) {
        let m = self.m;
        let s = a.as_slice();
        let mut y = std::mem::take(&mut self.work);
        for (y, &k) in y.iter_mut().zip(&self.kept[..self.rank]) {
            *y = self.spans.span(k).map(|j| s[k + j * m] * f[j]).sum();
        }
        self.forward_substitute(&mut y[..self.rank]);
        self.back_substitute(&mut y[..self.rank]);
        lambda.fill(0.0);
        for p in 0..self.rank {
            lambda[self.kept[p]] = y[p];
        }
        self.work = y;
        self.min_norm(lambda);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::rows::tests::lcg;

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
            // Random rows of norm ~1 with coefficients below 1/2: A is well conditioned on
            // its range (singular values above ~1e-2 for these seeds); both routes carry a
            // few hundred eps: 1e-10 bounds their difference.
            assert_projects(&mut b, &a, &lambda, &format!("r {r} m {m}"));
        }
    }

    /// `b.min_norm` of `lambda` (after `b.factor(a)`) within 1e-10 of the SVD projection.
    fn assert_projects(b: &mut RowBasis, a: &DMatrix<f64>, lambda: &[f64], label: &str) {
        let mut got = lambda.to_vec();
        b.min_norm(&mut got);
        let want = projected(a, lambda);
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!((g - w).abs() < 1e-10, "{label}: lambda[{i}] {g} vs {w}");
        }
    }

    /// Row i's distance to the span of `rows` (least squares by nalgebra's SVD), relative
    /// to |a_i|.
    fn relative_distance(a: &DMatrix<f64>, rows: &[usize], i: usize) -> f64 {
        let ai = a.row(i).transpose();
        if ai.norm() == 0.0 {
            return 0.0;
        }
        if rows.is_empty() {
            return 1.0;
        }
        let basis = DMatrix::from_fn(a.ncols(), rows.len(), |j, c| a[(rows[c], j)]);
        let x = basis.clone().svd(true, true).solve(&ai, 1e-12).unwrap();
        (&basis * x - &ai).norm() / ai.norm()
    }

    /// More rows than columns: the pendulum in (th, x, y) with the rows x - L sin th,
    /// y + L cos th and x^2 + y^2 - L^2 (implied by the other two on the constraint
    /// manifold) and a drive row on th, at the configuration an inverse-dynamics run tests
    /// them (th moved to 0.0021 rad, x and y not yet). The third row is 1.7e-3 |a| from
    /// the first two, so it is kept; the drive row's d is then round-off of a Gram matrix
    /// of condition 3e5 (3e-11, above tolerance^2 = 1e-12). Three kept rows span R^3: it
    /// must count as redundant and the rank stay 3.
    #[test]
    fn no_more_rows_are_kept_than_there_are_columns() {
        let th = 0.0020999968500014176_f64;
        let a = DMatrix::from_row_slice(
            4,
            3,
            &[
                -0.8 * th.cos(),
                1.0,
                0.0, //
                -0.8 * th.sin(),
                0.0,
                1.0, //
                0.0,
                0.0,
                -1.6, //
                1.0,
                0.0,
                0.0,
            ],
        );
        let mut basis = RowBasis::new(4, 3);
        assert_eq!(basis.factor(&a), 3);
        assert!(!basis.is_redundant(2) && basis.is_redundant(3));
    }

    #[test]
    fn kept_rows_are_those_an_svd_finds_independent_of_the_rows_kept_before() {
        // A banded Jacobian (three entries a row, fixed pattern) with exact repeats, exact
        // combinations of the two rows before, a zero row and rows nearly dependent (by
        // 1e-9, well below the tolerance 1e-6, and by 1e-3, well above it): each row is
        // kept exactly when its SVD distance to the rows kept before it exceeds 1e-6.
        let mut seed = 0x28_0002u64;
        let (m, n) = (30, 34);
        let mut a = DMatrix::zeros(m, n);
        let mut pattern = Vec::new();
        for r in 0..m {
            let lo = r.saturating_sub(3);
            for j in lo..r + 3 {
                pattern.push((r, j));
            }
            match r % 6 {
                3 => {
                    let row = a.row(r - 1).clone_owned();
                    a.row_mut(r).copy_from(&row);
                }
                4 => {
                    let row = a.row(r - 1) * 0.5 - a.row(r - 2) * 2.0;
                    a.row_mut(r).copy_from(&row);
                }
                5 if r == 11 => {}
                5 => {
                    let tilt = if r == 17 { 1e-9 } else { 1e-3 };
                    let mut row = a.row(r - 3).clone_owned();
                    row[(0, r + 2)] += tilt;
                    a.row_mut(r).copy_from(&row);
                }
                _ => {
                    for j in r..r + 3 {
                        a[(r, j)] = lcg(&mut seed);
                    }
                }
            }
        }
        let (mut fixed, mut scanned) = (RowBasis::new(m, n), RowBasis::new(m, n));
        fixed.fix(&pattern);
        let rank = fixed.factor(&a);
        assert_eq!(scanned.factor(&a), rank);
        let mut kept = Vec::new();
        for i in 0..m {
            let distance = relative_distance(&a, &kept, i);
            assert_eq!(
                fixed.is_redundant(i),
                distance <= 1e-6,
                "row {i}: distance {distance:e}"
            );
            assert_eq!(fixed.is_redundant(i), scanned.is_redundant(i), "row {i}");
            // The Gram route resolves distances to about sqrt(eps) |a_i| (module docs).
            assert!(
                (fixed.independence(i) - distance.min(1.0)).abs() < 1e-7,
                "row {i}: {} vs {distance}",
                fixed.independence(i)
            );
            if !fixed.is_redundant(i) {
                kept.push(i);
            }
        }
        assert_eq!(kept.len(), rank);
        // The minimum-norm multipliers, with row 17 an exact repeat of row 14 (tilted by
        // 1e-9 it counts as redundant here, where an SVD truth would keep it).
        let row = a.row(14).clone_owned();
        a.row_mut(17).copy_from(&row);
        assert_eq!(fixed.factor(&a), rank);
        assert_eq!(scanned.factor(&a), rank);
        let lambda: Vec<f64> = (0..m).map(|_| lcg(&mut seed)).collect();
        // Rows of norm ~1, coefficients up to 2: the projection carries a few hundred eps
        // on both routes, amplified by 1 / sigma_min ~ 1e3 (the 1e-3 tilts make A's
        // smallest nonzero singular value about 1e-3): 1e-10 bounds the difference.
        assert_projects(&mut fixed, &a, &lambda, "fixed spans");
        assert_projects(&mut scanned, &a, &lambda, "scanned spans");
    }

    #[test]
    fn many_copies_of_one_row_keep_the_first_and_average_the_multipliers() {
        // K copies of one row: rank 1, the first kept, and range(A) = span(1, ..., 1), so
        // the minimum-norm multipliers are the mean of lambda on every row (closed form).
        for copies in [2, 10, 1000] {
            let (m, n) = (copies, 2);
            let a = DMatrix::from_fn(m, n, |_, j| if j == 0 { 1.0 } else { 0.0 });
            let pattern: Vec<(usize, usize)> = (0..m).map(|r| (r, 0)).collect();
            let mut b = RowBasis::new(m, n);
            b.fix(&pattern);
            assert_eq!(b.factor(&a), 1);
            assert!(!b.is_redundant(0) && (1..m).all(|r| b.is_redundant(r)));
            let lambda: Vec<f64> = (0..m).map(|r| (r as f64 * 0.37).sin()).collect();
            let mean = lambda.iter().sum::<f64>() / m as f64;
            let mut got = lambda.clone();
            b.min_norm(&mut got);
            // The mean of m values below 1 carries m eps at most.
            assert!(
                got.iter().all(|g| (g - mean).abs() < 1e-15 * m as f64),
                "{copies}"
            );
            assert_eq!(b.indeterminate_rows().len(), m);
        }
    }
}
