//! The passes that turn matrices of arena expressions into one [`Program`], in their order.
//!
//! 1. Checks: the arena within its size budget, every matrix well formed, every entry a
//!    node of the arena.
//! 2. Factoring (`program::factor`): on a copy of what the outputs reach, sums rewritten by
//!    their most frequent factors (sum_j w_j sin a cos b_j ... becomes
//!    sin a (sum_j w_j cos b_j ...)). Both forms go through the passes below; the one with
//!    fewer operations per call once the parameter-only values are cached is kept, the
//!    derived one on a tie or when a constant of the rewrite overflowed.
//! 3. Instruction selection with common-subexpression elimination (`program::builder`):
//!    one register per distinct subexpression, identical instructions value-numbered,
//!    constants folded, the n-ary forms lowered (the table of `program::cse`).
//! 4. Dead-code elimination (`program::cse`), so that a product counts only its live
//!    readers.
//! 5. Scalings by powers of two moved early (`program::scale`), twice: a scaling moved onto
//!    a product of its own moves on into that product.
//! 6. Products fused with the sums that alone read them (`program::fuse`).
//! 7. Depth-first order from the outputs (`program::schedule`).
//! 8. Dead-code elimination and register renumbering again.
//!
//! Hoisting the parameter-only values of several programs into one cache is the stage's
//! next step, in [`super::compile`].

use crate::algebra::expr::{Arena, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::error::AlgebraError;
use crate::error::{Error, Result};
use crate::program::builder::InstructionSelection;
use crate::program::cse::{Program, compact, named_symbols};
use crate::program::factor::factored_copy;
use crate::program::fuse::fuse_multiply_add;
use crate::program::instructions::Output;
use crate::program::scale::scale_early;
use crate::program::schedule::schedule;

impl Program {
    /// The CSE'd program computing every entry of every matrix in `outputs`: the passes of
    /// this module in order. Its sums are lowered either as derived or factored by their
    /// most frequent factors, whichever needs fewer operations per call once the
    /// parameter-only values are cached; the value is the same up to rounding.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::InvalidId`] for an entry that is not a node of `arena`, [`crate::error::AlgebraError::MalformedMatrix`]
    /// for a matrix whose data length is not rows x cols, [`crate::error::EvalError::NonFinite`] for a constant
    /// subexpression that is not finite.
    ///
    /// # Example
    /// ```
    /// use mechanism_codegen::{Arena, Matrix, Program};
    ///
    /// // sin(u) in one output and cos(u) in another: one sin_cos call for both.
    /// let mut a = Arena::new();
    /// let [p, ..] = a.coordinate("th1");
    /// let [q, ..] = a.coordinate("th2");
    /// let u = a.sub(p, q);
    /// let (s, c) = (a.sin(u), a.cos(u));
    /// let program = Program::new(&a, &[&Matrix::column(vec![s]), &Matrix::column(vec![c])]).unwrap();
    /// let n = program.op_counts();
    /// assert_eq!((n.adds, n.calls, n.total()), (1, 1, 2));
    /// assert_eq!(program.output_op_counts(1).unwrap().total(), 2);
    /// ```
    pub fn new(arena: &Arena, outputs: &[&Matrix]) -> Result<Program> {
        check(arena, outputs)?;
        let plain = lower(arena, outputs)?;
        let (mut local, factored) = factored_copy(arena, outputs);
        if local.take_overflow().is_some() {
            // A constant of the rewrite overflowed (exponents near f64::MAX) and folded to 0
            // there: that form is wrong, the derived one is not.
            return Ok(plain);
        }
        let factored: Vec<&Matrix> = factored.iter().collect();
        let factored = lower(&local, &factored)?;
        Ok(
            if factored.ops_per_call(arena) < plain.ops_per_call(arena) {
                factored
            } else {
                plain
            },
        )
    }
}

/// Pass 1: the arena within its budget, each matrix rows x cols entries of the arena.
fn check(arena: &Arena, outputs: &[&Matrix]) -> Result<()> {
    arena.check_budget()?;
    let len = arena.len();
    for m in outputs {
        if m.rows.checked_mul(m.cols) != Some(m.data.len()) {
            return Err(Error::Algebra(AlgebraError::MalformedMatrix {
                rows: m.rows,
                cols: m.cols,
                len: m.data.len(),
            }));
        }
        if let Some(bad) = m.data.iter().find(|i| i.index() >= len) {
            return Err(Error::Algebra(AlgebraError::InvalidId { id: bad.0, len }));
        }
    }
    Ok(())
}

/// Passes 3 to 8: the lowering of `outputs` (valid entries of `arena`) into a program.
pub(crate) fn lower(arena: &Arena, outputs: &[&Matrix]) -> Result<Program> {
    let mut selection = InstructionSelection::new(arena, outputs);
    selection.run()?;
    let outs: Vec<Output> = outputs
        .iter()
        .map(|m| Output {
            rows: m.rows,
            cols: m.cols,
            entries: m.data.iter().map(|i| selection.op(*i)).collect(),
        })
        .collect();
    let symbols = named_symbols(arena, selection.used_symbols);
    let live = compact(&selection.b.instrs, outs, &symbols);
    let parameter: Vec<bool> = arena
        .symbols()
        .iter()
        .map(|s| s.kind == SymbolKind::Parameter)
        .collect();
    let (instrs, outputs) = live.into_parts();
    let scaled = scale_early(&instrs, &outputs, &parameter);
    let scaled = scale_early(&scaled, &outputs, &parameter);
    let fused = fuse_multiply_add(&scaled, &outputs);
    let scheduled = schedule(&fused, &outputs);
    Ok(compact(&scheduled, outputs, &symbols))
}
