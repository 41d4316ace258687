//! Typed errors of the computer-algebra crate, one type per stage: [`ParseError`] (the text
//! does not follow the grammar: `syntax`) and [`DeclarationError`] (a rule of the language
//! is broken: `mechanics`), both with their place; [`AlgebraError`] (the arena and symbolic
//! matrices), [`EvalError`] (numeric evaluation), [`BudgetError`] (the derivation's
//! budgets), [`DerivationError`] (a model `derive` cannot take) and [`ProgramError`] (the
//! back end's API). [`Error`](enum@Error) wraps them all. Each variant carries what went
//! wrong and where; its message quotes the user's names.

mod algebra;
mod budget;
mod declaration;
mod declared;
mod derivation;
mod eval;
mod parse;
mod program;

use thiserror::Error;

pub use algebra::AlgebraError;
pub use budget::BudgetError;
pub use declaration::DeclarationError;
pub use declared::{
    Constant, ConstantPlace, CoordinatePlace, NameKind, Needed, Quantity, SymbolRole,
};
pub use derivation::DerivationError;
pub use eval::EvalError;
pub use parse::{Expected, ParseError};
pub use program::ProgramError;

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

/// Everything that can go wrong in codegen, by stage: the declaration's mistakes with their
/// place ([`Error::Parse`], [`Error::Declaration`]), then the algebra, numeric evaluation,
/// the derivation's budgets, the derivation's preconditions on a [`Model`](crate::Model),
/// and requests the back end's API cannot carry out. Each stage's own type converts into
/// it by `From`; no two variants, at any depth, report the same mistake.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum Error {
    /// The text does not follow the grammar (the `syntax` stage).
    #[error("parse error at {location}: {kind}")]
    Parse {
        /// What was expected or found (boxed, as [`Error::Declaration`]'s kind).
        kind: Box<ParseError>,
        /// Where.
        location: Location,
    },
    /// A declaration breaks a rule of the language (an unknown name, a duplicate name, a
    /// rate in a constraint, `der` of a parameter, a division by the constant 0, ...), at
    /// the place it was written (the `mechanics` stage's checks and name resolution).
    #[error("{kind} (at {location})")]
    Declaration {
        /// Which rule, and what it found (boxed: some rules carry lists of names, and an
        /// error travels by value through every `Result` of the crate).
        kind: Box<DeclarationError>,
        /// Where.
        location: Location,
    },
    /// The expression arena or a symbolic matrix cannot carry out a request.
    #[error(transparent)]
    Algebra(#[from] AlgebraError),
    /// A value is missing or not finite in numeric evaluation.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// The derivation would exceed one of its budgets.
    #[error(transparent)]
    Budget(#[from] BudgetError),
    /// A model the derivation cannot take (built by hand), or constants that overflow.
    #[error(transparent)]
    Derivation(#[from] DerivationError),
    /// A request that does not fit a program's outputs or the compiled routines.
    #[error(transparent)]
    Program(#[from] ProgramError),
}

/// Result with the crate's [`Error`](enum@Error).
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// A [`Error::Parse`] of `kind` at `location`.
    pub(crate) fn parse(kind: ParseError, location: Location) -> Error {
        Error::Parse {
            kind: Box::new(kind),
            location,
        }
    }

    /// A [`Error::Declaration`] of `kind` at `location`.
    pub(crate) fn declaration(kind: DeclarationError, location: Location) -> Error {
        Error::Declaration {
            kind: Box::new(kind),
            location,
        }
    }

    /// The message without the "at line L, column C" part, for callers that show the
    /// place themselves (a span, or `file:line:column:`).
    pub fn message(&self) -> String {
        match self {
            Error::Declaration { kind, .. } => kind.to_string(),
            Error::Parse { kind, .. } => format!("parse error: {kind}"),
            other => other.to_string(),
        }
    }

    /// Where in the declaration the error is, for the variants that know it (a
    /// [`Error::Declaration`] about a model built by hand has no place: line 0).
    pub fn location(&self) -> Option<Location> {
        match self {
            Error::Parse { location, .. } | Error::Declaration { location, .. } => {
                Some(*location).filter(|l| l.line > 0)
            }
            _ => None,
        }
    }
}
