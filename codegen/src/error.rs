//! Typed errors of the computer-algebra crate.

use thiserror::Error;

/// Where in the source an error is: 1-based line and column, and the index of the token
/// (for callers that parsed a token stream and keep the tokens' spans).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Location {
    /// 1-based line.
    pub line: usize,
    /// 1-based column (in characters).
    pub column: usize,
    /// Index of the offending token in the token list the parser read, if known.
    pub token: Option<usize>,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}, column {}", self.line, self.column)
    }
}

/// Everything that can go wrong in parsing, simplifying, differentiating or evaluating.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum Error {
    /// The text does not follow the grammar.
    #[error("parse error at {location}: {message}")]
    Parse {
        /// What was expected or found.
        message: String,
        /// Where.
        location: Location,
    },
    /// A call to a function the language does not have.
    #[error("unknown function `{name}` at {location} (known: sin, cos, tan, exp, ln, sqrt, atan2, abs)")]
    UnknownFunction {
        /// The name written.
        name: String,
        /// Where.
        location: Location,
    },
    /// A name that is neither a coordinate, a parameter, nor `t` or `pi`.
    #[error("unknown symbol `{name}` at {location}")]
    UnknownSymbol {
        /// The name written.
        name: String,
        /// Where.
        location: Location,
    },
    /// A division by (or a negative power of) an expression that simplifies to the constant 0.
    #[error("division by zero")]
    DivisionByZero,
    /// A function evaluated outside its domain at a constant argument (e.g. ln(0)).
    #[error("`{function}` is undefined at the constant argument {argument}")]
    Domain {
        /// The function.
        function: &'static str,
        /// The constant argument.
        argument: String,
    },
    /// A symbol has no value in the table the evaluator was given.
    #[error("no value for symbol `{name}`")]
    MissingValue {
        /// The symbol's name.
        name: String,
    },
    /// The model is inconsistent (a declaration-level error with no single token to blame).
    #[error("{0}")]
    Model(String),
}

/// Result with the crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
