//! Finding a mechanism by built-in name or `.mech` path ([`load`]); `--set` and `--init`
//! are applied and checked in `physical`.

use std::path::Path;

use mechanism_codegen::{Arena, Tangents};

use super::CliError;
use super::budget::{derivation_budget, derivation_done};
use super::input::read_input;
use mechanism::Interpreted;
use mechanism::System;
use mechanism::builtin::{builtin, builtin_names, builtin_source};

/// A mechanism ready to run, with its declaration text.
pub struct Loaded {
    /// The system (compiled in, or interpreted from a file).
    pub system: Box<dyn System>,
    /// Short name: the built-in name or the file stem as a folder name (`out/<key>`).
    pub key: String,
    /// The declaration text.
    pub source: String,
    /// The mechanism as given (a built-in name or a path), which errors in the declaration
    /// are located by.
    pub shown: String,
    /// The parameter values as declared, before any `--set`.
    pub declared: Vec<f64>,
}

impl Loaded {
    /// `system` loaded from `spec` as `key`, with its declaration text `source`.
    fn new(system: Box<dyn System>, spec: &str, key: String, source: String) -> Self {
        let mut declared = vec![0.0; system.info().parameters.len()];
        system.parameter_values(&mut declared);
        Self {
            system,
            key,
            source,
            shown: spec.to_string(),
            declared,
        }
    }
}

/// Loads `spec`: a built-in name (`mechanism list`) or a path to a `.mech` file, which runs
/// through the interpreter route with the tangents `tangents` asks for (a built-in carries
/// all of them).
///
/// # Errors
/// An unknown name (listing the available ones), an unreadable file, or a declaration error
/// with `file:line:column`.
pub fn load(spec: &str, tangents: Tangents) -> Result<Loaded, CliError> {
    let path = Path::new(spec);
    if is_file_spec(spec) {
        let source = read_input(path).map_err(CliError::Mechanism)?;
        let system = mechanism_codegen::parse_model_str_with(&source, derivation_budget()?)
            .and_then(|mut model| {
                let eqs = mechanism_codegen::derive(&mut model)?;
                Interpreted::from_equations_with(model, eqs, tangents)
            });
        derivation_done();
        let system = system.map_err(|e| CliError::Mechanism(located(spec, &e)))?;
        return Ok(Loaded::new(Box::new(system), spec, file_key(path), source));
    }
    match (builtin(spec), builtin_source(spec)) {
        (Some(system), Some(source)) => Ok(Loaded::new(
            system,
            spec,
            spec.to_string(),
            source.to_string(),
        )),
        _ => Err(CliError::Mechanism(format!(
            "unknown mechanism `{spec}`; available: {} (or a path to a .mech file)",
            builtin_names().join(", ")
        ))),
    }
}

/// Loads `spec` like [`load`], always through the interpreter route and with the
/// constraint rows' tangents compiled ([`Interpreted::for_linearization`]), for
/// `linearize`. Its `--set` values are applied afterwards as for every other command
/// (`physical::apply_sets`): the initial values written with parameters follow them.
///
/// # Errors
/// As [`load`].
pub fn load_for_linearization(spec: &str) -> Result<Loaded, CliError> {
    let path = Path::new(spec);
    let (source, key) = if is_file_spec(spec) {
        let source = read_input(path).map_err(CliError::Mechanism)?;
        (source, file_key(path))
    } else {
        let source = builtin_source(spec).ok_or_else(|| {
            CliError::Mechanism(format!(
                "unknown mechanism `{spec}`; available: {} (or a path to a .mech file)",
                builtin_names().join(", ")
            ))
        })?;
        (source.to_string(), spec.to_string())
    };
    let system = mechanism_codegen::parse_model_str_with(&source, derivation_budget()?)
        .and_then(Interpreted::for_linearization);
    derivation_done();
    let system = system.map_err(|e| CliError::Mechanism(located(spec, &e)))?;
    Ok(Loaded::new(Box::new(system), spec, key, source))
}

/// True when `spec` names a `.mech` file rather than a built-in mechanism: it ends in
/// `.mech`, holds a path separator (no built-in name does: `/tmp` is read, and refused as a
/// directory, rather than looked up by name) or is an existing file.
pub fn is_file_spec(spec: &str) -> bool {
    spec.ends_with(".mech") || spec.contains(std::path::MAIN_SEPARATOR) || Path::new(spec).is_file()
}

/// The short name of the mechanism `spec` names, known without loading it (for
/// `out/<key>`): the built-in name, or the file's stem made safe as a folder name
/// ([`folder_name`]); `None` for a name that is neither.
pub fn key_of(spec: &str) -> Option<String> {
    if is_file_spec(spec) {
        Some(file_key(Path::new(spec)))
    } else {
        builtin_source(spec).map(|_| spec.to_string())
    }
}

/// The key of a `.mech` file: its stem as a folder name.
pub fn file_key(path: &Path) -> String {
    folder_name(&path.file_stem().unwrap_or_default().to_string_lossy())
}

/// `name` as a single folder name that stays inside `out/`: letters, digits, `_` and `-`
/// are kept, anything else (`.`, `/`, spaces) becomes `_`; an empty name is `mechanism`.
/// So `...mech` gives `__`, never `..`.
pub fn folder_name(name: &str) -> String {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if safe.is_empty() {
        "mechanism".into()
    } else {
        safe
    }
}

/// `file:line:column: message` for a codegen error that has a location, else `file: message`.
pub fn located(file: &str, e: &mechanism_codegen::Error) -> String {
    match e.location() {
        Some(l) => format!("{file}:{}:{}: {}", l.line, l.column, e.message()),
        None => format!("{file}: {e}"),
    }
}

/// Evaluates a constant expression such as `0.35`, `2*pi` or `1/3`.
pub fn constant(text: &str) -> Result<f64, String> {
    if let Ok(v) = text.parse::<f64>() {
        return Ok(v);
    }
    let mut arena = Arena::new();
    let e = mechanism_codegen::parse_expr(&mut arena, text)
        .map_err(|e| format!("`{text}` is not a constant: {e}"))?;
    mechanism_codegen::eval(&arena, e, &|_| None)
        .map_err(|e| format!("`{text}` is not a constant: {e}"))
}

/// [`constant`], which must be finite: `--set` and `--init` values are.
pub fn finite_constant(text: &str) -> Result<f64, String> {
    let v = constant(text)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("the value must be finite, got `{text}` = {v}"))
    }
}

/// `" (did you mean `l2`?)"` when one of `names` is a likely typo of `name` (at most two
/// edits, or equal up to letter case: [`mechanism_codegen::closest`]), else nothing.
pub fn did_you_mean(name: &str, names: &[String]) -> String {
    match mechanism_codegen::closest(name, names.iter().map(String::as_str)) {
        Some(c) => format!(" (did you mean `{c}`?)"),
        None => String::new(),
    }
}
