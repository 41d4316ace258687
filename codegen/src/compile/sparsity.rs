//! The structural pattern of M and Phi_q: which entries can be nonzero at some state.
//!
//! An entry of a compiled output is structurally zero when the program writes the constant
//! 0 there: the derivation simplified it to 0 for every t, q, q' and every parameter value
//! (for A02, the N four-bar chain, M is block tridiagonal and each row of Phi_q has at most
//! four nonzeros). Every other entry is in the pattern, whether or not it happens to vanish
//! at a given state. The pattern is read off the final [`Role::Evaluation`] program, the one
//! both back ends run, so it matches what they write entry for entry: the macro emits it
//! into the generated `impl Mechanism` (`SPARSITY`) and the interpreter reads it from
//! [`Routines::sparsity`]; the runtime's large-system solvers then touch only these entries.

use crate::compile::{Role, Routines};
use crate::error::Result;
use crate::mechanics::equations::EvaluationOutput;
use crate::program::instructions::{Operand, Output};

/// The entries of one output matrix that can be nonzero, row-major: (row, column) pairs
/// sorted by row, then column.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Sparsity {
    /// Rows of the matrix.
    pub rows: usize,
    /// Columns of the matrix.
    pub cols: usize,
    /// The structural nonzeros, row-major.
    pub entries: Vec<(usize, usize)>,
}

/// Whether an output entry is structurally zero (the constant 0 written by the program):
/// the one test the pattern and the emitted writes of `OutputTarget`s with `zeroed` share.
pub fn structural_zero(entry: Operand) -> bool {
    entry == Operand::Const(0.0)
}

impl Sparsity {
    /// The pattern of `output`: every entry that is not a structural zero (`structural_zero`).
    pub fn of(output: &Output) -> Sparsity {
        let cols = output.cols.max(1);
        let entries = output
            .entries
            .iter()
            .enumerate()
            .filter(|(_, e)| !structural_zero(**e))
            .map(|(k, _)| (k / cols, k % cols))
            .collect();
        Sparsity {
            rows: output.rows,
            cols: output.cols,
            entries,
        }
    }

    /// The number of structural nonzeros.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when every entry is structurally zero.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

impl Routines {
    /// The structural pattern of the evaluation output `which` (M and Phi_q are the ones the
    /// solvers use), read off the [`Role::Evaluation`] program; for routines of the
    /// constraint rows alone ([`crate::compile_constraints`]), Phi_q's off the
    /// [`Role::ConstraintJacobian`] program.
    ///
    /// # Errors
    /// [`crate::error::ProgramError::NoSuchRoutine`] when the evaluation was not compiled (never for
    /// routines made by [`crate::compile`]), except for Phi_q as above.
    ///
    /// # Example
    /// ```
    /// use mechanism_codegen::{EvaluationOutput, compile, derive, parse_model_str, residual_tangent};
    ///
    /// // Two free particles on a line, coupled by x1 - x0 = 1: M is diagonal, Phi_q = [-1 1].
    /// let mut model = parse_model_str(
    ///     "pub struct Pair;
    ///      coordinates { x0 = 0.0; x1 = 1.0; }
    ///      independent { x0 = 0.0; }
    ///      kinetic = der(x0)^2/2 + der(x1)^2;
    ///      potential = 0;
    ///      constraints { x1 - x0 - 1; }",
    /// )?;
    /// let eqs = derive(&mut model)?;
    /// let tangent = residual_tangent(&mut model, &eqs)?;
    /// let routines = compile(&mut model, &eqs, &tangent)?;
    /// assert_eq!(routines.sparsity(EvaluationOutput::Mass)?.entries, [(0, 0), (1, 1)]);
    /// assert_eq!(routines.sparsity(EvaluationOutput::PhiQ)?.entries, [(0, 0), (0, 1)]);
    /// # Ok::<(), mechanism_codegen::Error>(())
    /// ```
    pub fn sparsity(&self, which: EvaluationOutput) -> Result<Sparsity> {
        let jacobian = self.get(Role::ConstraintJacobian);
        if let (None, Some(program), EvaluationOutput::PhiQ) =
            (self.get(Role::Evaluation), jacobian, which)
        {
            // Routines of the constraint rows alone: Phi_q is the Jacobian's one output.
            return Ok(program
                .outputs()
                .first()
                .map(Sparsity::of)
                .unwrap_or_default());
        }
        let program = self.program(Role::Evaluation)?;
        let k = EvaluationOutput::ORDER
            .iter()
            .position(|o| *o == which)
            .unwrap_or(0);
        Ok(program
            .outputs()
            .get(k)
            .map(Sparsity::of)
            .unwrap_or_default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_lists_the_non_constant_zero_entries_row_major() {
        let o = Output {
            rows: 2,
            cols: 3,
            entries: vec![
                Operand::Const(0.0),
                Operand::Const(2.0),
                Operand::Const(-0.0),
                Operand::Const(0.0),
                Operand::Const(0.0),
                Operand::Const(1.0),
            ],
        };
        let s = Sparsity::of(&o);
        assert_eq!((s.rows, s.cols), (2, 3));
        // -0.0 is the constant zero too.
        assert_eq!(s.entries, [(0, 1), (1, 2)]);
    }
}
