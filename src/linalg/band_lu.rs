//! LU factorisation with partial pivoting of a banded matrix, in place in storage
//! allocated once.
//!
//! A has kl nonzero diagonals below the main one and ku above it. Row interchanges widen U
//! to kl + ku diagonals above the main one, never more, and L keeps kl below it (LAPACK's
//! `dgbtf2`; Golub & Van Loan, Matrix Computations, 4th ed., sec. 4.3.5), so
//!
//! ```text
//! P A = L U,    cost about 2 n kl (kl + ku) flops,    storage n (2 kl + ku + 1)
//! ```
//!
//! which is linear in n for a fixed band: the constrained dynamics of a chain, its coordinates
//! and constraint rows interleaved by [`super::BandOrder`]. Partial pivoting makes it backward
//! stable for the indefinite KKT matrices whose diagonal is zero on the constraint rows.
//!
//! Storage: entry (i, j) of the band lives at `ab[kl + ku + i - j + j * ld]`, ld = 2 kl +
//! ku + 1 (the first kl rows of each column hold the fill of U).

/// A banded matrix and, after [`BandLu::factor`], its LU factors with row pivoting.
/// Allocates nothing after [`BandLu::new`].
#[derive(Clone, Debug)]
pub struct BandLu {
    /// Largest order and band widths the storage holds.
    capacity: (usize, usize),
    n: usize,
    kl: usize,
    ku: usize,
    ab: Vec<f64>,
    piv: Vec<usize>,
    /// 1 / U_jj after a factorisation (the solve multiplies: a division's latency would
    /// sit on the back substitution's dependency chain).
    inverse: Vec<f64>,
}

/// Why [`BandLu::factor`] failed: the pivot of column `column` was at most the tolerance
/// times the largest entry of the matrix (or not finite), so A is singular to working
/// precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SingularPivot {
    /// The column whose pivot failed.
    pub column: usize,
}

impl BandLu {
    /// Storage for orders up to `n` with kl + ku at most `width` (each of them at most
    /// `width`).
    pub fn new(n: usize, width: usize) -> Self {
        Self {
            capacity: (n, width),
            n: 0,
            kl: 0,
            ku: 0,
            ab: vec![0.0; n * (3 * width + 1)],
            piv: vec![0; n],
            inverse: vec![0.0; n],
        }
    }

    /// Starts a matrix of order n with kl sub- and ku superdiagonals, all zero. Returns
    /// false (and changes nothing) when it does not fit the storage of [`BandLu::new`].
    pub fn reset(&mut self, n: usize, kl: usize, ku: usize) -> bool {
        let (cap_n, cap_w) = self.capacity;
        if n > cap_n || kl + ku > cap_w {
            return false;
        }
        (self.n, self.kl, self.ku) = (n, kl, ku);
        let used = n * self.ld();
        self.ab[..used].fill(0.0);
        true
    }

    /// Order n of the current matrix.
    #[cfg(test)]
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Leading dimension of the band storage, 2 kl + ku + 1.
    #[inline]
    fn ld(&self) -> usize {
        2 * self.kl + self.ku + 1
    }

    /// Adds `v` to entry (i, j), which must lie in the band (j - ku <= i <= j + kl).
    #[cfg(test)]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            i <= j + self.kl && j <= i + self.ku,
            "({i}, {j}) off the band"
        );
        let ld = self.ld();
        self.ab[self.kl + self.ku + i - j + j * ld] += v;
    }

    /// Index of entry (i, j) of the band (j - ku <= i <= j + kl) in the storage that
    /// [`BandLu::set`] writes; valid until the next [`BandLu::reset`] with other sizes.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        debug_assert!(
            i <= j + self.kl && j <= i + self.ku,
            "({i}, {j}) off the band"
        );
        self.kl + self.ku + i - j + j * self.ld()
    }

    /// Sets the entry at storage index `k` ([`BandLu::index`]) to `v`.
    #[inline]
    pub fn set(&mut self, k: usize, v: f64) {
        self.ab[k] = v;
    }

    /// Factors in place: P A = L U. Fails with [`SingularPivot`] at the first pivot of
    /// magnitude at most `tolerance` max |A_ij| (or not finite); the factor is then
    /// unusable.
    #[cfg(test)]
    pub fn factor(&mut self, tolerance: f64) -> Result<(), SingularPivot> {
        let scale = self.ab[..self.n * self.ld()]
            .iter()
            .fold(0.0f64, |a, v| if v.abs() > a { v.abs() } else { a });
        self.factor_scaled(tolerance, scale)
    }

    /// [`BandLu::factor`] with max |A_ij| given by the caller (`scale`, which it knows
    /// from filling the matrix), saving a pass over the band.
    pub fn factor_scaled(&mut self, tolerance: f64, scale: f64) -> Result<(), SingularPivot> {
        let (n, kl, ku, ld) = (self.n, self.kl, self.ku, self.ld());
        let kv = kl + ku;
        let threshold = tolerance * scale;
        let ab = &mut self.ab;
        // The last column of U touched so far (fill reaches kl + ku beyond the diagonal).
        let mut ju = 0;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let col = j * ld + kv;
            let mut jp = 0;
            let mut best = ab[col].abs();
            for (p, v) in ab[col + 1..=col + km].iter().enumerate() {
                if v.abs() > best {
                    (jp, best) = (p + 1, v.abs());
                }
            }
            self.piv[j] = j + jp;
            // `!(best > ..)` so that NaN fails too.
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !(best > threshold) || !best.is_finite() {
                return Err(SingularPivot { column: j });
            }
            ju = ju.max((j + ku + jp).min(n - 1));
            if jp != 0 {
                // Swap rows j and j + jp in columns j..=ju.
                for c in j..=ju {
                    let base = c * ld + kv + j - c;
                    ab.swap(base, base + jp);
                }
            }
            let inv = 1.0 / ab[col];
            self.inverse[j] = inv;
            if km == 0 {
                continue;
            }
            // Column j's multipliers, then the columns right of it (entry (j, c) of U at
            // c * ld + kv + j - c, below it the rows the multipliers update), which lie
            // beyond col + km in storage: split there.
            let (left, right) = ab.split_at_mut(col + km + 1);
            let multipliers = &mut left[col + 1..];
            for l in multipliers.iter_mut() {
                *l *= inv;
            }
            // Column c = j + 1 + t starts at `first + t * step` in `right`.
            let (first, step) = (col + ld - 1 - (col + km + 1), ld - 1);
            let columns = ju - j;
            match km {
                1 => update::<1>(right, first, step, columns, multipliers),
                2 => update::<2>(right, first, step, columns, multipliers),
                3 => update::<3>(right, first, step, columns, multipliers),
                4 => update::<4>(right, first, step, columns, multipliers),
                5 => update::<5>(right, first, step, columns, multipliers),
                6 => update::<6>(right, first, step, columns, multipliers),
                _ => {
                    for t in 0..columns {
                        let base = first + t * step;
                        let segment = &mut right[base..=base + km];
                        let u = segment[0];
                        if u != 0.0 {
                            for (b, l) in segment[1..].iter_mut().zip(multipliers.iter()) {
                                *b -= l * u;
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves A x = b in place after a successful [`BandLu::factor`].
    pub fn solve(&self, b: &mut [f64]) {
        let (n, kl, ld) = (self.n, self.kl, self.ld());
        let kv = kl + self.ku;
        let ab = &self.ab;
        for j in 0..n {
            let p = self.piv[j];
            if p != j {
                b.swap(p, j);
            }
            let bj = b[j];
            let km = kl.min(n - 1 - j);
            if bj != 0.0 && km > 0 {
                let col = j * ld + kv;
                for (x, l) in b[j + 1..=j + km].iter_mut().zip(&ab[col + 1..=col + km]) {
                    *x -= l * bj;
                }
            }
        }
        for j in (0..n).rev() {
            let col = j * ld + kv;
            let x = b[j] * self.inverse[j];
            b[j] = x;
            let lo = j.saturating_sub(kv);
            if x != 0.0 && lo < j {
                let u = &ab[col - (j - lo)..col];
                for (bi, u) in b[lo..j].iter_mut().zip(u) {
                    *bi -= u * x;
                }
            }
        }
    }
}

/// The elimination of one column's K multipliers `l` from the `columns` columns right of
/// it: in each, whose entry u in the pivot row sits at `first + t * step` of `right` and
/// the K rows below it follow, b -= l u. K fixed at compile time, so that the short inner
/// loop (K <= kl, a few for a chain) is unrolled.
#[inline(always)]
fn update<const K: usize>(right: &mut [f64], first: usize, step: usize, columns: usize, l: &[f64]) {
    let l: [f64; K] = core::array::from_fn(|p| l[p]);
    for t in 0..columns {
        let base = first + t * step;
        let segment = &mut right[base..=base + K];
        let u = segment[0];
        if u != 0.0 {
            for p in 0..K {
                segment[1 + p] -= l[p] * u;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::rows::tests::lcg;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn banded_solves_match_nalgebra_lu_with_pivoting_needed() {
        // Random bands with a zero main diagonal on every third row where both triangles
        // are present (the constraint rows of a KKT matrix): no factorisation without row
        // interchanges exists. A triangular band with a zero diagonal would be singular.
        let mut seed = 0xba4du64;
        let bands = [(1, 0, 0), (7, 1, 2), (20, 3, 1), (40, 4, 4), (33, 0, 3)];
        // Every unrolled width of the elimination (1..=6) and the general one (7).
        let more = [(25, 2, 2), (30, 5, 1), (30, 6, 5), (50, 7, 2)];
        for (n, kl, ku) in bands.into_iter().chain(more) {
            let a = DMatrix::from_fn(n, n, |i, j| {
                if i > j + kl || j > i + ku || (i == j && i % 3 == 2 && kl > 0 && ku > 0) {
                    0.0
                } else if i == j {
                    2.0 + lcg(&mut seed)
                } else {
                    lcg(&mut seed)
                }
            });
            let mut band = BandLu::new(n, kl + ku);
            assert!(band.reset(n, kl, ku));
            for i in 0..n {
                for j in 0..n {
                    if a[(i, j)] != 0.0 {
                        band.add(i, j, a[(i, j)]);
                    }
                }
            }
            band.factor(1e-14).unwrap();
            let b: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
            let want = a
                .clone()
                .lu()
                .solve(&DVector::from_column_slice(&b))
                .unwrap();
            let mut x = b.clone();
            band.solve(&mut x);
            // Both are backward stable: they differ by about cond(A) eps |x|; the
            // residual of ours is the sharper check, below 1e-13 |A| |x|.
            let r = &a * DVector::from_column_slice(&x) - DVector::from_column_slice(&b);
            let scale = a.amax() * x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(
                r.amax() < 1e-13 * scale.max(1.0),
                "n {n}: residual {}",
                r.amax()
            );
            let cond = a.clone().svd(false, false).singular_values;
            let cond = cond.max() / cond.min();
            for i in 0..n {
                assert!(
                    (x[i] - want[i]).abs() < 1e-14 * cond * want.amax().max(1.0),
                    "n {n} kl {kl} ku {ku}: x[{i}] {} vs {}",
                    x[i],
                    want[i]
                );
            }
        }
    }

    #[test]
    fn a_singular_band_is_refused_and_a_band_too_wide_does_not_fit() {
        // Rows 1 and 2 equal: singular.
        let a = [[1.0, 2.0, 0.0], [0.0, 1.0, 1.0], [0.0, 1.0, 1.0]];
        let mut band = BandLu::new(3, 2);
        assert!(band.reset(3, 1, 1));
        for (i, row) in a.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                if v != 0.0 {
                    band.add(i, j, v);
                }
            }
        }
        assert_eq!(band.factor(1e-14), Err(SingularPivot { column: 2 }));
        assert!(!band.reset(3, 2, 1) && !band.reset(4, 1, 1));
        assert_eq!(band.dim(), 3);
    }
}
