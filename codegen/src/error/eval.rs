//! Errors of numeric evaluation: the evaluator (`algebra/eval.rs`), the [`Tape`](crate::Tape),
//! the passes' constant folding, and the tables of symbol values the compiler and the
//! emitter check before anything is evaluated.

/// A value that is missing or not finite.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum EvalError {
    /// A symbol has no value in the table the evaluator was given (or no source in the
    /// table a compiled routine or an emitted body reads its symbols from).
    #[error("no value for symbol `{name}`")]
    MissingValue {
        /// The symbol's name.
        name: String,
    },
    /// Numeric evaluation produced a value that is not finite (a division by zero at run time,
    /// ln or sqrt of a negative number, an overflow), or was handed a non-finite input.
    #[error("evaluation of `{operation}` at {arguments} gives a non-finite value")]
    NonFinite {
        /// The operation (`pow`, `ln`, `+`, `*`, a symbol's name, ...).
        operation: String,
        /// The operand values, printed.
        arguments: String,
    },
}
