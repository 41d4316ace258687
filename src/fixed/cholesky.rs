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

    /// X with L L^T X = B for the C columns of `b` at once (each as [`Cholesky::solve`]).
    /// The substitutions run on the rows of X (the columns of X^T, contiguous): each step is
    /// one multiply-add over C independent values, which the compiler vectorises; a zero
    /// entry of L (between the branches of a tree's M, a quadruped's legs) skips its step.
    pub(crate) fn solve_columns<const C: usize>(
        &self,
        b: &SMatrix<f64, K, C>,
    ) -> SMatrix<f64, K, C> {
        let l = &self.l;
        let mut xt = b.transpose();
        let y = xt.as_mut_slice();
        for i in 0..K {
            let (done, rest) = y.split_at_mut(i * C);
            let row = &mut rest[..C];
            if self.dropped[i] {
                row.fill(0.0);
                continue;
            }
            for k in 0..i {
                let lik = l[(i, k)];
                if lik != 0.0 {
                    let known = &done[k * C..(k + 1) * C];
                    row.iter_mut().zip(known).for_each(|(x, v)| *x -= lik * v);
                }
            }
            let inv = 1.0 / l[(i, i)];
            row.iter_mut().for_each(|x| *x *= inv);
        }
        for i in (0..K).rev() {
            if self.dropped[i] {
                continue;
            }
            let (head, known) = y.split_at_mut((i + 1) * C);
            let row = &mut head[i * C..];
            for k in i + 1..K {
                let lki = l[(k, i)];
                if lki != 0.0 {
                    let v = &known[(k - i - 1) * C..(k - i) * C];
                    row.iter_mut().zip(v).for_each(|(x, v)| *x -= lki * v);
                }
            }
            let inv = 1.0 / l[(i, i)];
            row.iter_mut().for_each(|x| *x *= inv);
        }
        xt.transpose()
    }

    /// A^-1 of a definite A (no row dropped), exactly symmetric: W = L^-1 by forward
    /// substitution (W is lower triangular: K^3/6 multiply-adds), then
    /// (A^-1)_ij = sum over k >= max(i, j) of W_ki W_kj for the lower triangle, mirrored
    /// (K^3/6 more): a third of the K^3 of solving for the K columns of the identity.
    pub(crate) fn inverse(&self) -> SMatrix<f64, K, K> {
        let l = &self.l;
        let mut w = SMatrix::<f64, K, K>::zeros();
        for j in 0..K {
            w[(j, j)] = 1.0 / l[(j, j)];
            for i in j + 1..K {
                let mut s = 0.0;
                for k in j..i {
                    s -= l[(i, k)] * w[(k, j)];
                }
                w[(i, j)] = s / l[(i, i)];
            }
        }
        let mut inverse = SMatrix::<f64, K, K>::zeros();
        for j in 0..K {
            for i in j..K {
                let mut s = 0.0;
                for k in i..K {
                    s += w[(k, i)] * w[(k, j)];
                }
                inverse[(i, j)] = s;
                inverse[(j, i)] = s;
            }
        }
        inverse
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
        // The inverse: symmetric to the bit, and A A^-1 = 1 to round-off.
        let inverse = c.inverse();
        assert_eq!(inverse, inverse.transpose());
        assert!((a * inverse - SMatrix::<f64, 3, 3>::identity()).amax() < 1e-14);
        // Several right-hand sides at once: the same solutions, column by column.
        let b = SMatrix::<f64, 3, 2>::from_columns(&[a * x, a * (x * 2.0)]);
        let both = c.solve_columns(&b);
        assert!((both.column(0) - x).amax() < 1e-14);
        assert!((both.column(1) - x * 2.0).amax() < 1e-14);
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
