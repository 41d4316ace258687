//! Name resolution of scalar expressions: a [`crate::syntax`] [`Ast`] becomes the canonical
//! [`Arena`] node it denotes. Names resolve through a [`Resolver`] (the arena's symbol table,
//! or a body section's points and axes); `der(x)` and `der2(x)` become the rate and
//! acceleration symbols of coordinate x; sums and products are built with one n-ary
//! constructor call each, so the node is the arena's canonical form of the whole chain.

use crate::algebra::expr::{Arena, Func, Id, SymbolKind};
use crate::error::AlgebraError;
use crate::error::{DeclarationError, Error, Expected, Location, ParseError, Result, SymbolRole};
use crate::syntax::ast::Ast;
use crate::syntax::expression::{Language, parse};
use crate::syntax::lex::{Cursor, Tok};
use crate::syntax::plain_lex::tokens_from_str;
use crate::syntax::spelling::{closest, ranked};

/// How names resolve while building the node of a syntax tree.
pub(crate) trait Resolver {
    /// The node of the name `name` written at `at` (`pi` never reaches the resolver).
    fn name(&mut self, arena: &mut Arena, name: &str, at: Location) -> Result<Id>;
    /// The node of `der(name)` (`order` 1) or `der2(name)` (`order` 2).
    fn rate(&mut self, arena: &mut Arena, name: &str, order: usize, at: Location) -> Result<Id>;
}

/// Resolution through the arena's symbol table: declared symbols by name, `t` (created as
/// time if absent), `pi`; `der(x)` and `der2(x)` for coordinates x.
pub(crate) struct ArenaResolver;

impl Resolver for ArenaResolver {
    fn name(&mut self, arena: &mut Arena, name: &str, at: Location) -> Result<Id> {
        if let Some(s) = arena.lookup(name) {
            return Ok(arena.symbol_node(s));
        }
        match name {
            "pi" => Ok(arena.pi()),
            "t" => Ok(arena.symbol("t", SymbolKind::Time)),
            _ => Err(unknown_symbol(name, at, &arena_names(arena))),
        }
    }

    fn rate(&mut self, arena: &mut Arena, name: &str, order: usize, at: Location) -> Result<Id> {
        let Some(s) = arena.lookup(name) else {
            // Reports the unknown name (with its suggestion).
            self.name(arena, name, at)?;
            return Err(der_error(name, SymbolRole::NotACoordinate, at));
        };
        let info = arena.symbol_info(s);
        if info.kind != SymbolKind::Coordinate {
            return Err(der_error(name, role(info.kind), at));
        }
        let mut d = s;
        for _ in 0..order {
            match arena.symbol_info(d).derivative {
                Some(next) => d = next,
                None => return Err(der_error(name, SymbolRole::CoordinateWithoutRate, at)),
            }
        }
        Ok(arena.symbol_node(d))
    }
}

/// The names an expression may use in `arena`: its symbols but rates and accelerations
/// (written `der(x)`, `der2(x)`), then `t` and `pi`.
pub(crate) fn arena_names(arena: &Arena) -> Vec<&str> {
    let symbols = arena
        .symbols()
        .iter()
        .filter(|s| !matches!(s.kind, SymbolKind::Velocity | SymbolKind::Acceleration))
        .map(|s| s.name.as_str());
    let mut names: Vec<&str> = symbols.collect();
    for builtin in ["t", "pi"] {
        if !names.contains(&builtin) {
            names.push(builtin);
        }
    }
    names
}

/// The error for the unknown name `name` at `at`, among the names `known` (in the order to
/// list them when equally close).
pub(crate) fn unknown_symbol(name: &str, at: Location, known: &[&str]) -> Error {
    let kind = DeclarationError::UnknownSymbol {
        name: name.to_string(),
        suggestion: closest(name, known.iter().copied()),
        known: ranked(name, known.iter().copied()),
    };
    Error::declaration(kind, at)
}

/// What a symbol of kind `kind` is, for messages.
fn role(kind: SymbolKind) -> SymbolRole {
    match kind {
        SymbolKind::Coordinate => SymbolRole::Coordinate,
        SymbolKind::Velocity => SymbolRole::Rate,
        SymbolKind::Acceleration => SymbolRole::Acceleration,
        SymbolKind::Parameter => SymbolRole::Parameter,
        SymbolKind::Time => SymbolRole::Time,
        SymbolKind::Free => SymbolRole::NotACoordinate,
    }
}

/// "der() takes a coordinate; `m1` is a parameter".
fn der_error(name: &str, role: SymbolRole, at: Location) -> Error {
    let kind = DeclarationError::RateOfNonCoordinate {
        name: name.to_string(),
        role,
    };
    Error::declaration(kind, at)
}

/// Builds the canonical node of `ast` in `arena`, resolving names with `resolver`.
///
/// Errors: unknown names (from the resolver), `der` of something that is not a coordinate,
/// division by (or a negative power of) the constant 0 ([`DeclarationError::ZeroDivisor`]), a
/// function outside its domain at a constant argument (`ln(0)`), constants whose folded sum or
/// product overflows ([`DeclarationError::ConstantOverflow`], at the innermost such
/// expression).
pub(crate) fn resolve(arena: &mut Arena, ast: &Ast, resolver: &mut dyn Resolver) -> Result<Id> {
    let id = resolve_node(arena, ast, resolver)?;
    // The innermost expression whose constants overflowed reports it (children first).
    match arena.take_overflow() {
        None => Ok(id),
        Some(o) => Err(Error::declaration(
            DeclarationError::ConstantOverflow {
                expression: ast.text(),
                operation: o.to_string(),
            },
            ast.location(),
        )),
    }
}

fn resolve_node(arena: &mut Arena, ast: &Ast, resolver: &mut dyn Resolver) -> Result<Id> {
    match ast {
        Ast::Number(n, _) => Ok(arena.number(*n)),
        Ast::Name(name, _) if name == "pi" => Ok(arena.pi()),
        Ast::Name(name, at) => resolver.name(arena, name, *at),
        Ast::Neg(x, _) => {
            let v = resolve(arena, x, resolver)?;
            Ok(arena.neg(v))
        }
        Ast::Sum(ts) => {
            let mut terms = Vec::with_capacity(ts.len());
            for (minus, t, _) in ts {
                let v = resolve(arena, t, resolver)?;
                terms.push(if *minus { arena.neg(v) } else { v });
            }
            Ok(arena.add(&terms))
        }
        Ast::Product(fs) => {
            let mut factors = Vec::with_capacity(fs.len());
            for (div, f, op) in fs {
                let v = resolve(arena, f, resolver)?;
                if *div {
                    let m1 = arena.int(-1);
                    let inv = arena.pow(v, m1).map_err(|_| zero_divisor(f, *op))?;
                    factors.push(inv);
                } else {
                    factors.push(v);
                }
            }
            Ok(arena.mul(&factors))
        }
        Ast::Pow(b, e, at) => {
            let bv = resolve(arena, b, resolver)?;
            let ev = resolve(arena, e, resolver)?;
            arena.pow(bv, ev).map_err(|_| zero_divisor(b, *at))
        }
        Ast::Call(name, args, at) => resolve_call(arena, name, args, *at, resolver),
        // The scalar language has no vector forms (its parser refuses them).
        Ast::Member(_, _, at) | Ast::Brackets(_, at) => {
            Err(Error::parse(ParseError::VectorInScalar, *at))
        }
    }
}

fn zero_divisor(divisor: &Ast, at: Location) -> Error {
    Error::declaration(
        DeclarationError::ZeroDivisor {
            divisor: divisor.text(),
        },
        at,
    )
}

fn resolve_call(
    arena: &mut Arena,
    name: &str,
    args: &[Ast],
    at: Location,
    r: &mut dyn Resolver,
) -> Result<Id> {
    if name == "der" || name == "der2" {
        let order = if name == "der" { 1 } else { 2 };
        return match args {
            [Ast::Name(x, xat)] => r.rate(arena, x, order, *xat),
            [other] => {
                let kind = DeclarationError::RateOfExpression {
                    function: name.to_string(),
                    found: other.text(),
                };
                Err(Error::declaration(kind, other.location()))
            }
            _ => {
                let kind = ParseError::Arity {
                    function: name.to_string(),
                    expected: 1,
                    found: args.len(),
                };
                Err(Error::parse(kind, at))
            }
        };
    }
    let mut v = Vec::with_capacity(args.len());
    for a in args {
        v.push(resolve(arena, a, r)?);
    }
    let domain = |e: Error| match e {
        Error::Algebra(AlgebraError::DivisionByZero { .. }) => Error::declaration(
            DeclarationError::ZeroDivisor {
                divisor: args[0].text(),
            },
            at,
        ),
        other => {
            let kind = DeclarationError::ConstantOutOfDomain {
                error: Box::new(other),
            };
            Error::declaration(kind, at)
        }
    };
    match (name, v.as_slice()) {
        ("sqrt", [x]) => arena.sqrt(*x).map_err(domain),
        ("atan2", [y, x]) => Ok(arena.atan2(*y, *x)),
        ("pow", [b, e]) => arena.pow(*b, *e).map_err(domain),
        (_, [x]) => match Func::from_name(name) {
            Some(f) => arena.func(f, *x).map_err(domain),
            None => Err(Error::declaration(
                DeclarationError::UnknownFunction {
                    name: name.to_string(),
                },
                at,
            )),
        },
        _ => Err(Error::declaration(
            DeclarationError::UnknownFunction {
                name: name.to_string(),
            },
            at,
        )),
    }
}

/// Parses the expression `text` into `arena`.
///
/// Names resolve through [`Arena::lookup`]; `pi` is the constant and `t` is time (created
/// as a [`SymbolKind::Time`] symbol if absent); `der(x)` is the rate x' of a coordinate x
/// and `der2(x)` its acceleration x''. Functions: sin, cos, tan, exp, ln, sqrt, abs,
/// atan2(y, x), pow(x, e). `^` is power, right-associative and tighter than unary minus.
///
/// # Errors
/// [`Error::Parse`] with line and column for text that does not follow the grammar,
/// [`DeclarationError::UnknownSymbol`] (with the closest declared name when one is near),
/// [`DeclarationError::UnknownFunction`], [`DeclarationError::ZeroDivisor`] for a division by a
/// constant 0, [`Error::Declaration`] for `der` of a non-coordinate or a function outside its
/// domain at a constant argument.
///
/// # Example
/// ```
/// use mechanism_codegen::{parse_expr, to_text, Arena, SymbolKind};
/// let mut a = Arena::new();
/// a.symbol("x", SymbolKind::Free);
/// let e = parse_expr(&mut a, "-x^2 + 1/2*x").unwrap();
/// assert_eq!(to_text(&a, e), "x/2 - x^2");
/// ```
pub fn parse_expr(arena: &mut Arena, text: &str) -> Result<Id> {
    let tokens = tokens_from_str(text)?;
    let mut cursor = Cursor::new(&tokens);
    let ast = parse(&mut cursor, Language::Scalar)?;
    if !cursor.at(&Tok::End) {
        return Err(cursor.expected(Expected::EndOfExpression));
    }
    resolve(arena, &ast, &mut ArenaResolver)
}
