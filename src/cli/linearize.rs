//! `mechanism linearize`: the linearisation about an equilibrium or a steady motion in
//! minimal variables ([`mechanism::linearize_steady`]), its eigenvalues printed and
//! written with the state matrix to `linearization.json`, under the output folder's lock
//! ([`FolderLock`]).

use std::fmt::Write as _;
use std::path::PathBuf;

use super::CliError;
use super::args::{CommonArgs, FiguresArg, LinearizeArgs, ViewArg};
use super::load::{key_of, load_for_linearization};
use super::physical::{apply_sets, initial_values};
use super::stdio::print;
use mechanism::output::{FolderLock, OutputError, write_atomically};
use mechanism::{AssemblyOptions, SteadyLinearization, SteadyOptions, System};
use mechanism::{assemble_from, linearize_steady};

/// The file `linearize` writes.
pub const LINEARIZATION_FILE: &str = "linearization.json";

/// Runs `linearize` with `a`.
pub fn run(a: &LinearizeArgs) -> Result<(), CliError> {
    super::floating::refuse(&a.mechanism, "linearize")?;
    let mut loaded = load_for_linearization(&a.mechanism)?;
    apply_sets(&mut loaded, &a.set)?;
    let system = loaded.system.as_ref();
    let (independent, guess) = initial_values(system, &common(a))?;
    let state = assemble_from(
        system,
        0.0,
        &independent,
        &guess,
        &AssemblyOptions::default(),
    )?;
    let lin = linearize_steady(system, 0.0, &state.q, &state.qd, &SteadyOptions::default())?;
    let dir = match &a.out {
        Some(d) => d.clone(),
        None => PathBuf::from("out").join(key_of(&a.mechanism).unwrap_or(loaded.key.clone())),
    };
    let path = dir.join(LINEARIZATION_FILE);
    let json = document(system, &state.q, &state.qd, &lin);
    // The folder is claimed like the other writing commands claim theirs, once the
    // linearisation is computed (a refusal before leaves it untouched): a run writing there
    // refuses this one, and this one a run that comes while it writes.
    let lock = FolderLock::acquire(&dir)?;
    write_atomically(&path, |tmp| {
        std::fs::write(tmp, json.as_bytes()).map_err(|source| io_error(tmp, source))
    })?;
    drop(lock);
    print(&report(system, &lin, &path.display().to_string()))
}

fn io_error(path: &std::path::Path, source: std::io::Error) -> OutputError {
    OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The `CommonArgs` whose `--init` values [`initial_values`] reads.
fn common(a: &LinearizeArgs) -> CommonArgs {
    CommonArgs {
        mechanism: a.mechanism.clone(),
        t_end: 0.0,
        samples_per_second: 1.0,
        set: a.set.clone(),
        init: a.init.clone(),
        out: a.out.clone(),
        no_animation: true,
        view: ViewArg::Auto,
        strobe: 1,
        figures: FiguresArg::None,
    }
}

/// The printed report: the variables, the eigenvalues, the structural zeros.
fn report(system: &dyn System, lin: &SteadyLinearization, path: &str) -> String {
    let mut s = String::new();
    let name = &system.info().name;
    let _ = writeln!(
        s,
        "{name}: linearised in {} minimal variables: {}",
        lin.variables.len(),
        lin.variables.join(", ")
    );
    let structural: Vec<&str> = lin
        .structural
        .iter()
        .map(|&k| lin.variables[k].as_str())
        .collect();
    let _ = writeln!(
        s,
        "structural zero eigenvalues ({}): {}",
        structural.len(),
        if structural.is_empty() {
            "none".to_string()
        } else {
            structural.join(", ")
        }
    );
    let _ = writeln!(s, "eigenvalues without the structural zeros (1/s):");
    if lin.reduced.is_empty() {
        let _ = writeln!(s, "  none: every variable gives a structural zero");
    }
    for e in sorted(&lin.reduced) {
        let _ = writeln!(s, "  {:+.14e} {:+.14e} i", e[0], e[1]);
    }
    let _ = writeln!(s, "wrote {path}");
    s
}

/// Eigenvalues as [re, im], sorted by real part, then imaginary part.
fn sorted(values: &[nalgebra::Complex<f64>]) -> Vec<[f64; 2]> {
    let mut v: Vec<[f64; 2]> = values.iter().map(|c| [c.re, c.im]).collect();
    v.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    v
}

/// linearization.json.
fn document(system: &dyn System, q: &[f64], qd: &[f64], lin: &SteadyLinearization) -> String {
    let info = system.info();
    let mut parameters = vec![0.0; info.parameters.len()];
    system.parameter_values(&mut parameters);
    let named = |values: &[f64]| -> serde_json::Map<String, serde_json::Value> {
        info.coordinates
            .iter()
            .zip(values)
            .map(|(n, v)| (n.clone(), serde_json::json!(v)))
            .collect()
    };
    let rows: Vec<Vec<f64>> = (0..lin.state.nrows())
        .map(|i| lin.state.row(i).iter().copied().collect())
        .collect();
    let doc = serde_json::json!({
        "mechanism": info.name,
        "parameters": info.parameters.iter().zip(&parameters)
            .map(|(n, v)| (n.clone(), serde_json::json!(v)))
            .collect::<serde_json::Map<_, _>>(),
        "state": { "q": named(q), "qd": named(qd) },
        "variables": lin.variables,
        "state_matrix": rows,
        "eigenvalues": sorted(&lin.eigenvalues),
        "structural_zeros": lin.structural.iter().map(|&k| &lin.variables[k]).collect::<Vec<_>>(),
        "eigenvalues_without_structural_zeros": sorted(&lin.reduced),
    });
    let mut text = serde_json::to_string_pretty(&doc).unwrap_or_default();
    text.push('\n');
    text
}
