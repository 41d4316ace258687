//! A batch of states through the interpreter: each routine runs the batch's rows side by
//! side, [`LANES`](crate::system::registers) states to a block
//! ([`mechanism_codegen::Tape::execute_lanes`]), so that the tape's operations are decoded
//! once per block instead of once per state. Every row's result is bit for bit what the
//! one-state method ([`System::evaluate`], [`System::inverse_dynamics`],
//! [`System::frame_placement`], [`System::frame_jacobian`]) gives for that row.
//!
//! A batch is given row-major: row i of `q` is `q[i n..(i + 1) n]`, and likewise `qd` and
//! `qdd`; the number of rows is `q.len() / n`. A rate or acceleration slice shorter than
//! `q` gives NaN in the outputs it reaches, as a short slice does for one state. Nothing
//! is allocated per state: each thread keeps one lane register file, grown on its first
//! batch.

#[cfg(doc)]
use crate::system::System;
use crate::system::routine::Values;
use crate::system::{Evaluation, Interpreted};

impl Interpreted {
    /// [`System::evaluate`] at every row of the batch `q`, `qd` (see the module docs): for
    /// each row in order, `sink(row, evaluation)` with the row's evaluation written into
    /// `scratch` (an [`Evaluation::zeros`] of this system's sizes, whose entries outside
    /// M's and Phi_q's patterns stay as they are). Stops at the first error `sink` returns.
    ///
    /// # Errors
    /// The first error of `sink`.
    ///
    /// # Example
    /// ```
    /// use mechanism::{Evaluation, Interpreted, Kinematic, System};
    /// use mechanism::builtin::builtin_source;
    ///
    /// let crank = Interpreted::from_source(builtin_source("spatial_crank_slider").unwrap())?;
    /// let (n, m) = (crank.info().n(), crank.info().m());
    /// let q: Vec<f64> = (0..3 * n).map(|k| 0.1 * k as f64).collect();
    /// let qd: Vec<f64> = (0..3 * n).map(|k| 0.5 - 0.05 * k as f64).collect();
    /// let (mut scratch, mut one) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
    /// crank.evaluate_rows(0.0, &q, &qd, &mut scratch, |row, e| {
    ///     let r = row * n..(row + 1) * n;
    ///     crank.evaluate(0.0, &q[r.clone()], &qd[r], &mut one);
    ///     assert_eq!(e.mass, one.mass); // bit for bit
    ///     assert_eq!(e.gamma, one.gamma);
    ///     Ok::<(), ()>(())
    /// })
    /// .unwrap();
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn evaluate_rows<E>(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        scratch: &mut Evaluation,
        mut sink: impl FnMut(usize, &Evaluation) -> Result<(), E>,
    ) -> Result<(), E> {
        let n = self.info.n();
        let rows = q.len().checked_div(n).unwrap_or(0);
        let values = Values {
            qd,
            ..self.at(t, q)
        };
        self.full
            .execute_rows(&values, n, 0..rows, |first, count, registers| {
                for lane in 0..count {
                    self.lane_scatter.write_lane(registers, lane, scratch);
                    sink(first + lane, scratch)?;
                }
                Ok(())
            })
    }

    /// [`System::inverse_dynamics`] at every row of the batch `q`, `qd`, `qdd` (see the
    /// module docs) into the rows of `out` (n values each; as many rows as `out` holds);
    /// `None` without the robotics routines ([`Interpreted::from_model_with`]).
    pub fn inverse_dynamics_rows(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Option<()> {
        let robotics = self.robotics.as_ref()?;
        robotics.inverse_dynamics_rows(t, q, qd, qdd, out);
        Some(())
    }

    /// The placement of link frame `frame` at every row of the batch `q` into the rows of
    /// `out`, 12 values each: R (the link axes in world axes) row-major, then p, as
    /// [`System::frame_placement`] gives them. `None` without the robotics routines or past
    /// the last frame.
    pub fn frame_placement_rows(&self, frame: usize, q: &[f64], out: &mut [f64]) -> Option<()> {
        self.robotics.as_ref()?.placement_rows(frame, q, out)
    }

    /// The Jacobian J (6 x n, row-major) of link frame `frame` at every row of the batch
    /// `q` into the rows of `out`, 6 n values each, as [`System::frame_jacobian`] gives it.
    /// `None` without the robotics routines or past the last frame.
    pub fn frame_jacobian_rows(&self, frame: usize, q: &[f64], out: &mut [f64]) -> Option<()> {
        self.robotics.as_ref()?.jacobian_rows(frame, q, out)
    }
}
