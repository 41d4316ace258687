//! The rules the macro adds on top of the parser, one `check_*` function per rule. Every
//! failing rule contributes an error; they are combined so the user sees all at once.

use mechanism_codegen::{Id, Location, Model, Node, SymbolKind};

use crate::ast::Declaration;

/// Runs every check and combines the errors.
pub fn check(decl: &Declaration) -> syn::Result<()> {
    let mut errors: Vec<syn::Error> = Vec::new();
    check_identifiers(decl, &mut errors);
    check_finite(decl, &mut errors);
    check_sizes(decl, &mut errors);
    check_rates(decl, &mut errors);
    let mut errors = errors.into_iter();
    match errors.next() {
        None => Ok(()),
        Some(mut first) => {
            for e in errors {
                first.combine(e);
            }
            Err(first)
        }
    }
}

/// True when `name` can be a Rust identifier that is not a keyword (it becomes a type or
/// a field name in the expansion).
fn is_rust_identifier(name: &str) -> bool {
    syn::parse_str::<syn::Ident>(name).is_ok()
}

/// The struct name and every parameter name must be Rust identifiers: the struct is named
/// after the declaration, and each parameter becomes a `pub f64` field.
fn check_identifiers(decl: &Declaration, errors: &mut Vec<syn::Error>) {
    let model = &decl.model;
    if !is_rust_identifier(&model.name) {
        errors.push(decl.error_at(
            None,
            &format!("`{}` cannot name the generated struct: it is a Rust keyword", model.name),
        ));
    }
    for p in &model.parameters {
        if !is_rust_identifier(&p.name) {
            errors.push(decl.error_at(
                Some(p.location),
                &format!(
                    "parameter `{}` cannot be a field of the generated struct: it is a Rust keyword; rename it",
                    p.name
                ),
            ));
        }
    }
}

/// Parameter defaults, initial guesses and independent values must be finite numbers
/// (`1e400` or `0/0` would make the initial state meaningless).
fn check_finite(decl: &Declaration, errors: &mut Vec<syn::Error>) {
    let model = &decl.model;
    for p in &model.parameters {
        if !p.default.is_finite() {
            errors.push(decl.error_at(
                Some(p.location),
                &format!("the default of parameter `{}` is not a finite number ({})", p.name, p.default),
            ));
        }
    }
    for c in &model.coordinates {
        if !c.guess.is_finite() {
            errors.push(decl.error_at(
                Some(c.location),
                &format!("the initial guess of coordinate `{}` is not a finite number ({})", c.name, c.guess),
            ));
        }
    }
    for s in &model.independent {
        if !(s.position.is_finite() && s.velocity.is_finite()) {
            errors.push(decl.error_at(
                Some(s.location),
                "the independent coordinate's initial position or rate is not a finite number",
            ));
        }
    }
}

/// A mechanism needs at least one coordinate, and at most as many constraint rows as
/// coordinates (m > n leaves no motion and no solvable assembly; m = n is allowed for a
/// fully driven, rheonomic mechanism).
fn check_sizes(decl: &Declaration, errors: &mut Vec<syn::Error>) {
    let model = &decl.model;
    let n = model.coordinates.len();
    let m = model.constraints.len();
    if n == 0 {
        errors.push(decl.error_at(None, "`coordinates` is empty: declare at least one coordinate"));
    }
    if m > n {
        let surplus = &model.constraints[n.min(m - 1)];
        errors.push(decl.error_at(
            Some(surplus.location),
            &format!(
                "{m} constraint rows for {n} coordinates: a mechanism cannot have more independent constraints than coordinates"
            ),
        ));
    }
}

/// The symbols of `kind` that `id` depends on (first one found), by a walk over the DAG.
fn first_symbol_of_kind(model: &Model, id: Id, kind: SymbolKind) -> Option<String> {
    let arena = &model.arena;
    let mut stack = vec![id];
    let mut seen = vec![false; arena.len()];
    while let Some(x) = stack.pop() {
        if std::mem::replace(&mut seen[x.index()], true) {
            continue;
        }
        if let Node::Sym(s) = arena.node(x) {
            let info = arena.symbol_info(*s);
            if info.kind == kind {
                return Some(info.name.clone());
            }
        }
        stack.extend(arena.children(x));
    }
    None
}

/// Coordinate rates belong in `kinetic` and `forces` only: Pi(q, t) and Phi(q, t) must not
/// depend on q' (Lagrange's equations assume a velocity-free potential, and constraints
/// with rates are non-holonomic, which this formulation does not cover).
fn check_rates(decl: &Declaration, errors: &mut Vec<syn::Error>) {
    let model = &decl.model;
    if let Some(name) = first_symbol_of_kind(model, model.potential, SymbolKind::Velocity) {
        errors.push(decl.error_at(
            None::<Location>,
            &format!("the potential energy depends on the rate `{name}`; it may depend on coordinates, parameters and t only"),
        ));
    }
    for c in &model.constraints {
        if let Some(name) = first_symbol_of_kind(model, c.expr, SymbolKind::Velocity) {
            errors.push(decl.error_at(
                Some(c.location),
                &format!("this constraint depends on the rate `{name}`: only holonomic constraints Phi(q, t) = 0 are supported"),
            ));
        }
    }
}
