//! The rules the macro adds on top of the parser's (`mechanism_codegen` checks symbols,
//! duplicates, rates, sizes and defaults), one `check_*` function per rule: those that come
//! from the declaration becoming Rust items. Every failing rule contributes an error; they
//! are combined so the user sees all at once.

use crate::ast::Declaration;

/// Runs every check and combines the errors.
pub fn check(decl: &Declaration) -> syn::Result<()> {
    let mut errors: Vec<syn::Error> = Vec::new();
    check_identifiers(decl, &mut errors);
    check_finite(decl, &mut errors);
    check_energies_free_of_time(decl, &mut errors);
    if errors.is_empty() {
        Ok(())
    } else {
        Err(crate::ast::combine(errors))
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
            &format!(
                "`{}` cannot name the generated struct: it is a Rust keyword",
                model.name
            ),
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
                &format!(
                    "the default of parameter `{}` is not a finite number ({})",
                    p.name, p.default
                ),
            ));
        }
    }
    for c in &model.coordinates {
        if !c.guess.is_finite() {
            errors.push(decl.error_at(
                Some(c.location),
                &format!(
                    "the initial guess of coordinate `{}` is not a finite number ({})",
                    c.name, c.guess
                ),
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

/// T and Pi must not read t: the trait's `mass_matrix(q)`, `coriolis_forces(q, q')`,
/// `gravity(q)`, `kinetic_energy(q, q')` and `potential_energy(q)` take no time, so their
/// expansion could not compile. The interpreter route (`Interpreted`, a `.mech` file
/// through the command line) takes such a declaration; a moving base declared as a moving
/// anchor (a joint row or constraint with t, the bodies in absolute coordinates) keeps T and
/// Pi free of t and compiles.
fn check_energies_free_of_time(decl: &Declaration, errors: &mut Vec<syn::Error>) {
    let model = &decl.model;
    let energies = [
        ("kinetic energy", model.kinetic, Some(decl.spans.kinetic)),
        ("potential energy", model.potential, decl.spans.potential),
    ];
    for (what, e, at) in energies {
        if model.depends_on_time(e) {
            errors.push(decl.error_at(
                at.or(Some(decl.spans.kinetic)),
                &format!(
                    "the {what} depends on t explicitly, which `mechanism!` cannot compile (its `mass_matrix(q)`, `gravity(q)`, `kinetic_energy(q, q')` and `potential_energy(q)` take no time): declare the moving part as a moving anchor (a joint or constraint row with t), or run the declaration through the interpreter (`Interpreted`, `mechanism simulate FILE.mech`)"
                ),
            ));
        }
    }
}
