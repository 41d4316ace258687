//! The values given on the command line, applied ([`apply_sets`], [`initial_values`]) and
//! checked like declared ones: `--set` values against
//! the declaration's checks and a mass matrix with no negative direction, `--init` values
//! within a range where a step can still change them.
//!
//! - **`--set`.** A value outside the parameter's declared range (`r = 0.1 positive;`) is
//!   refused by `set_parameter` itself. The declaration is built again with the parameters
//!   at their new values ([`mechanism_codegen::check_parameter_values`]): a body's mass not
//!   negative, a wheel's radius positive, its inertia physically possible, its orientation
//!   a rotation. The initial guesses and independent values written with parameters follow
//!   the new values (`System::set_parameter` evaluates them again). Then, as the derivation tests
//!   T at the declared values, M(q) at the initial guesses (t = 0) must have no eigenvalue
//!   below -1e-9 times its largest entry: a negative mass or inertia written into T
//!   directly (`1/2*m2*v^2` with `m2 = -1`) shows there. The error names the `--set` that
//!   causes it: each is undone in turn, and the first without which the check passes is
//!   named (all of them when none alone is to blame).
//! - **`--init`.** |value| at most [`MAX_INITIAL_VALUE`], for a position and for a rate.
//! - **The assembled state.** The declaration's checks that depend on the coordinates (a
//!   body's explicit orientation a rotation) run again there ([`check_assembled`]).

use nalgebra::SymmetricEigen;

use super::CliError;
use super::args::{CommonArgs, check_repeated, split_assignment};
use super::load::{Loaded, did_you_mean, finite_constant};
use mechanism::{Evaluation, Independent, System};

/// Largest |value| of an `--init` position or rate, 1e9: the spacing of f64 values there is
/// 1.2e-7, so a step of a slow motion still moves it; at 1e300 the spacing is 1.5e284 and
/// no step can change the value, which stays frozen in every sample.
pub const MAX_INITIAL_VALUE: f64 = 1e9;

/// Relative size of a negative eigenvalue of M that counts as a negative direction (as the
/// derivation's test of T).
const NEGATIVE_EIGENVALUE: f64 = 1e-9;

/// Checks `value` of `--init lhs` (a position, or a rate `der(..)` when `rate`) against
/// [`MAX_INITIAL_VALUE`]. A rate is held to the positions' range: beyond 1e9 per second the
/// coordinate would leave it within a second.
pub fn check_initial_value(lhs: &str, value: f64, rate: bool) -> Result<(), CliError> {
    if value.abs() <= MAX_INITIAL_VALUE {
        return Ok(());
    }
    let why = if rate {
        "a rate beyond 1e9 per second carries its coordinate past the 1e9 allowed for a \
         position within a second"
            .to_string()
    } else {
        let spacing = value.abs().next_up() - value.abs();
        format!(
            "f64 values there are {spacing:.1e} apart (at 1e9, 1.2e-7), so no integration step \
             could change it and the coordinate would stay frozen"
        )
    };
    Err(CliError::Argument(format!(
        "--init {lhs}: |value| must be at most 1e9, got {value:e}: {why}"
    )))
}

/// Checks the parameters of `loaded` after `sets` (`NAME=VALUE`, already applied), see the
/// module docs.
pub fn check_set_values(loaded: &mut Loaded, sets: &[(usize, String)]) -> Result<(), CliError> {
    let Err(message) = check_values(loaded) else {
        return Ok(());
    };
    let mut blamed = Vec::new();
    for (index, text) in sets {
        let mut values = vec![0.0; loaded.declared.len()];
        loaded.system.parameter_values(&mut values);
        // The declared value and the value set were both admitted: neither can be refused.
        let undone = loaded.system.set_parameter(*index, loaded.declared[*index]);
        let passes_without = undone.is_ok() && check_values(loaded).is_ok();
        let _ = loaded.system.set_parameter(*index, values[*index]);
        if passes_without {
            blamed.push(text.as_str());
            break;
        }
    }
    if blamed.is_empty() {
        blamed = sets.iter().map(|s| s.1.as_str()).collect();
    }
    Err(CliError::Argument(format!(
        "--set {}: {message}",
        blamed.join(" --set ")
    )))
}

/// Checks the declaration of `loaded` at the assembled state `q` (t = 0) and the current
/// parameter values: the declared checks that depend on the coordinates, a body's explicit
/// orientation a rotation, run there too (they ran at the initial guesses when the
/// declaration was built; an orientation can be a rotation there and not at the state the
/// run starts from).
pub fn check_assembled(loaded: &Loaded, q: &[f64]) -> Result<(), CliError> {
    // Only an explicit `orientation` depends on the coordinates among these checks.
    if !loaded.source.contains("orientation") {
        return Ok(());
    }
    let named = named_values(loaded.system.as_ref(), q);
    let named: Vec<(&str, f64)> = named.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    mechanism_codegen::check_parameter_values(&loaded.source, &named)
        .map_err(|e| CliError::Mechanism(super::load::located(&loaded.shown, &e)))
}

/// The checks of the module docs on the current parameter values; the first failure.
fn check_values(loaded: &Loaded) -> Result<(), String> {
    let system = loaded.system.as_ref();
    let named = named_values(system, &[]);
    let named: Vec<(&str, f64)> = named.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    mechanism_codegen::check_parameter_values(&loaded.source, &named)
        .map_err(|e| super::load::located(&loaded.shown, &e))?;
    negative_direction(system)
}

/// The parameters' current values by name, then the first `q.len()` coordinates at `q`.
fn named_values(system: &dyn System, q: &[f64]) -> Vec<(String, f64)> {
    let info = system.info();
    let mut values = vec![0.0; info.parameters.len()];
    system.parameter_values(&mut values);
    let parameters = info.parameters.iter().cloned().zip(values);
    let coordinates = info.coordinates.iter().cloned().zip(q.iter().copied());
    parameters.chain(coordinates).collect()
}

/// M(q) at the initial guesses and t = 0 with no negative direction (see the module docs).
fn negative_direction(system: &dyn System) -> Result<(), String> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    let mut e = Evaluation::zeros(n, m);
    system.evaluate(0.0, &info.initial_guess, &vec![0.0; n], &mut e);
    let mass = e.mass.clone();
    let scale = mass.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    if !mass.iter().all(|v| v.is_finite()) || scale == 0.0 {
        return Ok(());
    }
    let eigen = SymmetricEigen::new(mass);
    let (k, lowest) = eigen
        .eigenvalues
        .iter()
        .copied()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, 0.0));
    if lowest >= -NEGATIVE_EIGENVALUE * scale {
        return Ok(());
    }
    let direction = eigen.eigenvectors.column(k);
    let along = (0..n)
        .max_by(|&a, &b| direction[a].abs().total_cmp(&direction[b].abs()))
        .map_or("", |c| info.coordinates[c].as_str());
    Err(format!(
        "the kinetic energy can be negative: at the initial guesses (t = 0) the mass matrix M \
         has the eigenvalue {lowest:.4e}, mostly along `{along}`; a mass or moment of inertia \
         cannot be negative"
    ))
}

/// Applies every `--set NAME=VALUE`, then checks the values like declared ones
/// ([`check_set_values`]).
pub fn apply_sets(loaded: &mut Loaded, sets: &[String]) -> Result<(), CliError> {
    check_repeated("--set", sets)?;
    let mut applied = Vec::with_capacity(sets.len());
    for s in sets {
        let system = loaded.system.as_mut();
        let (name, value) = split_assignment(s)
            .ok_or_else(|| CliError::Argument(format!("--set takes PARAM=VALUE, got `{s}`")))?;
        let info = system.info();
        let index = info.parameter_index(name).ok_or_else(|| {
            CliError::Argument(format!(
                "--set: unknown parameter `{name}`{}; parameters: {}",
                did_you_mean(name, &info.parameters),
                info.parameters.join(", ")
            ))
        })?;
        let v =
            finite_constant(value).map_err(|e| CliError::Argument(format!("--set {name}: {e}")))?;
        let range = info.parameter_range(index);
        system.set_parameter(index, v).map_err(|_| {
            CliError::Argument(format!(
                "--set {name}={value}: `{name}` must be {} (its declaration says `{}`), got {v}",
                range.describe(),
                range.keyword()
            ))
        })?;
        applied.push((index, format!("{name}={value}")));
    }
    if applied.is_empty() {
        return Ok(());
    }
    check_set_values(loaded, &applied)
}

/// The independent coordinates and the guess after every `--init COORD=VALUE` or
/// `--init 'der(COORD)=VALUE'`. A dependent coordinate's value replaces its guess (to pick
/// an assembly branch).
pub fn initial_values(
    system: &dyn System,
    common: &CommonArgs,
) -> Result<(Vec<Independent>, Vec<f64>), CliError> {
    check_repeated("--init", &common.init)?;
    let info = system.info();
    let mut independent = info.independent.clone();
    let mut guess = info.initial_guess.clone();
    for s in &common.init {
        let (lhs, value) = split_assignment(s).ok_or_else(|| {
            CliError::Argument(format!(
                "--init takes COORD=VALUE or der(COORD)=VALUE, got `{s}`"
            ))
        })?;
        let (name, rate) = match lhs.strip_prefix("der(").and_then(|r| r.strip_suffix(')')) {
            Some(inner) => (inner.trim(), true),
            None => (lhs, false),
        };
        let k = info.coordinate_index(name).ok_or_else(|| {
            CliError::Argument(format!(
                "--init: unknown coordinate `{name}`{}; coordinates: {}",
                did_you_mean(name, &info.coordinates),
                info.coordinates.join(", ")
            ))
        })?;
        let v =
            finite_constant(value).map_err(|e| CliError::Argument(format!("--init {lhs}: {e}")))?;
        check_initial_value(lhs, v, rate)?;
        match (independent.iter_mut().find(|i| i.coordinate == k), rate) {
            (Some(ind), false) => ind.position = v,
            (Some(ind), true) => ind.velocity = v,
            (None, false) => guess[k] = v,
            (None, true) => {
                let names: Vec<&str> = independent
                    .iter()
                    .map(|i| info.coordinates[i.coordinate].as_str())
                    .collect();
                return Err(CliError::Argument(format!(
                    "--init: der({name}) follows from the constraints; rates can be set for the independent coordinates ({})",
                    names.join(", ")
                )));
            }
        }
    }
    Ok((independent, guess))
}
