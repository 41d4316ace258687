//! The rules a declaration must follow, one `check_*` function per rule. Every rule runs and
//! every error is kept, so the user sees all mistakes at once; errors are sorted by position.

use std::collections::HashMap;

use crate::algebra::expr::{Id, SymbolId};
use crate::error::{
    ConstantPlace, CoordinatePlace, DeclarationError, Error, Location, NameKind, SymbolRole,
};
use crate::mechanics::model::Model;
use crate::mechanics::resolve::unknown_symbol;
use crate::syntax::ast::Ast;
use crate::syntax::bodies::BodyItem;
use crate::syntax::declaration::{Declaration, Item};
use crate::syntax::spelling::closest;

/// What a declared name is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// The k-th parameter.
    Parameter(usize),
    /// The k-th coordinate.
    Coordinate(usize),
}

/// Where an expression stands, which decides what it may use.
#[derive(Clone, Copy, Debug)]
enum Context {
    /// The default of the k-th parameter: numbers, `pi`, earlier parameters.
    Default(usize),
    /// An initial guess or initial value: numbers, `pi`, parameters.
    Initial,
    /// The kinetic energy T(q, q', t).
    Kinetic,
    /// The potential energy Pi(q, t).
    Potential,
    /// The i-th constraint row (1-based) Phi_i(q, t).
    Constraint(usize),
    /// A velocity constraint row A(q, t) q' + a(q, t): rates allowed (linearity is checked
    /// on the built expression, `mechanics::nonholonomic`).
    VelocityConstraint,
    /// A generalised force tau(t, q, q').
    Force,
}

/// The declared names.
struct Scope<'d> {
    kinds: HashMap<&'d str, Kind>,
    names: Vec<&'d str>,
    coordinates: Vec<&'d str>,
}

impl<'d> Scope<'d> {
    fn new(d: &'d Declaration) -> Self {
        let mut kinds = HashMap::new();
        let mut names = Vec::new();
        let params = d.parameters.iter().flat_map(|s| &s.body);
        for (k, p) in params.enumerate() {
            kinds.entry(p.name.as_str()).or_insert(Kind::Parameter(k));
            names.push(p.name.as_str());
        }
        // Distinct coordinate names (a duplicate is reported once, by its own rule).
        let mut coords: Vec<&str> = Vec::new();
        for c in d.coordinates.iter().flat_map(|s| &s.body) {
            if !coords.contains(&c.name.as_str()) {
                coords.push(&c.name);
            }
        }
        for (k, c) in coords.iter().enumerate() {
            kinds.entry(*c).or_insert(Kind::Coordinate(k));
            names.push(c);
        }
        Scope {
            kinds,
            names,
            coordinates: coords,
        }
    }

    /// The error for an unknown `name` at `at`, with the declared names, `t` and `pi`.
    fn unknown(&self, name: &str, at: Location) -> Error {
        let known: Vec<&str> = self.names.iter().copied().chain(["t", "pi"]).collect();
        unknown_symbol(name, at, &known)
    }
}

/// Runs every rule on `d`; an empty list means the declaration is valid.
pub(crate) fn check(d: &Declaration) -> Vec<Error> {
    let scope = Scope::new(d);
    let mut errors = Vec::new();
    check_kinetic_present(d, &mut errors);
    check_coordinates_present(d, &mut errors);
    check_duplicate_names(d, &mut errors);
    check_reserved_names(d, &mut errors);
    check_expressions(d, &scope, &mut errors);
    check_forces(d, &scope, &mut errors);
    check_independent(d, &scope, &mut errors);
    check_degrees_of_freedom(d, &scope, &mut errors);
    errors.sort_by_key(|e| e.location().map(|l| (l.line, l.column)).unwrap_or((0, 0)));
    errors
}

/// The kinetic energy is required: without T there is no mass matrix.
fn check_kinetic_present(d: &Declaration, errors: &mut Vec<Error>) {
    if d.kinetic.is_none() && !d.bodies.declares_energy() {
        let kind = DeclarationError::NoKinetic {
            mechanism: d.name.clone(),
        };
        errors.push(Error::declaration(kind, d.name_at));
    }
}

/// At least one coordinate: the equations of motion are written in them.
fn check_coordinates_present(d: &Declaration, errors: &mut Vec<Error>) {
    match &d.coordinates {
        None => {
            let kind = DeclarationError::NoCoordinates {
                mechanism: d.name.clone(),
                empty_section: false,
            };
            errors.push(Error::declaration(kind, d.name_at));
        }
        Some(s)
            if s.body.is_empty()
                && d.bodies
                    .items
                    .iter()
                    .any(|i| matches!(i, BodyItem::Link { .. })) =>
        {
            let kind = DeclarationError::NoMovingJoint {
                mechanism: d.name.clone(),
            };
            errors.push(Error::declaration(kind, d.name_at));
        }
        Some(s) if s.body.is_empty() => {
            let kind = DeclarationError::NoCoordinates {
                mechanism: d.name.clone(),
                empty_section: true,
            };
            errors.push(Error::declaration(kind, s.at));
        }
        Some(_) => {}
    }
}

/// Each name is declared once: twice as a parameter, twice as a coordinate, or as both.
fn check_duplicate_names(d: &Declaration, errors: &mut Vec<Error>) {
    let params = d
        .parameters
        .iter()
        .flat_map(|s| &s.body)
        .map(|i| (i, NameKind::Parameter));
    let coords = d
        .coordinates
        .iter()
        .flat_map(|s| &s.body)
        .map(|i| (i, NameKind::Coordinate));
    let mut seen: HashMap<&str, (&Item, NameKind)> = HashMap::new();
    for (item, kind) in params.chain(coords) {
        match seen.get(item.name.as_str()) {
            Some(&(first, first_kind)) => {
                let name = item.name.clone();
                let error = if first_kind == kind {
                    DeclarationError::DeclaredTwice {
                        name,
                        kind,
                        first: first.at,
                    }
                } else {
                    DeclarationError::DeclaredAsBoth {
                        name,
                        first_kind,
                        first: first.at,
                        kind,
                    }
                };
                errors.push(Error::declaration(error, item.at));
            }
            None => {
                seen.insert(item.name.as_str(), (item, kind));
            }
        }
    }
}

/// `t` (time) and `pi` are built in and cannot be redeclared.
fn check_reserved_names(d: &Declaration, errors: &mut Vec<Error>) {
    let params = d
        .parameters
        .iter()
        .flat_map(|s| &s.body)
        .map(|i| (i, NameKind::Parameter));
    let coords = d
        .coordinates
        .iter()
        .flat_map(|s| &s.body)
        .map(|i| (i, NameKind::Coordinate));
    for (item, kind) in params.chain(coords) {
        if item.name == "t" || item.name == "pi" {
            let error = DeclarationError::ReservedName {
                name: item.name.clone(),
                kind,
            };
            errors.push(Error::declaration(error, item.at));
        }
    }
}

/// Every expression uses declared names only, `der` only of coordinates, and only what its
/// place allows: defaults and initial values are constants, the potential and the
/// constraints depend on q and t only (holonomic), accelerations never appear.
fn check_expressions(d: &Declaration, scope: &Scope<'_>, errors: &mut Vec<Error>) {
    for (k, p) in d.parameters.iter().flat_map(|s| &s.body).enumerate() {
        check_expression(&p.value, Context::Default(k), scope, errors);
    }
    for c in d.coordinates.iter().flat_map(|s| &s.body) {
        check_expression(&c.value, Context::Initial, scope, errors);
    }
    for i in d.independent.iter().flat_map(|s| &s.body) {
        check_expression(&i.value, Context::Initial, scope, errors);
    }
    if let Some(k) = &d.kinetic {
        check_expression(&k.body, Context::Kinetic, scope, errors);
    }
    if let Some(p) = &d.potential {
        check_expression(&p.body, Context::Potential, scope, errors);
    }
    for (i, row) in d.constraints.iter().flat_map(|s| &s.body).enumerate() {
        check_expression(&row.lhs, Context::Constraint(i + 1), scope, errors);
        if let Some(rhs) = &row.rhs {
            check_expression(rhs, Context::Constraint(i + 1), scope, errors);
        }
    }
    for row in d.velocity_constraints.iter().flat_map(|s| &s.body) {
        for side in std::iter::once(&row.lhs).chain(&row.rhs) {
            check_expression(side, Context::VelocityConstraint, scope, errors);
        }
    }
    for f in d.forces.iter().flat_map(|s| &s.body) {
        check_expression(&f.value, Context::Force, scope, errors);
    }
}

/// Whether `ctx` allows only constants, and which place it is.
fn constant_place(ctx: Context) -> Option<ConstantPlace> {
    match ctx {
        Context::Default(_) => Some(ConstantPlace::Default),
        Context::Initial => Some(ConstantPlace::Initial),
        _ => None,
    }
}

/// "{place}; `{written}` is {role}".
fn not_constant(place: ConstantPlace, written: &str, role: SymbolRole, at: Location) -> Error {
    let kind = DeclarationError::NotConstant {
        place,
        written: written.to_string(),
        role,
    };
    Error::declaration(kind, at)
}

fn check_expression(ast: &Ast, ctx: Context, scope: &Scope<'_>, errors: &mut Vec<Error>) {
    let mut stack = vec![ast];
    while let Some(a) = stack.pop() {
        match a {
            Ast::Name(name, at) => check_name(name, *at, ctx, scope, errors),
            Ast::Call(f, args, at) if f == "der" || f == "der2" => {
                check_rate(f, args, *at, ctx, scope, errors);
            }
            Ast::Number(..) => {}
            Ast::Neg(x, _) => stack.push(x),
            Ast::Sum(items) | Ast::Product(items) => stack.extend(items.iter().map(|i| &i.1)),
            Ast::Pow(b, e, _) => stack.extend([&**b, &**e]),
            Ast::Call(_, args, _) | Ast::Brackets(args, _) => stack.extend(args),
            Ast::Member(x, _, _) => stack.push(x),
        }
    }
}

/// A plain name: declared, and allowed where it stands.
fn check_name(name: &str, at: Location, ctx: Context, scope: &Scope<'_>, errors: &mut Vec<Error>) {
    if name == "pi" {
        return;
    }
    if name == "t" {
        if let Some(place) = constant_place(ctx) {
            errors.push(not_constant(place, name, SymbolRole::Time, at));
        }
        return;
    }
    match (scope.kinds.get(name), ctx, constant_place(ctx)) {
        (None, _, _) => errors.push(scope.unknown(name, at)),
        (Some(Kind::Coordinate(_)), _, Some(place)) => {
            errors.push(not_constant(place, name, SymbolRole::Coordinate, at));
        }
        (Some(Kind::Parameter(j)), Context::Default(k), _) if *j == k => {
            let kind = DeclarationError::DefaultRefersToItself {
                name: name.to_string(),
            };
            errors.push(Error::declaration(kind, at));
        }
        (Some(Kind::Parameter(j)), Context::Default(k), _) if *j > k => {
            let kind = DeclarationError::DefaultUsesLater {
                name: name.to_string(),
            };
            errors.push(Error::declaration(kind, at));
        }
        _ => {}
    }
}

/// `der(x)` / `der2(x)`: x is a declared coordinate, and a rate is allowed where it stands.
fn check_rate(
    f: &str,
    args: &[Ast],
    at: Location,
    ctx: Context,
    scope: &Scope<'_>,
    errors: &mut Vec<Error>,
) {
    let [Ast::Name(x, xat)] = args else {
        let kind = DeclarationError::RateOfExpression {
            function: f.to_string(),
            found: args.first().map(Ast::text).unwrap_or_default(),
        };
        errors.push(Error::declaration(kind, at));
        return;
    };
    let role = match scope.kinds.get(x.as_str()) {
        Some(Kind::Coordinate(_)) => None,
        Some(Kind::Parameter(_)) => Some(SymbolRole::Parameter),
        None if x == "t" => Some(SymbolRole::Time),
        None => {
            errors.push(scope.unknown(x, *xat));
            return;
        }
    };
    if let Some(role) = role {
        let kind = DeclarationError::RateOfNonCoordinate {
            name: x.clone(),
            role,
        };
        errors.push(Error::declaration(kind, *xat));
        return;
    }
    let written = format!("{f}({x})");
    let kind = match (f, ctx, constant_place(ctx)) {
        ("der2", _, _) => DeclarationError::Acceleration { written },
        (_, _, Some(place)) => {
            errors.push(not_constant(place, &written, SymbolRole::Rate, at));
            return;
        }
        (_, Context::Potential, _) => DeclarationError::RateInPotential { written },
        (_, Context::Constraint(row), _) => DeclarationError::RateInConstraint { written, row },
        _ => return,
    };
    errors.push(Error::declaration(kind, at));
}

/// Forces act along declared coordinates, at most one entry per coordinate.
fn check_forces(d: &Declaration, scope: &Scope<'_>, errors: &mut Vec<Error>) {
    let mut seen: HashMap<&str, Location> = HashMap::new();
    for f in d.forces.iter().flat_map(|s| &s.body) {
        if !matches!(scope.kinds.get(f.name.as_str()), Some(Kind::Coordinate(_))) {
            let kind = not_a_coordinate(CoordinatePlace::Force, &f.name, scope);
            errors.push(Error::declaration(kind, f.at));
            continue;
        }
        if let Some(first) = seen.insert(&f.name, f.at) {
            let kind = DeclarationError::TwoForces {
                name: f.name.clone(),
                first,
            };
            errors.push(Error::declaration(kind, f.at));
        }
    }
}

/// "{place}, but `name` is a parameter (the coordinates are ...); did you mean ...?".
fn not_a_coordinate(place: CoordinatePlace, name: &str, scope: &Scope<'_>) -> DeclarationError {
    let role = match scope.kinds.get(name) {
        Some(Kind::Parameter(_)) => SymbolRole::Parameter,
        _ => SymbolRole::Undeclared,
    };
    DeclarationError::NotACoordinate {
        place,
        name: name.to_string(),
        role,
        coordinates: scope.coordinates.iter().map(|c| c.to_string()).collect(),
        suggestion: closest(name, scope.coordinates.iter().copied()),
    }
}

/// Independent entries name declared coordinates, each value at most once.
fn check_independent(d: &Declaration, scope: &Scope<'_>, errors: &mut Vec<Error>) {
    let mut seen: HashMap<(&str, bool), Location> = HashMap::new();
    for i in d.independent.iter().flat_map(|s| &s.body) {
        if !matches!(scope.kinds.get(i.name.as_str()), Some(Kind::Coordinate(_))) {
            let kind = not_a_coordinate(CoordinatePlace::Independent, &i.name, scope);
            errors.push(Error::declaration(kind, i.at));
            continue;
        }
        if let Some(first) = seen.insert((&i.name, i.rate), i.at) {
            let kind = DeclarationError::SetTwice {
                name: i.name.clone(),
                rate: i.rate,
                first,
            };
            errors.push(Error::declaration(kind, i.at));
        }
    }
}

/// The n - m degrees of freedom are each fixed by an independent coordinate; with fewer the
/// other coordinates cannot be determined from Phi(q) = 0 at t = 0. Redundant rows make the
/// mobility n - rank(Phi_q) larger than n - m, so n - m is only a lower bound (the runtime
/// knows the rank); with m > n there is nothing to check here.
fn check_degrees_of_freedom(d: &Declaration, scope: &Scope<'_>, errors: &mut Vec<Error>) {
    let n = scope.coordinates.len();
    let m = d.constraints.as_ref().map_or(0, |s| s.body.len())
        + d.velocity_constraints.as_ref().map_or(0, |s| s.body.len())
        + d.bodies.constraint_rows();
    if n == 0 || m > n {
        return;
    }
    let mut given: Vec<&str> = Vec::new();
    for i in d.independent.iter().flat_map(|s| &s.body) {
        if scope.coordinates.contains(&i.name.as_str()) && !given.contains(&i.name.as_str()) {
            given.push(&i.name);
        }
    }
    if given.len() >= n - m {
        return;
    }
    let candidates = scope
        .coordinates
        .iter()
        .filter(|c| !given.contains(c))
        .map(|c| c.to_string())
        .collect();
    let kind = DeclarationError::TooFewIndependent {
        n,
        m,
        given: given.iter().map(|g| g.to_string()).collect(),
        candidates,
    };
    let at = d.independent.as_ref().map_or(d.name_at, |s| s.at);
    errors.push(Error::declaration(kind, at));
}

/// A rule broken by the built expressions (canonical forms decide what is constant), with
/// the expression the rule found, so that the caller can quote it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ModelFinding {
    /// Constraint row `row` (0-based) depends on neither the coordinates nor t; `expr` is
    /// its simplified form.
    ConstraintWithoutMotion {
        /// The row, 0-based.
        row: usize,
        /// The row's expression.
        expr: Id,
        /// Where the row is declared.
        location: Location,
    },
    /// The kinetic energy `expr` depends on no rate der(q).
    KineticWithoutRates {
        /// The kinetic energy.
        expr: Id,
        /// Where `kinetic` is declared.
        location: Location,
    },
}

/// The rules that need the built expressions.
pub(crate) fn check_model(model: &Model, kinetic_at: Location) -> Vec<ModelFinding> {
    let mut findings = Vec::new();
    check_constraints_depend_on_motion(model, &mut findings);
    // Links that carry all of T are checked once M is built (`lagrange`): T is not formed.
    if !model.kinetic_from_links {
        check_kinetic_has_rates(model, kinetic_at, &mut findings);
    }
    findings
}

/// The symbols of the coordinates (and of t, when `with_time`).
fn motion_symbols(model: &Model, with_time: bool) -> Vec<SymbolId> {
    let a = &model.arena;
    let mut syms: Vec<SymbolId> = model
        .coordinates
        .iter()
        .filter_map(|c| a.as_symbol(c.q))
        .collect();
    if with_time {
        syms.extend(a.as_symbol(model.time));
    }
    syms
}

/// Each constraint row depends on the coordinates or on t: a row of parameters and numbers
/// (`x - x`, `l1 - l2`) either always holds or never does, and gives a zero row in Phi_q.
fn check_constraints_depend_on_motion(model: &Model, findings: &mut Vec<ModelFinding>) {
    let mut motion = vec![false; model.arena.symbols().len()];
    for s in motion_symbols(model, true) {
        motion[s.index()] = true;
    }
    for (row, c) in model.constraints.iter().enumerate() {
        // One walk per row (a walk per (row, symbol) pair was m n walks on A02).
        if !model.arena.depends_on_any(c.expr, |s| motion[s.index()]) {
            findings.push(ModelFinding::ConstraintWithoutMotion {
                row,
                expr: c.expr,
                location: c.location,
            });
        }
    }
}

/// The kinetic energy depends on at least one rate der(q); otherwise M = 0 and the equations
/// of motion say nothing about accelerations.
fn check_kinetic_has_rates(model: &Model, at: Location, findings: &mut Vec<ModelFinding>) {
    let a = &model.arena;
    let rates: Vec<SymbolId> = model
        .coordinates
        .iter()
        .filter_map(|c| a.as_symbol(c.qd))
        .collect();
    let mut is_rate = vec![false; a.symbols().len()];
    for s in &rates {
        is_rate[s.index()] = true;
    }
    if !a.depends_on_any(model.kinetic, |s| is_rate[s.index()]) {
        findings.push(ModelFinding::KineticWithoutRates {
            expr: model.kinetic,
            location: at,
        });
    }
}
