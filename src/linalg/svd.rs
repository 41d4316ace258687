//! Rank and least squares by the singular value decomposition, for checks and assembly
//! outside the step loop (they allocate).

use nalgebra::{DMatrix, Dyn, SVD};

/// Numerical rank of `a` by singular values: the count of sigma_i > rtol * sigma_max
/// (and above an absolute floor of 1e-300). Uses an SVD, so it allocates: call it outside
/// the step loop. Returns the rank and the singular values in decreasing order.
pub fn numerical_rank(a: &DMatrix<f64>, rtol: f64) -> (usize, Vec<f64>) {
    if a.nrows() == 0 || a.ncols() == 0 {
        return (0, Vec::new());
    }
    ranked(&a.clone().svd(false, false), rtol)
}

/// The rank of [`numerical_rank`] and the singular values in decreasing order, from `svd`.
fn ranked(svd: &SVD<f64, Dyn, Dyn>, rtol: f64) -> (usize, Vec<f64>) {
    let mut s: Vec<f64> = svd.singular_values.iter().copied().collect();
    s.sort_by(|x, y| y.total_cmp(x));
    let smax = s.first().copied().unwrap_or(0.0);
    let rank = s.iter().filter(|&&v| v > rtol * smax && v > 1e-300).count();
    (rank, s)
}

/// [`numerical_rank`] (with `rank_rtol`) and [`least_squares`] (with `rtol`) of the same
/// A and b from one SVD: the rank, the singular values, x. Allocates.
pub fn rank_and_least_squares(
    a: &DMatrix<f64>,
    b: &[f64],
    rank_rtol: f64,
    rtol: f64,
) -> (usize, Vec<f64>, Vec<f64>) {
    if a.nrows() == 0 || a.ncols() == 0 {
        return (0, Vec::new(), vec![0.0; a.ncols()]);
    }
    let svd = a.clone().svd(true, true);
    let (rank, s) = ranked(&svd, rank_rtol);
    (rank, s, solved(&svd, b, rtol))
}

/// Minimum-norm least-squares solution x of A x = b by SVD, treating singular values below
/// rtol * sigma_max as zero. Allocates; for assembly and other work outside the step loop.
pub fn least_squares(a: &DMatrix<f64>, b: &[f64], rtol: f64) -> Vec<f64> {
    if a.nrows() == 0 || a.ncols() == 0 {
        return vec![0.0; a.ncols()];
    }
    solved(&a.clone().svd(true, true), b, rtol)
}

/// The solution of [`least_squares`] from the SVD of A (with both singular vectors).
fn solved(svd: &SVD<f64, Dyn, Dyn>, b: &[f64], rtol: f64) -> Vec<f64> {
    let smax = svd.singular_values.max();
    let eps = (rtol * smax).max(1e-300);
    let rhs = nalgebra::DVector::from_column_slice(b);
    match svd.solve(&rhs, eps) {
        Ok(x) => x.iter().copied().collect(),
        Err(_) => vec![0.0; svd.v_t.as_ref().map_or(0, |v| v.ncols())],
    }
}
