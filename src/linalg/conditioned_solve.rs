//! The solution of a square, certainly well-conditioned system by LU, where an SVD would
//! give the same answer at several times the cost (assembly outside the step loop).
//!
//! The SVD's least squares truncates singular values below rtol * sigma_max and its rank
//! test counts those above rank_rtol * sigma_max. When the condition number is certainly
//! below both thresholds' inverses neither acts: the SVD returns A^-1 b, which LU with
//! partial pivoting computes in about 2 n^3 flops (the factors and the inverse), where the
//! SVD with both sets of singular vectors takes several times that. The certificate:
//!
//! ```text
//! kappa_2(A) = |A|_2 |A^-1|_2 <= |A|_F |A^-1|_F
//! ```
//!
//! with |A^-1|_F from the LU factors, one solve per column of the identity. A sparse A whose
//! rows and columns reorder into a narrow band (a chain's Phi_v) is factored there
//! ([`SquareBand`]: O(n) to factor, O(n^2) for the bound, where dense LU takes O(n^3)); any
//! other A by the step loop's [`Lu`]. Its `condition_estimate` is not used here, as
//! Hager's estimate is a lower bound of the condition, not a certificate. The bound's
//! relative error is about kappa eps, negligible below the bound accepted here; above it,
//! or for a singular or non-square A, the caller takes the SVD.

use nalgebra::DMatrix;

use super::lu::Lu;
use super::square_band::{Declined, SquareBand};

/// The largest certified condition number accepted (the bound |A|_F |A^-1|_F): far below
/// the inverse of every rank tolerance the solvers use (1e-8 and 1e-10) and of the least
/// squares' truncation (1e-14), and small enough that the computed inverse, with a relative
/// error of about kappa * 1.1e-16, bounds the true one.
pub const MAX_CERTIFIED_CONDITION: f64 = 1e7;

/// x = A^-1 b when A is square and |A|_F |A^-1|_F < `max_condition`; `None` otherwise
/// (not square, a zero or non-finite pivot, or the bound not met). Allocates.
pub fn conditioned_solve(a: &DMatrix<f64>, b: &[f64], max_condition: f64) -> Option<Vec<f64>> {
    let n = a.nrows();
    if n == 0 || a.ncols() != n || b.len() != n {
        return None;
    }
    let factors = match SquareBand::factor(a) {
        Ok(band) => Factors::Band(band),
        Err(Declined::Singular) => return None,
        Err(Declined::Wide) => {
            let mut lu = Lu::new(n);
            lu.matrix_mut().copy_from(a);
            if !lu.factor() {
                return None;
            }
            Factors::Dense(lu)
        }
    };
    // NaN (an overflowing inverse) fails the test too.
    let bound = a.norm() * factors.inverse_norm_squared(n).sqrt();
    if bound.partial_cmp(&max_condition) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let mut x = b.to_vec();
    factors.solve(&mut x, &mut vec![0.0; n]);
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The LU factors of A: in a narrow band after reordering when A is sparse enough
/// ([`SquareBand`]: a chain's Phi_v, O(n) to factor), dense otherwise.
enum Factors {
    Band(SquareBand),
    Dense(Lu),
}

impl Factors {
    /// |A^-1|_F^2, column by column: A^-1 e_j (O(n^2 (2 kl + ku)) in a band, O(n^3)
    /// dense).
    fn inverse_norm_squared(&self, n: usize) -> f64 {
        let (mut column, mut scratch) = (vec![0.0; n], vec![0.0; n]);
        let mut sum = 0.0;
        for j in 0..n {
            column.fill(0.0);
            column[j] = 1.0;
            self.solve(&mut column, &mut scratch);
            sum += column.iter().map(|v| v * v).sum::<f64>();
        }
        sum
    }

    /// x = A^-1 b in place; `scratch` has length n.
    fn solve(&self, x: &mut [f64], scratch: &mut [f64]) {
        match self {
            Factors::Band(band) => band.solve(x, scratch),
            Factors::Dense(lu) => lu.solve(x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::rank_and_least_squares;
    use nalgebra::DVector;

    /// A well-conditioned square system: the answer is the SVD's, to rounding, and the
    /// residual is at round-off.
    #[test]
    fn agrees_with_the_svd_on_a_well_conditioned_system() {
        let n = 40;
        // Diagonally dominant with off-diagonal couplings of both signs: kappa about 3.
        let a = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                4.0 + i as f64 * 0.01
            } else {
                ((i * 7 + j * 3) % 5) as f64 * 0.02 - 0.04
            }
        });
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let x = conditioned_solve(&a, &b, MAX_CERTIFIED_CONDITION).expect("certified");
        let (rank, _, y) = rank_and_least_squares(&a, &b, 1e-10, 1e-14);
        assert_eq!(rank, n);
        for (u, v) in x.iter().zip(&y) {
            assert!((u - v).abs() <= 1e-13 * (1.0 + v.abs()), "{u} vs {v}");
        }
        let r = &a * DVector::from_column_slice(&x) - DVector::from_column_slice(&b);
        assert!(r.amax() <= 1e-14, "residual {}", r.amax());
    }

    /// Declined where the SVD must decide: a rectangular system, a singular one, and one
    /// whose condition (1e9 here, by a graded diagonal) is beyond the bound although LU
    /// solves it.
    #[test]
    fn declines_rectangular_singular_and_ill_conditioned_systems() {
        let b = [1.0, 2.0, 3.0];
        let wide = DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 1.0, 0.0, 1.0, 1.0]);
        assert_eq!(conditioned_solve(&wide, &b[..2], 1e7), None);
        let singular =
            DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0]);
        assert_eq!(conditioned_solve(&singular, &b, 1e7), None);
        let graded = DMatrix::from_diagonal(&DVector::from_column_slice(&[1.0, 1e-4, 1e-9]));
        assert_eq!(conditioned_solve(&graded, &b, 1e7), None);
        // The same graded matrix is accepted under a bound above its condition.
        assert!(conditioned_solve(&graded, &b, 1e10).is_some());
    }

    /// A sparse chain-like system with rows and columns scrambled (the banded route): the
    /// certificate is |A|_F |A^-1|_F exactly (accepted just above it, declined just
    /// below, with the inverse from nalgebra), and the answer is the SVD's.
    #[test]
    fn a_sparse_system_is_certified_by_the_same_bound() {
        let n = 120;
        let (row, column) = (|i: usize| (i * 43 + 7) % n, |j: usize| (j * 77 + 3) % n);
        let mut a = DMatrix::zeros(n, n);
        for i in 0..n {
            a[(row(i), column(i))] = 2.0 + (i as f64 * 0.3).cos();
            if i + 1 < n {
                a[(row(i), column(i + 1))] = -1.5;
            }
        }
        let inverse = a.clone().try_inverse().expect("invertible");
        let bound = a.norm() * inverse.norm();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        assert!(conditioned_solve(&a, &b, bound * (1.0 - 1e-9)).is_none());
        let x = conditioned_solve(&a, &b, bound * (1.0 + 1e-9)).expect("certified");
        let (rank, _, y) = rank_and_least_squares(&a, &b, 1e-10, 1e-14);
        assert_eq!(rank, n);
        for (u, v) in x.iter().zip(&y) {
            assert!((u - v).abs() <= 1e-12 * (1.0 + v.abs()), "{u} vs {v}");
        }
    }
}
