//! The stages in order, for a whole declaration: tokens ([`crate::syntax::lex`]), the
//! syntax tree ([`crate::syntax::declaration`]), every rule on it ([`crate::mechanics::check`]),
//! the model ([`crate::mechanics::build`]), the rules on the built expressions (whose
//! findings quote the expression in the text form of [`crate::print::text`]). This is the
//! one module that may import every stage; the stages import only earlier ones.

use proc_macro2::{Span, TokenStream};

use crate::algebra::budget::Budget;
use crate::error::{DeclarationError, Error, Location, ParseError, Result};
use crate::mechanics::build::{ParsedModel, build, build_with_values};
use crate::mechanics::check::{ModelFinding, check, check_model};
use crate::mechanics::model::Model;
use crate::print::text::to_text;
use crate::syntax::declaration::{Declaration, parse_declaration_tokens};
use crate::syntax::lex::{Tokens, tokens_from_stream};
use crate::syntax::links::declare_link_coordinates;
use crate::syntax::plain_lex::tokens_from_str;
use crate::syntax::unconstrained::independent_when_unconstrained;

/// An error with the span of the offending token, for a proc-macro to report
/// (`syn::Error::new(e.span, e.message())`).
#[derive(Clone, Debug)]
pub struct SpannedError {
    /// What went wrong (its location is the same place as `span`, as line and column).
    pub error: Error,
    /// The offending token's span (the call site when no token is to blame).
    pub span: Span,
}

impl SpannedError {
    /// The message without the "at line L, column C" part (the span shows the place).
    pub fn message(&self) -> String {
        self.error.message()
    }
}

impl std::fmt::Display for SpannedError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.error.fmt(f)
    }
}

impl std::error::Error for SpannedError {}

/// Parses, checks and builds a declaration from macro input, reporting every error with the
/// span of the offending token.
///
/// # Errors
/// The first syntax error, or else every violated rule (see `check.rs`): unknown symbols,
/// duplicates, rates in the potential or the constraints, `der` of a parameter, an empty
/// `coordinates`, forces or independent values on unknown coordinates, non-constant
/// defaults, a missing `kinetic`, too few independent coordinates; then errors evaluating
/// constants (a division by zero, ln of a negative). More constraint rows than coordinates
/// are allowed (redundant rows): the runtime reports the rank of Phi_q and the mobility.
pub fn parse_declaration(tokens: TokenStream) -> Result<ParsedModel, Vec<SpannedError>> {
    parse_declaration_with(tokens, Budget::default())
}

/// [`parse_declaration`] with the model's arena keeping to `budget` (the macro's, from the
/// environment).
///
/// # Errors
/// As [`parse_declaration`].
pub fn parse_declaration_with(
    tokens: TokenStream,
    budget: Budget,
) -> Result<ParsedModel, Vec<SpannedError>> {
    let toks = tokens_from_stream(tokens);
    let spans = toks.spans();
    let span_of = |e: &Error| {
        e.location()
            .and_then(|l| l.token)
            .and_then(|i| spans.get(i).copied())
    };
    match declare(&toks, budget) {
        Ok(mut parsed) => {
            parsed.spans.tokens = spans.clone();
            Ok(parsed)
        }
        Err(errors) => Err(errors
            .into_iter()
            .map(|error| SpannedError {
                span: span_of(&error).unwrap_or_else(Span::call_site),
                error,
            })
            .collect()),
    }
}

/// Parses, checks and builds a declaration from text (a `.mech` file); errors carry line and
/// column.
///
/// # Errors
/// As [`parse_declaration`]; a text that cannot be split into tokens (unbalanced brackets)
/// is an [`Error::Parse`] at the line and column where the lexer stopped.
pub fn parse_declaration_str(text: &str) -> Result<ParsedModel, Vec<Error>> {
    parse_declaration_str_with(text, Budget::default())
}

/// [`parse_declaration_str`] with the model's arena keeping to `budget`.
///
/// # Errors
/// As [`parse_declaration_str`].
pub fn parse_declaration_str_with(text: &str, budget: Budget) -> Result<ParsedModel, Vec<Error>> {
    let toks = tokens_from_str(text).map_err(|e| vec![e])?;
    declare(&toks, budget)
}

/// Checks the declaration `text` with the parameters and coordinates named in `values`
/// (name, value) at those values instead of their declared defaults and initial guesses:
/// every check that a declared value gets at build time (a body's mass not negative, its
/// inertia physically possible, its orientation a rotation, the constants finite) runs on
/// them. The command-line tool uses it for `--set` and for the assembled state. The kinetic
/// energy's positive semi-definiteness, tested in the derivation, is not repeated here (the
/// caller has M at run time).
///
/// # Errors
/// The first error, with its line and column.
pub fn check_parameter_values(text: &str, values: &[(&str, f64)]) -> Result<(), Error> {
    let toks = tokens_from_str(text)?;
    let d = declaration(&toks)?;
    build_with_values(&d, values).map(|_| ())
}

/// The model declared by macro input; the first error with its span.
///
/// # Errors
/// The first of the errors [`parse_declaration`] reports.
pub fn parse_model(tokens: TokenStream) -> Result<Model, SpannedError> {
    parse_declaration(tokens).map(|p| p.model).map_err(first)
}

/// The model declared by a text (a `.mech` file); the first error, with line and column.
///
/// # Errors
/// The first of the errors [`parse_declaration_str`] reports.
///
/// # Example
/// ```
/// let m = mechanism_codegen::parse_model_str(
///     "/// A pendulum in Cartesian coordinates.
///      pub struct Pendulum;
///      parameters { m = 1.0; l = 0.5; g = 9.81; }
///      coordinates { x = 0.5; y = 0.0; }
///      independent { x = 0.5; der(x) = 0.0; }
///      kinetic = 1/2*m*(der(x)^2 + der(y)^2);
///      potential = m*g*y;
///      constraints { x^2 + y^2 = l^2; }",
/// )
/// .unwrap();
/// assert_eq!((m.coordinates.len(), m.constraints.len()), (2, 1));
/// assert_eq!(m.doc, ["A pendulum in Cartesian coordinates."]);
/// ```
pub fn parse_model_str(text: &str) -> Result<Model, Error> {
    parse_model_str_with(text, Budget::default())
}

/// [`parse_model_str`] with the model's arena keeping to `budget` (the command-line tool's,
/// from the environment): the derivation and compilation of the model keep to it too.
///
/// # Errors
/// As [`parse_model_str`].
pub fn parse_model_str_with(text: &str, budget: Budget) -> Result<Model, Error> {
    let toks = tokens_from_str(text)?;
    declare(&toks, budget).map(|p| p.model).map_err(first)
}

/// [`parse_model_str`] with the parameters and coordinates named in `values` (name, value)
/// at those values instead of their declared defaults and initial guesses: the values that
/// depend on them (later defaults, the `independent` values such as `der(w) = v/r`) follow.
///
/// # Errors
/// As [`parse_model_str`].
pub fn parse_model_str_at(text: &str, values: &[(&str, f64)]) -> Result<Model, Error> {
    let toks = tokens_from_str(text)?;
    let d = declaration(&toks)?;
    if let Some(e) = check(&d).into_iter().next() {
        return Err(e);
    }
    build_with_values(&d, values).map(|p| p.model)
}

fn first<E>(errors: Vec<E>) -> E
where
    E: From<Error>,
{
    errors.into_iter().next().unwrap_or_else(|| {
        let kind = ParseError::Unreadable {
            reason: "no mistake was recorded".to_string(),
        };
        E::from(Error::parse(kind, Location::default()))
    })
}

impl From<Error> for SpannedError {
    fn from(error: Error) -> Self {
        SpannedError {
            error,
            span: Span::call_site(),
        }
    }
}

/// The syntax tree of a declaration, with what its links declare besides their frames
/// (their joints' coordinates: `syntax::links`), and `independent` for a declaration
/// without constraint rows (`syntax::unconstrained`).
fn declaration(tokens: &Tokens) -> Result<Declaration, Error> {
    let mut d = parse_declaration_tokens(tokens)?;
    declare_link_coordinates(&mut d);
    independent_when_unconstrained(&mut d);
    Ok(d)
}

/// Syntax, then every rule, then the model.
fn declare(tokens: &Tokens, budget: Budget) -> Result<ParsedModel, Vec<Error>> {
    let d = declaration(tokens).map_err(|e| vec![e])?;
    let errors = check(&d);
    if !errors.is_empty() {
        return Err(errors);
    }
    let parsed = build(&d, budget).map_err(|e| vec![e])?;
    let errors: Vec<Error> = check_model(&parsed.model, parsed.spans.kinetic)
        .into_iter()
        .map(|f| finding_error(&parsed.model, f))
        .collect();
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(parsed)
}

/// The message of a rule broken by the built expressions, quoting the expression.
fn finding_error(model: &Model, finding: ModelFinding) -> Error {
    match finding {
        ModelFinding::ConstraintWithoutMotion {
            row,
            expr,
            location,
        } => {
            let kind = DeclarationError::ConstraintWithoutMotion {
                row: row + 1,
                simplified: to_text(&model.arena, expr),
            };
            Error::declaration(kind, location)
        }
        // Declared by links, T is theirs: say what the links lack, not how to write T.
        ModelFinding::KineticWithoutRates { location, .. } if model.kinetic_from_links => {
            let kind = DeclarationError::LinksWithoutMovingMass {
                coordinates: model.coordinates.iter().map(|c| c.name.clone()).collect(),
            };
            Error::declaration(kind, location)
        }
        ModelFinding::KineticWithoutRates { expr, location } => {
            let kind = DeclarationError::KineticWithoutRates {
                kinetic: to_text(&model.arena, expr),
            };
            Error::declaration(kind, location)
        }
    }
}
