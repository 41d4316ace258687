//! From a checked declaration to a [`Model`]: symbols in one arena, constants evaluated,
//! names resolved into arena nodes (the entry points that run
//! every stage are in `pipeline.rs`).

use proc_macro2::Span;

use crate::algebra::budget::Budget;
use crate::algebra::eval::eval;
use crate::algebra::expr::{Arena, Id, SymbolId, SymbolKind};
use crate::error::{Constant, DeclarationError, Error, Location, Result};
use crate::mechanics::model::{Constraint, Coordinate, IndependentSpec, Model, Parameter};
use crate::mechanics::resolve::{ArenaResolver, resolve};
use crate::syntax::ast::Ast;
use crate::syntax::declaration::{Declaration, Item, Row, Section};

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

/// Lowers `ast` into the arena.
fn resolve_at(arena: &mut Arena, ast: &Ast) -> Result<Id> {
    resolve(arena, ast, &mut ArenaResolver)
}

/// The value of a constant expression, with parameters at the values known so far.
fn constant(
    arena: &mut Arena,
    ast: &Ast,
    known: &[(SymbolId, f64)],
    what: Constant,
) -> Result<f64> {
    constant_expression(arena, ast, known, what).map(|(v, _)| v)
}

/// [`constant`] and the expression it is the value of (its node in `arena`), for the
/// values that follow the parameters: the initial guesses and the independent values.
fn constant_expression(
    arena: &mut Arena,
    ast: &Ast,
    known: &[(SymbolId, f64)],
    what: Constant,
) -> Result<(f64, Id)> {
    let id = resolve_at(arena, ast)?;
    let env = |s: SymbolId| known.iter().find(|k| k.0 == s).map(|k| k.1);
    let value = eval(arena, id, &env).map_err(|e| {
        let kind = DeclarationError::NotEvaluable {
            what,
            error: Box::new(e),
        };
        Error::declaration(kind, ast.location())
    })?;
    Ok((value, id))
}

/// A given value `v` (of `--set` or `--init`) as an expression: the number itself (a
/// domain error for a value that is not finite).
fn given_expression(arena: &mut Arena, v: f64) -> Result<Id> {
    arena.float(v)
}

/// Builds the model of a checked declaration. The arena's symbols and nodes are created in
/// a fixed order (parameters, coordinates, t, then the expressions in declaration order), so
/// that the same declaration gives the same ids.
pub(crate) fn build(d: &Declaration, budget: Budget) -> Result<ParsedModel> {
    build_with(d, &[], budget)
}

/// [`build`] with the parameters and coordinates named in `values` at those values instead
/// of their declared defaults and guesses, so that every check of the declared values
/// (masses, inertias, orientations) runs on them: the run-time check of `--set` and of the
/// assembled state.
pub(crate) fn build_with_values(d: &Declaration, values: &[(&str, f64)]) -> Result<ParsedModel> {
    build_with(d, values, Budget::default())
}

/// [`build_with_values`] in an arena that keeps to `budget` (and the derivation after it).
fn build_with(d: &Declaration, values: &[(&str, f64)], budget: Budget) -> Result<ParsedModel> {
    let mut arena = Arena::new();
    arena.set_budget(budget);
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
    let (parameters, known) = build_parameters(&mut arena, param_items, &param_syms, values)?;
    let coordinates = build_coordinates(&mut arena, coord_items, &coord_ids, &known, values)?;
    let independent = build_independent(&mut arena, d, &coordinates, &known)?;
    let (kinetic, kinetic_at) = match &d.kinetic {
        Some(k) => (resolve_at(&mut arena, &k.body)?, k.at),
        // Bodies declare T (`mechanics::body_model`); `check` rejects a missing T otherwise.
        None => (arena.int(0), d.bodies.first_location().unwrap_or(d.name_at)),
    };
    let potential = match &d.potential {
        Some(p) => resolve_at(&mut arena, &p.body)?,
        None => arena.int(0),
    };
    let constraints = build_constraints(&mut arena, d.constraints.as_ref(), "constraint")?;
    let velocity_constraints = build_constraints(
        &mut arena,
        d.velocity_constraints.as_ref(),
        "velocity constraint",
    )?;
    let (forces, force_entries) = build_forces(&mut arena, d, &coordinates)?;
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
        kinetic_location: kinetic_at,
        potential,
        constraints,
        vanished_rows: Vec::new(),
        velocity_constraints,
        forces,
        drawing: Default::default(),
        links: Vec::new(),
        kinetic_from_links: false,
        potential_from_links: false,
        gravity: None,
        rotations: Vec::new(),
        link_bodies: Vec::new(),
    };
    crate::mechanics::body_model::build_bodies(&d.bodies, &mut model)?;
    Ok(ParsedModel { model, spans })
}

/// Parameter symbols with their default values, in declaration order.
type Defaults = Vec<(SymbolId, f64)>;

/// The parameters with their defaults, each evaluated with the defaults before it; also
/// the (symbol, default) table for the later constants.
fn build_parameters(
    arena: &mut Arena,
    items: &[Item],
    syms: &[SymbolId],
    values: &[(&str, f64)],
) -> Result<(Vec<Parameter>, Defaults)> {
    let mut known: Defaults = Vec::with_capacity(items.len());
    let mut parameters = Vec::with_capacity(items.len());
    for (p, &s) in items.iter().zip(syms) {
        let given = values.iter().find(|v| v.0 == p.name).map(|v| v.1);
        let default = match given {
            Some(v) => v,
            None => constant(arena, &p.value, &known, Constant::Default(p.name.clone()))?,
        };
        if !p.range.admits(default) {
            let kind = DeclarationError::OutOfRange {
                name: p.name.clone(),
                value: default,
                keyword: p.range.keyword(),
                meaning: p.range.describe(),
            };
            return Err(Error::declaration(kind, p.value.location()));
        }
        known.push((s, default));
        parameters.push(Parameter {
            name: p.name.clone(),
            symbol: arena.symbol_node(s),
            default,
            range: p.range,
            location: p.at,
        });
    }
    Ok((parameters, known))
}

/// The coordinates with their initial guesses.
fn build_coordinates(
    arena: &mut Arena,
    items: &[Item],
    ids: &[[Id; 3]],
    known: &[(SymbolId, f64)],
    values: &[(&str, f64)],
) -> Result<Vec<Coordinate>> {
    let mut coordinates = Vec::with_capacity(items.len());
    for (c, ids) in items.iter().zip(ids) {
        let given = values.iter().find(|v| v.0 == c.name).map(|v| v.1);
        let (guess, guess_expr) = match given {
            Some(v) => (v, given_expression(arena, v)?),
            None => constant_expression(arena, &c.value, known, Constant::Guess(c.name.clone()))?,
        };
        let [q, qd, qdd] = *ids;
        coordinates.push(Coordinate {
            name: c.name.clone(),
            q,
            qd,
            qdd,
            guess,
            guess_expr,
            location: c.at,
        });
    }
    Ok(coordinates)
}

/// The independent coordinates: one entry per coordinate named in `independent`, its
/// position (the guess unless given) and rate (0 unless given).
fn build_independent(
    arena: &mut Arena,
    d: &Declaration,
    coordinates: &[Coordinate],
    known: &[(SymbolId, f64)],
) -> Result<Vec<IndependentSpec>> {
    let mut independent: Vec<IndependentSpec> = Vec::new();
    let mut positioned: Vec<usize> = Vec::new();
    for i in d.independent.iter().flat_map(|s| &s.body) {
        let Some(k) = coordinates.iter().position(|c| c.name == i.name) else {
            continue;
        };
        let what = if i.rate {
            Constant::Rate(i.name.clone())
        } else {
            Constant::Position(i.name.clone())
        };
        let (v, expr) = constant_expression(arena, &i.value, known, what)?;
        let spec = match independent.iter_mut().position(|s| s.coordinate == k) {
            Some(at) => &mut independent[at],
            None => {
                independent.push(IndependentSpec {
                    coordinate: k,
                    position: coordinates[k].guess,
                    velocity: 0.0,
                    position_expr: coordinates[k].guess_expr,
                    velocity_expr: None,
                    location: i.at,
                });
                let last = independent.len() - 1;
                &mut independent[last]
            }
        };
        if i.rate {
            spec.velocity = v;
            spec.velocity_expr = Some(expr);
        } else {
            spec.position = v;
            spec.position_expr = expr;
            positioned.push(k);
        }
    }
    // A rate makes sense only for a coordinate the section also sets: the others follow
    // from the constraints, and listing a bare rate would silently make one more coordinate
    // independent than the mechanism has freedoms.
    for i in d
        .independent
        .iter()
        .flat_map(|s| &s.body)
        .filter(|i| i.rate)
    {
        if let Some(k) = coordinates.iter().position(|c| c.name == i.name)
            && !positioned.contains(&k)
        {
            let free: Vec<String> = positioned
                .iter()
                .map(|&j| coordinates[j].name.clone())
                .collect();
            return Err(Error::declaration(
                DeclarationError::RateOfDependent {
                    name: i.name.clone(),
                    independent: free,
                },
                i.at,
            ));
        }
    }
    Ok(independent)
}

/// The rows lhs - rhs of a `constraints` (or `velocity_constraints`) section, in declaration
/// order, each labelled `{label} k` after its statement k.
fn build_constraints(
    arena: &mut Arena,
    section: Option<&Section<Vec<Row>>>,
    label: &str,
) -> Result<Vec<Constraint>> {
    let mut constraints = Vec::new();
    for row in section.iter().flat_map(|s| &s.body) {
        let lhs = resolve_at(arena, &row.lhs)?;
        let expr = match &row.rhs {
            Some(r) => {
                let rhs = resolve_at(arena, r)?;
                arena.sub(lhs, rhs)
            }
            None => lhs,
        };
        constraints.push(Constraint {
            expr,
            location: row.at,
            joint: format!("{label} {}", row.statement),
            component: row.component.clone(),
        });
    }
    Ok(constraints)
}

/// The generalised force of each coordinate (0 unless declared) and where it is declared.
fn build_forces(
    arena: &mut Arena,
    d: &Declaration,
    coordinates: &[Coordinate],
) -> Result<(Vec<Id>, Vec<Option<Location>>)> {
    let zero = arena.int(0);
    let mut forces = vec![zero; coordinates.len()];
    let mut force_entries = vec![None; coordinates.len()];
    for f in d.forces.iter().flat_map(|s| &s.body) {
        if let Some(k) = coordinates.iter().position(|c| c.name == f.name) {
            forces[k] = resolve_at(arena, &f.value)?;
            force_entries[k] = Some(f.at);
        }
    }
    Ok((forces, force_entries))
}
