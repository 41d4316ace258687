//! Balancing of a square matrix by a diagonal similarity (Parlett and Reinsch, Numer. Math.
//! 13, 1969; LAPACK's `dgebal` without its permutations): B = D^-1 A D with D = diag(d),
//! each d_k a power of two, chosen so that row k and column k of B (their off-diagonal
//! entries) have about the same 1-norm.
//!
//! The eigenvalues of B are those of A exactly (a similarity; powers of two scale without
//! round-off), and zero entries stay zero. A state matrix whose variables have very
//! different units (the Whipple bicycle at v = 1e5 m/s: entries from 1 to 2e10) has eigenvalues
//! far smaller than its largest entry; balanced, its norm is about that of its eigenvalues,
//! so round-off relative to the norm is round-off relative to them (the QR iteration's
//! backward error eps ||B|| instead of eps ||A||).

use nalgebra::DMatrix;

/// Sweeps over the rows before balancing stops (each sweep equalises every row and column
/// pair in turn; a few sweeps usually settle it).
const SWEEPS: usize = 100;

/// A sweep rescales row and column k only if it shrinks their summed 1-norm below this
/// fraction of what it was (LAPACK's 0.95: a smaller gain is not worth a sweep).
const GAIN: f64 = 0.95;

/// B = D^-1 A D and d (module docs). A variable whose off-diagonal row or column is zero
/// keeps d_k = 1 (no finite scaling balances it).
pub fn balance(a: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let n = a.nrows();
    let mut b = a.clone();
    let mut d = vec![1.0; n];
    for _ in 0..SWEEPS {
        let mut changed = false;
        for k in 0..n {
            let off = |x: &mut dyn Iterator<Item = f64>| x.map(f64::abs).sum::<f64>();
            let mut c = off(&mut (0..n).filter(|&i| i != k).map(|i| b[(i, k)]));
            let mut r = off(&mut (0..n).filter(|&j| j != k).map(|j| b[(k, j)]));
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let before = c + r;
            let mut f = 1.0;
            while c < r / 2.0 {
                c *= 2.0;
                r /= 2.0;
                f *= 2.0;
            }
            while c >= 2.0 * r {
                c /= 2.0;
                r *= 2.0;
                f /= 2.0;
            }
            if c + r < GAIN * before {
                changed = true;
                d[k] *= f;
                for i in 0..n {
                    b[(i, k)] *= f;
                    b[(k, i)] /= f;
                }
            }
        }
        if !changed {
            break;
        }
    }
    (b, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [1 1e8; 1e-8 1] balances to about [1 1; 1 1], d_0 / d_1 near 1e-8, each d_k a
    /// power of two, and keeps its eigenvalues 0 and 2 (the trace and the product of the
    /// off-diagonal pair are exact).
    #[test]
    fn a_badly_scaled_pair_balances_with_powers_of_two() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 1e8, 1e-8, 1.0]);
        let (b, d) = balance(&a);
        for x in &d {
            assert_eq!(*x, 2f64.powi(x.log2().round() as i32), "{d:?}");
        }
        // Balanced within the factor 2 a power-of-two scaling leaves (either way).
        assert!(
            b[(0, 1)] / b[(1, 0)] <= 4.0 && b[(1, 0)] / b[(0, 1)] <= 4.0,
            "{b}"
        );
        assert_eq!(b.trace(), a.trace());
        assert_eq!(b[(0, 1)] * b[(1, 0)], a[(0, 1)] * a[(1, 0)]);
        // B = D^-1 A D entry by entry.
        for i in 0..2 {
            for j in 0..2 {
                assert_eq!(b[(i, j)], a[(i, j)] * d[j] / d[i]);
            }
        }
    }

    /// A zero column (a structural zero) is left unscaled, and zeros stay zero.
    #[test]
    fn a_zero_column_is_left_alone() {
        let a = DMatrix::from_row_slice(3, 3, &[0.0, 1e6, 0.0, 0.0, 0.0, 1.0, 0.0, -1e-6, 0.0]);
        let (b, d) = balance(&a);
        assert_eq!(d[0], 1.0);
        for (x, y) in a.iter().zip(b.iter()) {
            assert_eq!(*x == 0.0, *y == 0.0);
        }
    }
}
