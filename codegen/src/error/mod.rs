//! Typed errors of the computer-algebra crate: [`Error`](enum@Error), with the kinds of its two
//! declaration variants, [`ParseError`] (the text does not follow the grammar: the `syntax`
//! stage) and [`DeclarationError`] (a rule of the language is broken: the `mechanics`
//! stage). Each variant carries what went wrong and where; its message quotes the user's
//! names.

mod declaration;
mod parse;

use thiserror::Error;

pub use declaration::{
    Constant, ConstantPlace, CoordinatePlace, DeclarationError, NameKind, Needed, Quantity,
    SymbolRole,
};
pub use parse::{Expected, ParseError};

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
    #[error("parse error at {location}: {kind}")]
    Parse {
        /// What was expected or found (boxed, as [`Error::Declaration`]'s kind).
        kind: Box<ParseError>,
        /// Where.
        location: Location,
    },
    /// A call to a function the language does not have.
    #[error(
        "unknown function `{name}` at {location} (known: sin, cos, tan, exp, ln, sqrt, atan2, abs, pow, der; in body and link sections also rot_x, rot_y, rot_z, diag, dot, cross, norm)"
    )]
    UnknownFunction {
        /// The name written.
        name: String,
        /// Where.
        location: Location,
    },
    /// A name that is neither a coordinate, a parameter, nor `t` or `pi` (nor, in a body
    /// section, a body, point or axis).
    #[error("unknown symbol `{name}` at {location}{}", unknown_hint(.suggestion, .known))]
    UnknownSymbol {
        /// The name written.
        name: String,
        /// Where.
        location: Location,
        /// The closest declared name, when one is near (a likely typo).
        suggestion: Option<String>,
        /// The names that exist there, closest to `name` first (the message shows the
        /// first few).
        known: Vec<String>,
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
    /// Numeric evaluation produced a value that is not finite (a division by zero at run time,
    /// ln or sqrt of a negative number, an overflow), or was handed a non-finite input.
    #[error("evaluation of `{operation}` at {arguments} gives a non-finite value")]
    NonFinite {
        /// The operation (`pow`, `ln`, `+`, `*`, a symbol's name, ...).
        operation: String,
        /// The operand values, printed.
        arguments: String,
    },
    /// An expression id that does not belong to the arena it was used with.
    #[error("expression id {id} is not in the arena (which has {len} nodes)")]
    InvalidId {
        /// The id.
        id: u32,
        /// Number of nodes in the arena.
        len: usize,
    },
    /// Matrix operands whose sizes do not fit the operation (or a matrix whose `data` length
    /// is not rows x cols).
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
        /// Rows of the right operand (or the length of `data` for a malformed matrix).
        right_rows: usize,
        /// Columns of the right operand.
        right_cols: usize,
    },
    /// A declaration breaks a rule of the language (a duplicate name, a rate in a constraint,
    /// `der` of a parameter, ...), at the place it was written.
    #[error("{kind} (at {location})")]
    Declaration {
        /// Which rule, and what it found (boxed: some rules carry lists of names, and an
        /// error travels by value through every `Result` of the crate).
        kind: Box<DeclarationError>,
        /// Where.
        location: Location,
    },
    /// A division by an expression that is the constant 0 (`x/0`, `1/(2-2)`), where written.
    #[error("division by zero at {location}: `{divisor}` is the constant 0")]
    ZeroDivisor {
        /// The divisor as written.
        divisor: String,
        /// Where.
        location: Location,
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
    /// A symbol handle from another arena.
    #[error("symbol id {id} is not in the arena (which has {symbols} symbols)")]
    UnknownSymbolId {
        /// The handle's index.
        id: u32,
        /// Symbols in the arena.
        symbols: usize,
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
    /// A model entry that must be a symbol (a coordinate, its rate or acceleration, a
    /// multiplier) is another expression.
    #[error("{role} is not a symbol of the model's arena")]
    NotASymbol {
        /// What the entry is, e.g. "the position of coordinate `x`".
        role: String,
    },
    /// A model with no coordinates.
    #[error("a mechanism needs at least one coordinate")]
    NoCoordinates,
    /// The derivation would need matrices beyond its budget: Khang's dM/dq of n coordinates
    /// has an entry for each (M_ij, q_k) where M_ij depends on q_k.
    #[error(
        "the derivation needs dM/dq with {entries} nonzero entries (an M_ij depending on a q_k) for the {coordinates} coordinates, beyond its budget of {limit}; declare fewer coordinates (each body's or point's own) or raise the budget with the environment variable MECHANISM_MAX_ENTRIES={entries}"
    )]
    DerivationTooLarge {
        /// n.
        coordinates: usize,
        /// The nonzero entries of dM/dq.
        entries: usize,
        /// The budget in entries.
        limit: usize,
    },
    /// The derivation worked beyond its budget ([`crate::Budget::work`]): it stops there,
    /// within the budget's time, instead of running on for hours.
    #[error(
        "the derivation did {work} units of work (building expressions), beyond its budget of {budget}; simplify the declaration (fewer coordinates, bodies declared with their own coordinates, links instead of one long kinetic energy) or raise the budget with the environment variable MECHANISM_MAX_WORK={suggest}",
        suggest = work.saturating_mul(4)
    )]
    WorkTooLarge {
        /// The work done when it stopped.
        work: u64,
        /// The budget.
        budget: u64,
    },
    /// The expressions grew beyond the derivation's budget (see `MAX_SIZE`): the work stops
    /// there, within seconds, instead of exhausting the memory.
    #[error(
        "the derivation's expressions reached {size} nodes and child references, beyond its budget of {budget} (about 190 bytes each at the peak of the derivation); simplify the declaration (fewer chained rotations, bodies declared with their own coordinates) or raise the budget with the environment variable MECHANISM_MAX_SIZE={suggest}",
        suggest = size.saturating_mul(2)
    )]
    ExpressionsTooLarge {
        /// The size reached.
        size: usize,
        /// The budget.
        budget: usize,
    },
    /// The derivation (a derivative's or a product's constant factor) overflowed the range
    /// of f64; the declared expressions themselves were finite.
    #[error(
        "deriving the equations of `{mechanism}` multiplies or adds constants beyond the largest f64 (about 1.8e308): {operation}; rescale the declaration's constants (other units)"
    )]
    DerivationOverflow {
        /// The struct name.
        mechanism: String,
        /// The folding that overflowed, e.g. `2 * 1e308`.
        operation: String,
    },
    /// The number of generalised forces differs from the number of coordinates.
    #[error("{forces} generalised forces given for {coordinates} coordinates")]
    ForceCount {
        /// Forces given.
        forces: usize,
        /// Coordinates.
        coordinates: usize,
    },
    /// An expression depends on a symbol it must not contain (a rate in the potential or a
    /// constraint, an acceleration in T or a force).
    #[error("the {what} must not depend on `{symbol}`")]
    ForbiddenDependence {
        /// The expression's role, e.g. "potential energy".
        what: String,
        /// The symbol it contains.
        symbol: String,
    },
    /// A body quantity (position, orientation, inertia, mass, stiffness) depends on a rate or
    /// an acceleration.
    #[error("the {what} must depend on the coordinates and t only; it contains `{symbol}`")]
    NotPositionLevel {
        /// The quantity, e.g. "mass of body `B1`".
        what: String,
        /// The rate or acceleration it contains.
        symbol: String,
    },
    /// A body's inertia that is not 3 x 3.
    #[error("the inertia of body `{body}` is {rows}x{cols}, not 3x3")]
    InertiaShape {
        /// The body.
        body: String,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// A program output index past the last output.
    #[error("the program has {outputs} outputs, not {wanted}")]
    NoSuchOutput {
        /// Outputs of the program.
        outputs: usize,
        /// The 1-based count asked for.
        wanted: usize,
    },
    /// A role with no compiled routine (a frame past the last, the drawing of a model that
    /// draws nothing).
    #[error("no routine was compiled for the role {role}")]
    NoSuchRoutine {
        /// The role, as `Debug` prints it.
        role: String,
    },
    /// A list of output slots or targets whose length is not the program's output count.
    #[error("{given} {what} for {outputs} outputs")]
    OutputCount {
        /// "output slots" or "output targets for a program with".
        what: &'static str,
        /// Slots or targets given.
        given: usize,
        /// Outputs of the program.
        outputs: usize,
    },
    /// An emission prefix that is not a Rust identifier.
    #[error("register prefix `{prefix}` is not an identifier")]
    RegisterPrefix {
        /// The prefix.
        prefix: String,
    },
    /// More than one output targeted as the body's returned value.
    #[error("at most one output can be the returned value")]
    SeveralReturns,
    /// A returned output that is not 1 x 1.
    #[error("a returned output must be 1 x 1, not {rows} x {cols}")]
    ReturnNotScalar {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// A matrix output targeted as a vector.
    #[error("a {rows} x {cols} output cannot be written as a vector; use a matrix target")]
    MatrixAsVector {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// A list of declaration errors that came back empty (nothing to report).
    #[error("the declaration could not be read")]
    Unreadable,
}

/// Result with the crate's [`Error`](enum@Error).
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Known names an unknown-symbol message lists before `...`.
const KNOWN_SHOWN: usize = 8;

/// `"; did you mean `x`? known: x, y, ..."` for an unknown-symbol message (each part only
/// when there is something to say).
fn unknown_hint(suggestion: &Option<String>, known: &[String]) -> String {
    let mut hint = match suggestion {
        Some(s) => format!("; did you mean `{s}`?"),
        None => String::new(),
    };
    if !known.is_empty() {
        hint.push_str(if suggestion.is_some() {
            " known: "
        } else {
            "; known: "
        });
        hint.push_str(&known[..known.len().min(KNOWN_SHOWN)].join(", "));
        if known.len() > KNOWN_SHOWN {
            hint.push_str(", ...");
        }
    }
    hint
}

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
            Error::UnknownSymbol {
                name,
                suggestion,
                known,
                ..
            } => format!("unknown symbol `{name}`{}", unknown_hint(suggestion, known)),
            Error::UnknownFunction { name, .. } => format!(
                "unknown function `{name}` (known: sin, cos, tan, exp, ln, sqrt, atan2, abs, pow, der; in body and link sections also rot_x, rot_y, rot_z, diag, dot, cross, norm)"
            ),
            Error::ZeroDivisor { divisor, .. } => {
                format!("division by zero: `{divisor}` is the constant 0")
            }
            other => other.to_string(),
        }
    }

    /// Where in the declaration the error is, for the variants that know it.
    pub fn location(&self) -> Option<Location> {
        match self {
            Error::Parse { location, .. }
            | Error::UnknownFunction { location, .. }
            | Error::UnknownSymbol { location, .. }
            | Error::Declaration { location, .. }
            | Error::ZeroDivisor { location, .. } => Some(*location),
            _ => None,
        }
    }
}
