//! Cholesky factorisation A = L L^T of a dense symmetric positive semi-definite matrix in
//! storage allocated once, dropping the pivots that vanish: the run-time-sized twin of the
//! fixed-size solver's (`fixed::cholesky`), for the augmented-Lagrangian Schur complement
//! of the dynamics' derivatives.

use nalgebra::DMatrix;

/// L of A = L L^T in the lower triangle of its own storage, with `dropped[j]` set where the
/// pivot of row j fell to `drop_below` times the largest diagonal entry of A or less: such
/// a row depends linearly on the rows before it (to that tolerance), its column of L is zero
/// and [`DenseCholesky::solve`] sets its unknown to 0, which for a consistent right-hand
/// side is still a solution.
#[derive(Clone, Debug)]
pub struct DenseCholesky {
    l: DMatrix<f64>,
    dropped: Vec<bool>,
}

impl DenseCholesky {
    /// Storage for k x k matrices.
    pub fn new(k: usize) -> Self {
        Self {
            l: DMatrix::zeros(k, k),
            dropped: vec![false; k],
        }
    }

    /// Factors the lower triangle of `a` (k x k); allocates nothing.
    pub fn factor(&mut self, a: &DMatrix<f64>, drop_below: f64) {
        let k = self.dropped.len();
        self.l.copy_from(a);
        let l = &mut self.l;
        let scale = (0..k).fold(0.0_f64, |s, j| s.max(a[(j, j)]));
        let floor = drop_below * scale;
        for j in 0..k {
            let mut d = l[(j, j)];
            for p in 0..j {
                d -= l[(j, p)] * l[(j, p)];
            }
            if d <= floor || scale <= 0.0 {
                self.dropped[j] = true;
                for i in j..k {
                    l[(i, j)] = 0.0;
                }
                continue;
            }
            self.dropped[j] = false;
            let r = d.sqrt();
            l[(j, j)] = r;
            for i in j + 1..k {
                let mut s = l[(i, j)];
                for p in 0..j {
                    s -= l[(i, p)] * l[(j, p)];
                }
                l[(i, j)] = s / r;
            }
        }
    }

    /// The first dropped row, if any (for a matrix that must be definite).
    pub fn first_dropped(&self) -> Option<usize> {
        self.dropped.iter().position(|&d| d)
    }

    /// x with L L^T x = b, in place in `x` (holding b), the unknowns of dropped rows 0.
    pub fn solve(&self, x: &mut [f64]) {
        let l = &self.l;
        let k = self.dropped.len();
        for i in 0..k {
            if self.dropped[i] {
                x[i] = 0.0;
                continue;
            }
            let mut s = x[i];
            for p in 0..i {
                s -= l[(i, p)] * x[p];
            }
            x[i] = s / l[(i, i)];
        }
        for i in (0..k).rev() {
            if self.dropped[i] {
                continue;
            }
            let mut s = x[i];
            for p in i + 1..k {
                s -= l[(p, i)] * x[p];
            }
            x[i] = s / l[(i, i)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dependent_row_is_dropped_and_a_consistent_system_still_solved() {
        // Rows of J: r0, r1, r0 + r1 (the third is redundant); A = J J^T is singular.
        let j = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.5, 2.0, 1.5, 2.0]);
        let a = &j * j.transpose();
        let mut c = DenseCholesky::new(3);
        c.factor(&a, 1e-12);
        assert_eq!(c.first_dropped(), Some(2));
        let b = &a * nalgebra::DVector::from_row_slice(&[0.3, -1.0, 2.0]);
        let mut x = b.as_slice().to_vec();
        c.solve(&mut x);
        assert_eq!(x[2], 0.0);
        let x = nalgebra::DVector::from_vec(x);
        assert!((&a * x - b).amax() < 1e-13);
        // Refactored with a definite matrix, no row stays dropped.
        let definite = DMatrix::from_row_slice(2, 2, &[4.0, 1.0, 1.0, 3.0]);
        let mut c = DenseCholesky::new(2);
        c.factor(&definite, 1e-12);
        assert_eq!(c.first_dropped(), None);
    }
}
