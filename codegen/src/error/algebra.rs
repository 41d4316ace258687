//! Errors of the `algebra` stage: building, differentiating and reshaping expressions and
//! symbolic matrices in an [`Arena`](crate::Arena).

/// A request the expression arena or a symbolic matrix cannot carry out. None of these has a
/// place in a declaration: the declaration stage reports its own mistakes with their place
/// ([`DeclarationError`](super::DeclarationError), e.g. `ZeroDivisor` for `x/0` as written).
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum AlgebraError {
    /// A constant divided by the constant 0, or 0 raised to a negative constant power.
    #[error("division by zero in the constant expression `{operation}`")]
    DivisionByZero {
        /// The operation, e.g. `1/0` or `0^-1`.
        operation: String,
    },
    /// A function evaluated outside its domain at a constant argument (e.g. ln(0)).
    #[error("`{function}` is undefined at the constant argument {argument}")]
    Domain {
        /// The function.
        function: &'static str,
        /// The constant argument.
        argument: String,
    },
    /// An expression id that does not belong to the arena it was used with.
    #[error("expression id {id} is not in the arena (which has {len} nodes)")]
    InvalidId {
        /// The id.
        id: u32,
        /// Number of nodes in the arena.
        len: usize,
    },
    /// A symbol handle from another arena.
    #[error("symbol id {id} is not in the arena (which has {symbols} symbols)")]
    UnknownSymbolId {
        /// The handle's index.
        id: u32,
        /// Symbols in the arena.
        symbols: usize,
    },
    /// Matrix operands whose sizes do not fit the operation.
    #[error(
        "matrix size mismatch in {operation}: {left_rows} x {left_cols} and {right_rows} x {right_cols}"
    )]
    Shape {
        /// The operation (`mul`, `add`, ...).
        operation: &'static str,
        /// Rows of the left (or only) operand.
        left_rows: usize,
        /// Columns of the left (or only) operand.
        left_cols: usize,
        /// Rows of the right operand (or the size the operation expects).
        right_rows: usize,
        /// Columns of the right operand (or the size the operation expects).
        right_cols: usize,
    },
    /// A matrix whose data length is not rows x cols.
    #[error("matrix of size {rows} x {cols} has {len} entries")]
    MalformedMatrix {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// Entries found.
        len: usize,
    },
    /// dA/dt by Theorem 1 needs x' for every symbol x of the list.
    #[error("symbol `{name}` has no time derivative")]
    NoTimeDerivative {
        /// The symbol.
        name: String,
    },
    /// d/dt of an expression in an acceleration (a third derivative).
    #[error(
        "the time derivative of an expression in the acceleration `{name}` is not defined (no third derivatives)"
    )]
    ThirdDerivative {
        /// The acceleration symbol.
        name: String,
    },
}
