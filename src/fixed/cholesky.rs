//! Cholesky factorisation A = L L^T of a small symmetric positive semi-definite matrix, in
//! place, dropping the pivots that vanish: what both the KKT solve and the projections need.

use nalgebra::{SMatrix, SVector};

/// L of A = L L^T (lower triangle; the upper one is left as it was), with `dropped[j]` set
/// where the pivot of row j fell to `drop_below` times the largest diagonal entry of A or
/// less. A dropped row is linearly dependent on the rows before it (to that tolerance): its
/// column of L is zero and [`Cholesky::solve`] sets its unknown to 0, which for a
/// consistent right-hand side is still a solution.
pub(crate) struct Cholesky<const K: usize> {
    l: SMatrix<f64, K, K>,
    dropped: [bool; K],
}

impl<const K: usize> Cholesky<K> {
    /// Factors the lower triangle of `a`.
    pub(crate) fn new(a: SMatrix<f64, K, K>, drop_below: f64) -> Self {
        let mut l = a;
        let mut dropped = [false; K];
        let scale = (0..K).fold(0.0_f64, |s, j| s.max(a[(j, j)]));
        let floor = drop_below * scale;
        for j in 0..K {
            let mut d = l[(j, j)];
            for k in 0..j {
                d -= l[(j, k)] * l[(j, k)];
            }
            if d <= floor || scale <= 0.0 {
                dropped[j] = true;
                for i in j..K {
                    l[(i, j)] = 0.0;
                }
                continue;
            }
            let r = crate::math::sqrt(d);
            l[(j, j)] = r;
            for i in j + 1..K {
                let mut s = l[(i, j)];
                for k in 0..j {
                    s -= l[(i, k)] * l[(j, k)];
                }
                l[(i, j)] = s / r;
            }
        }
        Self { l, dropped }
    }

    /// The first dropped row, if any (for a matrix that must be definite).
    pub(crate) fn first_dropped(&self) -> Option<usize> {
        self.dropped.iter().position(|&d| d)
    }

    /// x with L L^T x = b, the unknowns of dropped rows set to 0.
    pub(crate) fn solve(&self, b: &SVector<f64, K>) -> SVector<f64, K> {
        let l = &self.l;
        let mut x = *b;
        for i in 0..K {
            if self.dropped[i] {
                x[i] = 0.0;
                continue;
            }
            let mut s = x[i];
            for k in 0..i {
                s -= l[(i, k)] * x[k];
            }
            x[i] = s / l[(i, i)];
        }
        for i in (0..K).rev() {
            if self.dropped[i] {
                continue;
            }
            let mut s = x[i];
            for k in i + 1..K {
                s -= l[(k, i)] * x[k];
            }
            x[i] = s / l[(i, i)];
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_definite_system() {
        let a = SMatrix::<f64, 3, 3>::new(4.0, 2.0, 0.6, 2.0, 5.0, 1.0, 0.6, 1.0, 3.0);
        let x = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let c = Cholesky::new(a, 1e-12);
        assert_eq!(c.first_dropped(), None);
        let got = c.solve(&(a * x));
        assert!((got - x).amax() < 1e-14, "{got}");
    }

    #[test]
    fn a_dependent_row_is_dropped_and_the_system_still_solved() {
        // Rows of J: r0, r1, r0 + r1 (the third is redundant); A = J J^T is singular.
        let j = SMatrix::<f64, 3, 2>::new(1.0, 0.0, 0.5, 2.0, 1.5, 2.0);
        let a = j * j.transpose();
        let c = Cholesky::new(a, 1e-12);
        assert_eq!(c.first_dropped(), Some(2));
        // A consistent right-hand side (in the range of A): the solution reproduces it.
        let b = a * SVector::<f64, 3>::new(0.3, -1.0, 2.0);
        let x = c.solve(&b);
        assert_eq!(x[2], 0.0);
        assert!((a * x - b).amax() < 1e-13, "{}", a * x - b);
    }
}
