//! `mechanism list` and `mechanism equations`.

use std::fmt::Write as _;

use super::CliError;
use super::load::load;
use crate::builtin::{builtin, builtin_names};

/// The table printed by `mechanism list`: name, n, m, degrees of freedom n - m.
pub fn list() -> Result<String, CliError> {
    let mut s = String::new();
    let w = builtin_names()
        .iter()
        .map(|n| n.len())
        .max()
        .unwrap_or(0)
        .max("mechanism".len());
    let _ = writeln!(s, "{:<w$} {:>3} {:>3} {:>4}", "mechanism", "n", "m", "dof");
    for name in builtin_names() {
        let sys = builtin(name)
            .ok_or_else(|| CliError::Mechanism(format!("built-in `{name}` is missing")))?;
        let info = sys.info();
        let _ = writeln!(
            s,
            "{:<w$} {:>3} {:>3} {:>4}",
            name,
            info.n(),
            info.m(),
            info.n().saturating_sub(info.m())
        );
    }
    Ok(s)
}

/// The derived equations of a built-in mechanism or a `.mech` file, as text or LaTeX.
pub fn equations(spec: &str, latex: bool) -> Result<String, CliError> {
    let loaded = load(spec)?;
    let err = |e: mechanism_codegen::Error| CliError::Mechanism(format!("{spec}: {e}"));
    let mut model = mechanism_codegen::parse_model_str(&loaded.source).map_err(err)?;
    let eqs = mechanism_codegen::derive(&mut model).map_err(err)?;
    Ok(if latex {
        mechanism_codegen::equations_latex(&model, &eqs)
    } else {
        mechanism_codegen::equations_text(&model, &eqs)
    })
}
