//! The structural zeros of a state matrix S computed in floating point, and whether its
//! eigenvalues can be trusted ([`crate::algorithms::steady`]).
//!
//! A column that is zero in exact arithmetic (a cyclic coordinate's) holds round-off: eps
//! times the terms its entries were computed from, which grow with the largest entries of
//! their row (the bicycle's yaw column at v = 1e5 m/s holds 1e-6 beside entries of 2e10 that
//! carry v^2, 0.7 eps of them). An entry S_ij is taken as zero when
//!
//! ```text
//! |S_ij| <= tol * max(1, max_k |S_ik|, max_k |S_kj|)        (tol = 1e-12 by default)
//! ```
//!
//! a test that follows each row's and column's own scale (the lean angle's row, its rate
//! with coefficient 1, is no zero beside the 2e10 of other rows, which a test against the
//! whole matrix's largest entry took it for).
//!
//! Round-off cannot be told from a term that decides the motion when the two are of one
//! size: the bicycle's gravity terms (10 1/s^2) lie at 1e-13 of their rows at v = 1e7
//! m/s and at 1e-17 at v = 1e9, below the round-off of the yaw column beside them. The
//! linearisation is refused, with the reason, where
//! - the structural zeros change when the tolerance is made 1000 times smaller (an entry
//!   between 1e-15 and 1e-12 of its row or column: round-off and terms of the motion both
//!   fall there);
//! - the entries of S without its structural zeros span more than 1e15 (a term below
//!   1e-15 of its row's largest is below double precision's resolution, 2.2e-16, with the
//!   margin round-off takes through the solves);
//! - an eigenvalue printed, with or without the structural zeros (and 0 if there are
//!   any), is no eigenvalue of S: its relative residual sigma_min(B - lambda I) /
//!   sigma_max(B) on S balanced ([`crate::linalg::relative_residual`]) is above 1e-8.

use nalgebra::{Complex, DMatrix};

use crate::error::Error;
use crate::linalg::relative_residual;

/// How much smaller the tolerance of the second classification is (module docs).
const STRICTER: f64 = 1e-3;

/// The largest spread max |S_ij| / min |S_ij| over the nonzero entries of S without its
/// structural zeros (module docs).
const MAX_SPREAD: f64 = 1e15;

/// The largest relative residual allowed of an eigenvalue printed: a backward stable one has
/// about 1e-16, and removing the structural zeros adds the round-off entries removed. A
/// variable removed wrongly (the bicycle's lean at v = 1e5 m/s under a test against the
/// whole matrix) leaves eigenvalues with residuals of 0.05 to 0.2.
const RESOLVED: f64 = 1e-8;

/// The variables of S that are not structural (module docs): those left when every
/// variable whose column or row of S is zero is removed. Removing one can make another's
/// row or column zero (psi's column holds the rates of x and y only): repeated until none
/// is found.
///
/// # Errors
/// [`Error::Linearization`] when the variables kept depend on the tolerance (1000 times
/// smaller), or the entries of S without them span more than 1e15; `names` name them.
pub fn kept_variables(
    state: &DMatrix<f64>,
    names: &[String],
    tolerance: f64,
) -> Result<Vec<usize>, Error> {
    let kept = peel(state, tolerance);
    let strict = peel(state, tolerance * STRICTER);
    let undecided: Vec<&str> = strict
        .iter()
        .filter(|j| !kept.contains(j))
        .map(|&j| names[j].as_str())
        .collect();
    if !undecided.is_empty() {
        return Err(unresolved(format!(
            "the columns or rows of {} hold entries between {:.0e} and {tolerance:.0e} of \
             the largest entries beside them, where round-off of those and the terms that \
             decide the motion both fall: whether they give structural zero eigenvalues \
             cannot be told",
            undecided.join(", "),
            tolerance * STRICTER
        )));
    }
    let reduced = state.select_rows(&kept).select_columns(&kept);
    let nonzero = || reduced.iter().filter(|x| **x != 0.0).map(|x| x.abs());
    let (smallest, largest) = (
        nonzero().fold(f64::INFINITY, f64::min),
        nonzero().fold(0.0, f64::max),
    );
    if largest > MAX_SPREAD * smallest {
        return Err(unresolved(format!(
            "without its structural zeros the state matrix S has entries from \
             {smallest:.1e} to {largest:.1e}, a spread beyond the {MAX_SPREAD:.0e} that \
             double precision resolves: round-off of the largest terms reaches the smallest"
        )));
    }
    Ok(kept)
}

/// The variables left by removing zero rows and columns, entries zero at `tolerance`.
fn peel(state: &DMatrix<f64>, tolerance: f64) -> Vec<usize> {
    let d = state.ncols();
    let rows: Vec<f64> = (0..d).map(|i| state.row(i).amax()).collect();
    let cols: Vec<f64> = (0..d).map(|j| state.column(j).amax()).collect();
    let zero =
        |i: usize, j: usize| state[(i, j)].abs() <= tolerance * rows[i].max(cols[j]).max(1.0);
    let mut kept: Vec<usize> = (0..d).collect();
    loop {
        let found: Vec<usize> = kept
            .iter()
            .copied()
            .filter(|&j| kept.iter().all(|&i| zero(i, j)) || kept.iter().all(|&k| zero(j, k)))
            .collect();
        if found.is_empty() {
            return kept;
        }
        kept.retain(|j| !found.contains(j));
    }
}

/// Every eigenvalue of the state matrix `state` found (`eigenvalues`, and `reduced`, those
/// without the structural zeros), and 0 if there are structural zeros (`structural`), must
/// be an eigenvalue of S within [`RESOLVED`] (module docs).
///
/// # Errors
/// [`Error::Linearization`] naming the eigenvalue and its residual otherwise.
pub fn check_resolved(
    state: &DMatrix<f64>,
    eigenvalues: &[Complex<f64>],
    reduced: &[Complex<f64>],
    structural: bool,
) -> Result<(), Error> {
    let zero = [Complex::new(0.0, 0.0)];
    let zero = if structural { &zero[..] } else { &[][..] };
    let candidates: Vec<Complex<f64>> = reduced
        .iter()
        .chain(eigenvalues)
        .chain(zero)
        .copied()
        .collect();
    let residuals = relative_residual(state, &candidates);
    let worst = residuals
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1));
    match worst {
        Some((k, r)) if r > RESOLVED => Err(unresolved(format!(
            "{:.6e} {:+.6e} i, found as an eigenvalue, is none of the state matrix S \
             (relative residual {r:.1e})",
            candidates[k].re, candidates[k].im
        ))),
        _ => Ok(()),
    }
}

fn unresolved(what: String) -> Error {
    Error::Linearization {
        reason: format!(
            "its eigenvalues cannot be resolved in double precision: {what}. The scales are \
             too far apart (a speed or rate far beyond the mechanism's own?): linearise at \
             smaller ones"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|k| format!("z{k}")).collect()
    }

    /// z0' = z1, z1' = -z0 + 1e10 z2 + noise z3, z2' = z1, z3' = z2: z3's column holds only
    /// round-off of row 1 (1e-16 of it: zero), z0's row holds 1 beside the 1e10 of row 1
    /// (not zero: its own row's scale is 1), so z3 alone is structural.
    #[test]
    fn round_off_is_told_from_a_small_row() {
        let s = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0, 1.0, 0.0, 0.0, //
                -1.0, 0.0, 1e10, 1e-6, //
                0.0, 1.0, 0.0, 0.0, //
                0.0, 0.0, 1.0, 0.0,
            ],
        );
        assert_eq!(kept_variables(&s, &names(4), 1e-12).unwrap(), vec![0, 1, 2]);
    }

    /// The same with the coupling z0 -> z1 at 1e-13 of row 1: between the two tolerances,
    /// refused and named.
    #[test]
    fn an_entry_at_round_off_level_is_refused() {
        let s = DMatrix::from_row_slice(
            3,
            3,
            &[
                0.0, 1.0, 0.0, //
                -1e-3, 0.0, 1e10, //
                0.0, 1.0, 0.0,
            ],
        );
        let e = kept_variables(&s, &names(3), 1e-12)
            .unwrap_err()
            .to_string();
        assert!(e.contains("the columns or rows of z0 hold entries"), "{e}");
    }

    /// Two oscillators apart, of 1 and 1e16 rad/s: every entry is the largest of its row
    /// and column, but a QR sweep over the whole matrix resolves eigenvalues only to eps
    /// times 1e16 = 2 rad/s, the size of the slow pair: refused for the spread.
    #[test]
    fn a_spread_beyond_double_precision_is_refused() {
        let mut s = DMatrix::zeros(4, 4);
        s[(0, 1)] = 1.0;
        s[(1, 0)] = -1.0;
        s[(2, 3)] = 1e16;
        s[(3, 2)] = -1e16;
        let e = kept_variables(&s, &names(4), 1e-12)
            .unwrap_err()
            .to_string();
        assert!(e.contains("a spread beyond the 1e15"), "{e}");
        s[(2, 3)] = 1e8;
        s[(3, 2)] = -1e8;
        assert_eq!(
            kept_variables(&s, &names(4), 1e-12).unwrap(),
            vec![0, 1, 2, 3]
        );
    }
}
