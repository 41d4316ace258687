//! Eigenvalues of a real square matrix (the state matrices of the linearisations) that
//! never panic nor loop: nalgebra's `complex_eigenvalues` indexes `dim - 1` (a panic on a
//! 0 x 0 matrix, which a linearisation whose every variable is a structural zero leaves)
//! and iterates its QR sweeps without a cap (forever on entries near f64::MAX, whose shifts
//! overflow: the matrix is scaled to entries of at most 1 first). The matrix is balanced
//! first (`balance`): the iteration's round-off is then relative to the balanced norm,
//! about that of the eigenvalues, not to the largest entry of a badly scaled matrix.
//!
//! [`relative_residual`] measures how far a number is from being an eigenvalue: the
//! smallest relative change of the balanced matrix that makes it one.

use nalgebra::{Complex, DMatrix, linalg::Schur};

use super::balance::balance;
use crate::error::Error;

/// QR sweeps allowed per row before the Schur form is declared not converged (LAPACK's
/// `dhseqr` allows 30 per row; a well-scaled matrix needs 2 to 4).
const SWEEPS_PER_ROW: usize = 30;

/// The eigenvalues of `a` (none for a 0 x 0 matrix), from its real Schur form.
///
/// # Errors
/// [`Error::Linearization`] naming `what` when an entry is not finite or the iteration
/// does not converge within 30 sweeps per row, or an eigenvalue is beyond the range of
/// f64.
pub fn eigenvalues(a: &DMatrix<f64>, what: &str) -> Result<Vec<Complex<f64>>, Error> {
    let n = a.nrows();
    if n == 0 {
        return Ok(Vec::new());
    }
    if let Some(k) = a.iter().position(|x| !x.is_finite()) {
        return Err(Error::Linearization {
            reason: format!(
                "{what} has the non-finite entry {} at ({}, {})",
                a[k],
                k % n + 1,
                k / n + 1
            ),
        });
    }
    // Eigenvalues of b / s times s, with b = D^-1 a D balanced and s the power of two at or
    // above its largest entry (exact scalings): the iteration's shifts and the 2 x 2
    // blocks' discriminants then cannot overflow, which on entries near 1e300 gave
    // infinite eigenvalues or no end.
    let largest = a.amax();
    let (a, _) = balance(a);
    let largest_balanced = a.amax();
    let scale = if largest_balanced > 0.0 {
        2f64.powi(largest_balanced.log2().ceil() as i32)
    } else {
        1.0
    };
    let schur =
        Schur::try_new(&a / scale, f64::EPSILON, SWEEPS_PER_ROW * n.max(2)).ok_or_else(|| {
            Error::Linearization {
                reason: format!(
                    "the eigenvalues of {what} did not converge (largest entry {largest:e})"
                ),
            }
        })?;
    let values: Vec<Complex<f64>> = schur
        .complex_eigenvalues()
        .iter()
        .map(|z| z * scale)
        .collect();
    if values
        .iter()
        .any(|z| !(z.re.is_finite() && z.im.is_finite()))
    {
        return Err(Error::Linearization {
            reason: format!("an eigenvalue of {what} is beyond the floating-point range"),
        });
    }
    Ok(values)
}

/// How far each of `lambdas` is from being an eigenvalue of `a`: sigma_min(B - lambda I) /
/// sigma_max(B), B = D^-1 a D balanced (`balance`), the smallest change of B relative to
/// its norm (in the 2-norm) that makes lambda an eigenvalue of it, and so of the matrix
/// D (B + E) D^-1 beside `a`. About 1e-16 for an eigenvalue computed by a backward stable
/// method; of order one for a number that is none. For a zero matrix, sigma_min(-lambda I) =
/// |lambda|; for an empty one, infinite (it has no eigenvalue).
pub fn relative_residual(a: &DMatrix<f64>, lambdas: &[Complex<f64>]) -> Vec<f64> {
    let n = a.nrows();
    if n == 0 {
        return vec![f64::INFINITY; lambdas.len()];
    }
    let (b, _) = balance(a);
    let norm = b.clone().singular_values().max();
    let norm = if norm > 0.0 { norm } else { 1.0 };
    lambdas
        .iter()
        .map(|&lambda| {
            let shifted = DMatrix::from_fn(n, n, |i, j| {
                let diagonal = if i == j {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                };
                Complex::new(b[(i, j)], 0.0) - diagonal
            });
            shifted.singular_values().min() / norm
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The companion matrix of (s - 1)(s + 2)(s^2 + 4) = s^4 + s^3 + 2 s^2 + 4 s - 8: its
    /// eigenvalues are the roots 1, -2 and +-2i.
    #[test]
    fn companion_matrix_roots() {
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0, 1.0, 0.0, 0.0, //
                0.0, 0.0, 1.0, 0.0, //
                0.0, 0.0, 0.0, 1.0, //
                8.0, -4.0, -2.0, -1.0,
            ],
        );
        let mut s = eigenvalues(&a, "A").unwrap();
        s.sort_by(|x, y| x.re.total_cmp(&y.re).then(x.im.total_cmp(&y.im)));
        let expected = [(-2.0, 0.0), (0.0, -2.0), (0.0, 2.0), (1.0, 0.0)];
        for (z, (re, im)) in s.iter().zip(expected) {
            assert!(
                (z.re - re).abs() < 1e-12 && (z.im - im).abs() < 1e-12,
                "{s:?}"
            );
        }
    }

    /// A 0 x 0 matrix has no eigenvalues; the nilpotent [0 1; 0 0] (a free mass) has the
    /// double zero.
    #[test]
    fn empty_and_nilpotent() {
        assert!(eigenvalues(&DMatrix::zeros(0, 0), "A").unwrap().is_empty());
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let s = eigenvalues(&a, "A").unwrap();
        assert_eq!(s, vec![Complex::new(0.0, 0.0); 2]);
    }

    /// A NaN entry is named; entries near f64::MAX are scaled: a (1 +- i) of
    /// [a -a; a a] with a = 1e300, to round-off.
    #[test]
    fn non_finite_is_an_error_and_huge_is_scaled() {
        let mut a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
        a[(1, 0)] = f64::NAN;
        let e = eigenvalues(&a, "the state matrix S")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("S has the non-finite entry NaN at (2, 1)"),
            "{e}"
        );
        let huge = DMatrix::from_row_slice(2, 2, &[1e300, -1e300, 1e300, 1e300]);
        let mut s = eigenvalues(&huge, "S").unwrap();
        s.sort_by(|x, y| x.im.total_cmp(&y.im));
        for (z, im) in s.iter().zip([-1e300, 1e300]) {
            assert!(
                (z.re - 1e300).abs() <= 1e285 && (z.im - im).abs() <= 1e285,
                "{s:?}"
            );
        }
    }

    /// The companion matrix of (s - 1)(s + 2)(s^2 + 4) scaled by D A D^-1 with D =
    /// diag(1, 1e8, 1e-8, 1e4) (entries from 1e-16 to 1e16, the eigenvalues unchanged):
    /// balancing recovers the roots to round-off of their own size (1e-12 allows for the
    /// power-of-two balance settling within a factor 2 of the ideal), and their residuals
    /// are at round-off while a number that is no eigenvalue has a residual of order one.
    #[test]
    fn a_badly_scaled_matrix_keeps_its_eigenvalues() {
        let c = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0, 1.0, 0.0, 0.0, //
                0.0, 0.0, 1.0, 0.0, //
                0.0, 0.0, 0.0, 1.0, //
                8.0, -4.0, -2.0, -1.0,
            ],
        );
        let d = [1.0, 1e8, 1e-8, 1e4];
        let a = DMatrix::from_fn(4, 4, |i, j| d[i] * c[(i, j)] / d[j]);
        let mut s = eigenvalues(&a, "A").unwrap();
        s.sort_by(|x, y| x.re.total_cmp(&y.re).then(x.im.total_cmp(&y.im)));
        let expected = [(-2.0, 0.0), (0.0, -2.0), (0.0, 2.0), (1.0, 0.0)];
        for (z, (re, im)) in s.iter().zip(expected) {
            assert!(
                (z.re - re).abs() < 1e-12 && (z.im - im).abs() < 1e-12,
                "{s:?}"
            );
        }
        for r in relative_residual(&a, &s) {
            assert!(r < 1e-14, "{r:e}");
        }
        let none = [Complex::new(-1.0, 0.0), Complex::new(0.0, 1.0)];
        for r in relative_residual(&a, &none) {
            assert!(r > 1e-3, "{r:e}");
        }
    }
}
