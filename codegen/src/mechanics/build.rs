//! From a checked declaration to a [`Model`]: symbols in one arena, constants evaluated,
//! expressions lowered; and the public entry points for macro input and for text.

use proc_macro2::{Span, TokenStream};

use crate::algebra::eval::eval;
use crate::algebra::expr::{Arena, Id, SymbolId, SymbolKind};
use crate::error::{Error, Location, Result};
use crate::mechanics::check::{check, check_model};
use crate::mechanics::model::{Constraint, Coordinate, IndependentSpec, Model, Parameter};
use crate::syntax::declaration::{Declaration, parse_declaration_tokens};
use crate::syntax::expression::{ArenaResolver, Ast, lower};
use crate::syntax::lex::{Tokens, tokens_from_str, tokens_from_stream};

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

impl Error {
    /// The message without the "at line L, column C" part, for callers that show the
    /// place themselves (a span, or `file:line:column:`).
    pub fn message(&self) -> String {
        match self {
            Error::Declaration { message, .. } => message.clone(),
            Error::Parse { message, .. } => format!("parse error: {message}"),
            Error::UnknownSymbol {
                name,
                suggestion: Some(s),
                ..
            } => {
                format!("unknown symbol `{name}`; did you mean `{s}`?")
            }
            Error::UnknownSymbol { name, .. } => format!("unknown symbol `{name}`"),
            Error::UnknownFunction { name, .. } => format!(
                "unknown function `{name}` (known: sin, cos, tan, exp, ln, sqrt, atan2, abs, pow, der)"
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

/// Locations of the parts of a declaration that [`Model`] does not record, and the spans of
/// all tokens, so later stages (derivation, the macro) can point at the user's text.
#[derive(Clone, Debug, Default)]
pub struct ModelSpans {
    /// The span of every token by index ([`Location::token`]); empty for text input.
    pub tokens: Vec<Span>,
    /// The struct name.
    pub name: Location,
    /// The `parameters` keyword, if the section is present.
    pub parameters: Option<Location>,
    /// The `coordinates` keyword.
    pub coordinates: Location,
    /// The `independent` keyword, if present.
    pub independent: Option<Location>,
    /// The `kinetic` keyword.
    pub kinetic: Location,
    /// The `potential` keyword, if present.
    pub potential: Option<Location>,
    /// The `constraints` keyword, if present.
    pub constraints: Option<Location>,
    /// The `forces` keyword, if present.
    pub forces: Option<Location>,
    /// For each coordinate, where its force is declared (`None`: no force, tau_i = 0).
    pub force_entries: Vec<Option<Location>>,
}

impl ModelSpans {
    /// The span of the token at `location` (the call site for text input or no token).
    pub fn span(&self, location: Location) -> Span {
        location
            .token
            .and_then(|i| self.tokens.get(i).copied())
            .unwrap_or_else(Span::call_site)
    }
}

/// A parsed and checked declaration with the locations of its parts.
#[derive(Clone, Debug)]
pub struct ParsedModel {
    /// The model.
    pub model: Model,
    /// Where its parts are.
    pub spans: ModelSpans,
}

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
    let toks = tokens_from_stream(tokens);
    let spans = toks.spans();
    let span_of = |e: &Error| {
        e.location()
            .and_then(|l| l.token)
            .and_then(|i| spans.get(i).copied())
    };
    match declare(&toks) {
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
    let toks = tokens_from_str(text).map_err(|e| vec![e])?;
    declare(&toks)
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
    parse_declaration_str(text).map(|p| p.model).map_err(first)
}

fn first<E>(errors: Vec<E>) -> E
where
    E: From<Error>,
{
    errors
        .into_iter()
        .next()
        .unwrap_or_else(|| E::from(Error::Model("the declaration could not be read".into())))
}

impl From<Error> for SpannedError {
    fn from(error: Error) -> Self {
        SpannedError {
            error,
            span: Span::call_site(),
        }
    }
}

/// Syntax, then every rule, then the model.
fn declare(tokens: &Tokens) -> Result<ParsedModel, Vec<Error>> {
    let d = parse_declaration_tokens(tokens).map_err(|e| vec![e])?;
    let errors = check(&d);
    if !errors.is_empty() {
        return Err(errors);
    }
    let parsed = build(&d).map_err(|e| vec![e])?;
    let errors = check_model(&parsed.model, parsed.spans.kinetic);
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(parsed)
}

/// Lowers `ast` into the arena.
fn lower_at(arena: &mut Arena, ast: &Ast) -> Result<Id> {
    lower(arena, ast, &mut ArenaResolver)
}

/// The value of a constant expression, with parameters at the values known so far.
fn constant(arena: &mut Arena, ast: &Ast, known: &[(SymbolId, f64)], what: &str) -> Result<f64> {
    let id = lower_at(arena, ast)?;
    let env = |s: SymbolId| known.iter().find(|k| k.0 == s).map(|k| k.1);
    eval(arena, id, &env).map_err(|e| Error::Declaration {
        message: format!("{what} cannot be evaluated: {e}"),
        location: ast.location(),
    })
}

/// Builds the model of a checked declaration.
fn build(d: &Declaration) -> Result<ParsedModel> {
    let mut arena = Arena::new();
    let param_items = d.parameters.as_ref().map_or(&[][..], |s| &s.body[..]);
    let coord_items = d.coordinates.as_ref().map_or(&[][..], |s| &s.body[..]);
    let param_syms: Vec<SymbolId> = param_items
        .iter()
        .map(|p| arena.symbol_id(&p.name, SymbolKind::Parameter))
        .collect();
    let coord_ids: Vec<[Id; 3]> = coord_items
        .iter()
        .map(|c| arena.coordinate(&c.name))
        .collect();
    // Time last: products then read `Omega*t`, parameters first.
    let time = arena.symbol("t", SymbolKind::Time);

    let mut known: Vec<(SymbolId, f64)> = Vec::with_capacity(param_items.len());
    let mut parameters = Vec::with_capacity(param_items.len());
    for (p, &s) in param_items.iter().zip(&param_syms) {
        let default = constant(
            &mut arena,
            &p.value,
            &known,
            &format!("the default of `{}`", p.name),
        )?;
        known.push((s, default));
        parameters.push(Parameter {
            name: p.name.clone(),
            symbol: arena.symbol_node(s),
            default,
            location: p.at,
        });
    }

    let mut coordinates = Vec::with_capacity(coord_items.len());
    for (c, ids) in coord_items.iter().zip(&coord_ids) {
        let guess = constant(
            &mut arena,
            &c.value,
            &known,
            &format!("the initial guess of `{}`", c.name),
        )?;
        let [q, qd, qdd] = *ids;
        coordinates.push(Coordinate {
            name: c.name.clone(),
            q,
            qd,
            qdd,
            guess,
            location: c.at,
        });
    }

    let mut independent: Vec<IndependentSpec> = Vec::new();
    for i in d.independent.iter().flat_map(|s| &s.body) {
        let Some(k) = coordinates.iter().position(|c| c.name == i.name) else {
            continue;
        };
        let what = if i.rate {
            format!("the initial rate of `{}`", i.name)
        } else {
            format!("the initial value of `{}`", i.name)
        };
        let v = constant(&mut arena, &i.value, &known, &what)?;
        let spec = match independent.iter_mut().find(|s| s.coordinate == k) {
            Some(s) => s,
            None => {
                let guess = coordinates[k].guess;
                independent.push(IndependentSpec {
                    coordinate: k,
                    position: guess,
                    velocity: 0.0,
                    location: i.at,
                });
                independent
                    .last_mut()
                    .ok_or_else(|| Error::Model("independent list is empty".into()))?
            }
        };
        if i.rate {
            spec.velocity = v;
        } else {
            spec.position = v;
        }
    }

    let (kinetic, kinetic_at) = match &d.kinetic {
        Some(k) => (lower_at(&mut arena, &k.body)?, k.at),
        // Bodies declare T (parse_bodies.rs); `check` rejects a missing T otherwise.
        None => (arena.int(0), d.bodies.first_location().unwrap_or(d.name_at)),
    };
    let potential = match &d.potential {
        Some(p) => lower_at(&mut arena, &p.body)?,
        None => arena.int(0),
    };
    let mut constraints = Vec::new();
    for row in d.constraints.iter().flat_map(|s| &s.body) {
        let lhs = lower_at(&mut arena, &row.lhs)?;
        let expr = match &row.rhs {
            Some(r) => {
                let rhs = lower_at(&mut arena, r)?;
                arena.sub(lhs, rhs)
            }
            None => lhs,
        };
        constraints.push(Constraint {
            expr,
            location: row.at,
            joint: format!("constraint {}", row.statement),
            component: row.component.clone(),
        });
    }
    let zero = arena.int(0);
    let mut forces = vec![zero; coordinates.len()];
    let mut force_entries = vec![None; coordinates.len()];
    for f in d.forces.iter().flat_map(|s| &s.body) {
        if let Some(k) = coordinates.iter().position(|c| c.name == f.name) {
            forces[k] = lower_at(&mut arena, &f.value)?;
            force_entries[k] = Some(f.at);
        }
    }

    let spans = ModelSpans {
        tokens: Vec::new(),
        name: d.name_at,
        parameters: d.parameters.as_ref().map(|s| s.at),
        coordinates: d.coordinates.as_ref().map_or(d.name_at, |s| s.at),
        independent: d.independent.as_ref().map(|s| s.at),
        kinetic: kinetic_at,
        potential: d.potential.as_ref().map(|s| s.at),
        constraints: d.constraints.as_ref().map(|s| s.at),
        forces: d.forces.as_ref().map(|s| s.at),
        force_entries,
    };
    let mut model = Model {
        name: d.name.clone(),
        doc: d.doc.clone(),
        public: d.public,
        arena,
        time,
        parameters,
        coordinates,
        independent,
        kinetic,
        potential,
        constraints,
        forces,
    };
    crate::syntax::bodies::build_bodies(&d.bodies, &mut model)?;
    Ok(ParsedModel { model, spans })
}
