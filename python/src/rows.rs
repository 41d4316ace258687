//! The batch side of `Model`'s per-state methods (`methods.rs`): a piece of rows at once
//! through the library's rows methods ([`mechanism::Interpreted::evaluate_rows`] and the
//! robotics `*_rows`), which run the interpreter's tape on 16 states side by side. Each
//! row's answer is bit for bit the one-state call's: the rows methods give the one-state
//! tape's bits, and what is done with an evaluation here is what the one-state path does.

use mechanism::Evaluation;

use crate::batch::{PyErrLater, later};
use crate::effort::WithEffort;
use crate::errors::SolverError;
use crate::model::Model;
use crate::scratch::with_scratch;

/// A failure at a row of a piece.
pub type Failed = (usize, PyErrLater);

/// The error of a frame method on a system without frame routines.
pub fn no_frames() -> PyErrLater {
    PyErrLater::new(SolverError::new_err, "no frame routines")
}

impl Model {
    /// Evaluates the rows of `q`, `qd` (n values each) side by side and calls
    /// `write(row, evaluation, answer)` for each row with its `width` values of `out`,
    /// using this thread's evaluation buffers.
    ///
    /// # Errors
    /// The first error of `write`, with its row.
    pub(crate) fn evaluate_rows(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        width: usize,
        out: &mut [f64],
        mut write: impl FnMut(usize, &Evaluation, &mut [f64]) -> Result<(), PyErrLater>,
    ) -> Result<(), Failed> {
        with_scratch(self, |scratch, _| {
            self.system.evaluate_rows(t, q, qd, scratch, |row, e| {
                let answer = &mut out[row * width..(row + 1) * width];
                write(row, e, answer).map_err(|err| (row, err))
            })
        })
    }
}

/// The accelerations of each row of the piece `s` (q, v, tau; n values each) into `out`:
/// the rows' evaluations side by side, then for each the library's augmented solve, handed
/// the row's evaluation with the effort added to the forces ([`Evaluated`]), as the
/// one-state path hands it the system with the effort added.
///
/// # Errors
/// The first row whose solve fails, with the library's error.
pub fn forward_dynamics_rows(
    model: &Model,
    t: f64,
    s: &[&[f64]],
    out: &mut [f64],
) -> Result<(), Failed> {
    let n = mechanism::Kinematic::info(model.system.as_ref()).n();
    with_scratch(model, |scratch, dynamics| {
        model
            .system
            .evaluate_rows(t, s[0], s[1], scratch, |row, e| {
                let r = row * n..(row + 1) * n;
                let system = WithEffort::evaluated(model.system.as_ref(), e, &s[2][r.clone()]);
                dynamics
                    .solve(&system, t, &s[0][r.clone()], &s[1][r.clone()])
                    .map_err(|err| (row, later(err)))?;
                out[r].copy_from_slice(dynamics.accelerations());
                Ok(())
            })
    })
}
