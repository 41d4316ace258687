//! `mechanism list` and `mechanism equations`.

use std::fmt::Write as _;

use std::path::Path;

use super::CliError;
use super::budget::{derivation_budget, derivation_done};
use super::input::read_input;
use super::load::{is_file_spec, load, located};
use mechanism::builtin::{builtin, builtin_names};
use mechanism::{AssemblyOptions, assemble};
use mechanism::{InterpretedConstraints, Kinematic};
use mechanism::{Mobility, mobility};
use mechanism_codegen::Tangents;

/// The mobility of `system` at its assembled initial configuration (declared independent
/// coordinates and guesses), or why it could not be assembled.
fn assembled_mobility(system: &dyn Kinematic) -> Result<Mobility, mechanism::Error> {
    let state = assemble(system, 0.0, &AssemblyOptions::default())?;
    mobility(system, 0.0, &state.q)
}

/// The table printed by `mechanism list`: name, n, m, the rank of Phi_q at the assembled
/// configuration, the degrees of freedom n - rank, Grübler's count n - m and the number of
/// redundant rows.
pub fn list() -> Result<String, CliError> {
    let mut s = String::new();
    let w = builtin_names()
        .iter()
        .map(|n| n.len())
        .max()
        .unwrap_or(0)
        .max("mechanism".len());
    let _ = writeln!(
        s,
        "{:<w$} {:>3} {:>3} {:>4} {:>4} {:>7} {:>9}",
        "mechanism", "n", "m", "rank", "dof", "grubler", "redundant"
    );
    for name in builtin_names() {
        let sys = builtin(name)
            .ok_or_else(|| CliError::Mechanism(format!("built-in `{name}` is missing")))?;
        let info = sys.info();
        let (rank, dof, redundant) = match assembled_mobility(sys.as_ref()) {
            Ok(mob) => (
                mob.rank.to_string(),
                mob.degrees_of_freedom.to_string(),
                mob.redundant_rows.len().to_string(),
            ),
            Err(_) => ("-".into(), "-".into(), "-".into()),
        };
        let _ = writeln!(
            s,
            "{:<w$} {:>3} {:>3} {rank:>4} {dof:>4} {:>7} {redundant:>9}",
            name,
            info.n(),
            info.m(),
            info.n() as i64 - info.m() as i64,
        );
    }
    let _ = writeln!(
        s,
        "(rank of Phi_q at the assembled initial configuration; dof = n - rank; Grubler = n - m)"
    );
    Ok(s)
}

/// The mobility paragraph of `mechanism equations`.
fn mobility_text(system: &dyn Kinematic) -> String {
    let info = system.info();
    let mut s = String::new();
    match assembled_mobility(system) {
        Ok(mob) => {
            let _ = writeln!(
                s,
                "Mobility at the assembled configuration: n = {}, m = {}, rank Phi_q = {}, \
                 degrees of freedom n - rank = {} (Grubler's n - m = {}).",
                mob.n, mob.m, mob.rank, mob.degrees_of_freedom, mob.grubler
            );
            if !mob.full_rank() {
                let rows: Vec<String> = mob
                    .redundant_rows
                    .iter()
                    .map(|&r| format!("row {} {}", r + 1, info.constraint_label(r)))
                    .collect();
                let _ = writeln!(s, "Redundant rows: {}.", rows.join("; "));
                let _ = writeln!(
                    s,
                    "The multipliers of {} are not unique (their forces Phi_q^T lambda are); \
                     results give the minimum-norm choice.",
                    info.joints_of(&mob.indeterminate_rows).join(", ")
                );
            }
        }
        Err(e) => {
            let _ = writeln!(s, "Mobility: not assembled ({e}).");
        }
    }
    s
}

/// The derived equations of a built-in mechanism or a `.mech` file, as text or LaTeX. A
/// file is derived once: the equations printed are the ones the mobility is computed from.
pub fn equations(spec: &str, latex: bool) -> Result<String, CliError> {
    let err = |e: mechanism_codegen::Error| CliError::Mechanism(located(spec, &e));
    let file = is_file_spec(spec);
    let (source, builtin_system) = if file {
        let source = read_input(Path::new(spec)).map_err(CliError::Mechanism)?;
        (source, None)
    } else {
        let loaded = load(spec, Tangents::None)?;
        (loaded.source, Some(loaded.system))
    };
    let derived = mechanism_codegen::parse_model_str_with(&source, derivation_budget()?)
        .and_then(|mut model| mechanism_codegen::derive(&mut model).map(|eqs| (model, eqs)));
    derivation_done();
    let (model, eqs) = derived.map_err(err)?;
    if latex {
        return Ok(mechanism_codegen::equations_latex(&model, &eqs));
    }
    let mut text = mechanism_codegen::equations_text(&model, &eqs);
    text.push('\n');
    if model.floating_root().is_some() {
        let joints = model.coordinates.len() - 6;
        let _ = writeln!(
            text,
            "Mobility: a floating base, no constraint rows: 6 + {joints} degrees of freedom."
        );
        // The equations above are written in v (their q' is v, their q'' is a = v'), q
        // in the configuration's layout: say so first.
        let joints: Vec<&str> = (model.coordinates[6..].iter())
            .map(|c| c.name.as_str())
            .collect();
        let root = &model.coordinates[0].name;
        let base = root.strip_suffix("_vx").unwrap_or(root);
        let note = format!(
            "Floating base: the coordinates below are the velocities v (der(NAME) reads v's \
             entry NAME, der(der(NAME)) its rate a); the configuration is q = [{base}_x, \
             {base}_y, {base}_z, {base}_qx, {base}_qy, {base}_qz, {base}_qw{}{}] ({} entries), \
             p' = R v, R' = R [w]x.\n",
            if joints.is_empty() { "" } else { ", " },
            joints.join(", "),
            model.configuration_size()
        );
        return Ok(note + &text);
    }
    // A file's mobility needs its constraint rows only: compiling the dynamics as well
    // would be most of the command's work on a large mechanism.
    let mobility = match builtin_system {
        Some(system) => mobility_text(system.as_ref()),
        None => mobility_text(
            &InterpretedConstraints::from_equations(model, &eqs)
                .map_err(|e| CliError::Mechanism(format!("{spec}: {e}")))?,
        ),
    };
    text.push_str(&mobility);
    Ok(text)
}
