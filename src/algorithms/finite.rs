//! Which term of the equations is NaN or infinite, named for the user:
//! `Phi row 2 (constraint 2)`, `M[th1, th2]`, `Phi_q[constraint 1, th3]`, `tau of th1`,
//! `gamma row 1 (revolute(B1, B2, z, z) x)`, for [`Error::NonFiniteTerm`].
//!
//! The solvers test finiteness in one pass, without allocating; only when that test fails do
//! they call these to find the first culprit (which allocates its message). Rows are named
//! by their 1-based number and their label from [`SystemInfo::constraint_label`],
//! coordinates by name.

use nalgebra::DMatrix;

use crate::error::Error;
use crate::system::{Evaluation, SystemInfo};

/// A term entry that is not finite: its name and its value.
type Culprit = (String, f64);

/// `<quantity> of <coordinate>` for the first non-finite entry of a vector over the
/// coordinates (`tau of th1`).
pub(crate) fn coordinate_entry(
    quantity: &str,
    values: &[f64],
    info: &SystemInfo,
) -> Option<Culprit> {
    let i = values.iter().position(|v| !v.is_finite())?;
    Some((format!("{quantity} of {}", coordinate(info, i)), values[i]))
}

/// `<quantity> row k (<label>)` for the first non-finite entry of a vector over the
/// constraint rows (`Phi row 2 (constraint 2)`).
pub(crate) fn row_entry(quantity: &str, values: &[f64], info: &SystemInfo) -> Option<Culprit> {
    let r = values.iter().position(|v| !v.is_finite())?;
    Some((format!("{quantity} {}", row(info, r)), values[r]))
}

/// `M[<coordinate>, <coordinate>]` for the first non-finite entry of the mass matrix.
pub(crate) fn mass_entry(mass: &DMatrix<f64>, info: &SystemInfo) -> Option<Culprit> {
    let (i, j) = first_in(mass)?;
    let name = format!("M[{}, {}]", coordinate(info, i), coordinate(info, j));
    Some((name, mass[(i, j)]))
}

/// `Phi_q[<row label>, <coordinate>]` for the first non-finite entry of the constraint
/// Jacobian.
pub(crate) fn jacobian_entry(phi_q: &DMatrix<f64>, info: &SystemInfo) -> Option<Culprit> {
    let (r, j) = first_in(phi_q)?;
    let name = format!(
        "Phi_q[{}, {}]",
        info.constraint_label(r),
        coordinate(info, j)
    );
    Some((name, phi_q[(r, j)]))
}

/// The first non-finite term of `e` in the order the equations list them (and the
/// interpreter route evaluates them): M, C q', g, tau, Phi, Phi_q, Phi_t, gamma; matrices
/// row by row. The interpreter stops at its first non-finite entry and leaves the later
/// ones NaN, so only this order names the entry that failed.
pub(crate) fn evaluation_entry(e: &Evaluation, info: &SystemInfo) -> Option<Culprit> {
    mass_entry(&e.mass, info)
        .or_else(|| coordinate_entry("C q'", e.coriolis.as_slice(), info))
        .or_else(|| coordinate_entry("g", e.gravity.as_slice(), info))
        .or_else(|| coordinate_entry("tau", e.forces.as_slice(), info))
        .or_else(|| row_entry("Phi", e.phi.as_slice(), info))
        .or_else(|| jacobian_entry(&e.phi_q, info))
        .or_else(|| row_entry("Phi_t", e.phi_t.as_slice(), info))
        .or_else(|| row_entry("gamma", e.gamma.as_slice(), info))
}

/// [`Error::NonFiniteTerm`] for `culprit` at (t, q).
pub(crate) fn term_error((term, value): Culprit, t: f64, q: &[f64]) -> Error {
    Error::NonFiniteTerm {
        term,
        value,
        t,
        q: q.to_vec(),
    }
}

/// Ok when every row of `values` (Phi, Phi_t, gamma at (t, q)) is finite, else
/// [`Error::NonFiniteTerm`] naming the first that is not.
pub(crate) fn check_rows(
    quantity: &str,
    values: &[f64],
    info: &SystemInfo,
    t: f64,
    q: &[f64],
) -> Result<(), Error> {
    match row_entry(quantity, values, info) {
        Some(culprit) => Err(term_error(culprit, t, q)),
        None => Ok(()),
    }
}

/// Ok when every entry of Phi_q at (t, q) is finite, else [`Error::NonFiniteTerm`] naming
/// the first that is not.
pub(crate) fn check_jacobian(
    phi_q: &DMatrix<f64>,
    info: &SystemInfo,
    t: f64,
    q: &[f64],
) -> Result<(), Error> {
    match jacobian_entry(phi_q, info) {
        Some(culprit) => Err(term_error(culprit, t, q)),
        None => Ok(()),
    }
}

/// The error for an evaluation at (t, q, q') that the dynamics found not finite: the state
/// itself when it is not finite, else the first non-finite term of `e`; `fallback` names
/// what was not finite when neither is (a value computed from them).
pub(crate) fn evaluation_error(
    e: &Evaluation,
    info: &SystemInfo,
    (t, q, qd): (f64, &[f64], &[f64]),
    fallback: &str,
) -> Error {
    let state = Error::check_finite(q, "position", &info.coordinates, t)
        .and_then(|()| Error::check_finite(qd, "rate", &info.coordinates, t));
    if let Err(e) = state {
        return e;
    }
    match evaluation_entry(e, info) {
        Some(culprit) => term_error(culprit, t, q),
        None => Error::NonFinite {
            what: fallback.to_string(),
            t,
        },
    }
}

/// The first non-finite entry of `a`, row by row (as `mechanism equations` prints them).
fn first_in(a: &DMatrix<f64>) -> Option<(usize, usize)> {
    let (rows, cols) = a.shape();
    (0..rows)
        .flat_map(|i| (0..cols).map(move |j| (i, j)))
        .find(|&ij| !a[ij].is_finite())
}

fn coordinate(info: &SystemInfo, i: usize) -> &str {
    info.coordinates.get(i).map_or("?", String::as_str)
}

/// `row k (<label>)`, or `row k` alone when the row has no label of its own.
fn row(info: &SystemInfo, r: usize) -> String {
    let (number, label) = (format!("row {}", r + 1), info.constraint_label(r));
    if label == number {
        number
    } else {
        format!("{number} ({label})")
    }
}
