//! Velocity constraint rows that depend on the rows above them: redundant or contradictory.
//!
//! The last k rows of the stacked Jacobian G = [Phi_q; A] are velocity rows
//! A_j q' + a_j = 0. Row j, tested at an assembled configuration q, against the rows B above
//! it (every position row and the velocity rows before j), with b their entries of
//! [Phi_t; a]:
//!
//! ```text
//! rank [B; A_j] = rank B          A_j = c^T B for some c (least squares by SVD)
//!   d = a_j - c^T b = 0            redundant: every q' with B q' = -b satisfies row j
//!   d != 0                         contradictory: no q' satisfies B q' = -b and row j
//! ```
//!
//! Either way row j is refused: a redundant velocity row adds nothing (a time derivative of
//! the position rows, or a repeat, is integrable and belongs in `constraints`), and a
//! contradictory one leaves no consistent rates. Position rows may repeat one another
//! (redundant joints of a loop); velocity rows may not.

use nalgebra::DMatrix;

use crate::algorithms::finite::{check_jacobian, check_rows};
use crate::error::Error;
use crate::linalg::{least_squares, numerical_rank};
use crate::system::Kinematic;

/// |d| above this times the scale max(1, |a_j|, sum_i |c_i b_i|) is a contradiction: the
/// right-hand sides then differ by more than the round-off of forming c^T b (about n ulps
/// of its terms, n <= 1e4 coordinates in practice, so below 1e-12 of the scale).
const MISMATCH: f64 = 1e-9;

/// Checks that no velocity row of `system` at (t, q) is a combination of the rows above it
/// (module docs). `rank_tolerance` is the relative singular-value threshold of the rank
/// tests ([`crate::AssemblyOptions::rank_tolerance`]).
///
/// # Errors
/// For the first dependent velocity row, [`Error::VelocityRowRedundant`] or
/// [`Error::VelocityRowContradicts`], naming it and the rows it is a combination of;
/// [`Error::NonFinite`] for a non-finite entry of Phi_q or Phi_t.
pub(crate) fn check_velocity_rows(
    system: &dyn Kinematic,
    t: f64,
    q: &[f64],
    rank_tolerance: f64,
) -> Result<(), Error> {
    let info = system.info();
    let (n, m, p) = (info.n(), info.m(), info.position_rows());
    if m == p {
        return Ok(());
    }
    let mut g = DMatrix::zeros(m, n);
    let mut rhs = vec![0.0; m];
    system.constraint_jacobian(t, q, &mut g, &mut rhs);
    check_jacobian(&g, info, t, q)?;
    check_rows("Phi_t", &rhs, info, t, q)?;
    for j in p..m {
        let above = g.rows(0, j).into_owned();
        let (rank_above, _) = numerical_rank(&above, rank_tolerance);
        let (rank_with, _) = numerical_rank(&g.rows(0, j + 1).into_owned(), rank_tolerance);
        if rank_with > rank_above {
            continue;
        }
        let row: Vec<f64> = g.row(j).iter().copied().collect();
        let c = least_squares(&above.transpose(), &row, rank_tolerance);
        let combined: f64 = (0..j).map(|i| c[i] * rhs[i]).sum();
        let scale = (0..j)
            .map(|i| (c[i] * rhs[i]).abs())
            .sum::<f64>()
            .max(rhs[j].abs())
            .max(1.0);
        let mismatch = rhs[j] - combined;
        // The rows it combines: the ones with a coefficient that matters.
        let cmax = c.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let of = (0..j)
            .filter(|&i| c[i].abs() > 1e-8 * cmax)
            .map(|i| info.constraint_label(i))
            .collect();
        let row = info.constraint_label(j);
        return Err(if mismatch.abs() > MISMATCH * scale {
            Error::VelocityRowContradicts {
                t,
                row,
                of,
                mismatch,
            }
        } else {
            Error::VelocityRowRedundant { t, row, of }
        });
    }
    Ok(())
}
