//! Shared helpers for the criterion benchmarks of `mechanism`: the benchmarked mechanisms
//! (compiled, interpreted, automatic differentiation), the macro's derivation pipeline, and
//! small timing utilities.
#![warn(missing_docs)]

pub mod a02;
pub mod ad_models;
pub mod autodiff;
pub mod n_four_bar;
pub mod simulation;

use mechanism::{Interpreted, System};
use mechanism_codegen::{
    EmitBindings, Equations, Matrix, Model, OpCounts, OutputTarget, Program, Result, Source,
    emit_body,
};
use quote::quote;

use crate::ad_models::{ChainAd, FourBarAd, RssrAd, SeedAd};
use crate::autodiff::AutoDiff;

/// The quantities the derivation benchmark covers: M, C q', g, Phi, Phi_q and gamma.
pub fn derived_outputs(eqs: &Equations) -> [&Matrix; 6] {
    [
        &eqs.mass,
        &eqs.coriolis_forces,
        &eqs.gravity,
        &eqs.phi,
        &eqs.phi_q,
        &eqs.gamma,
    ]
}

/// The five quantities of the evaluation target: M, C q', g, Phi and Phi_q.
pub fn five_outputs(eqs: &Equations) -> [&Matrix; 5] {
    [
        &eqs.mass,
        &eqs.coriolis_forces,
        &eqs.gravity,
        &eqs.phi,
        &eqs.phi_q,
    ]
}

/// Derives `model` and builds the CSE'd program of M, C q', g, Phi, Phi_q and gamma: the
/// whole derivation the issue measures. Returns the program's operation counts.
pub fn derive_and_cse(mut model: Model) -> Result<OpCounts> {
    let eqs = mechanism_codegen::derive(&mut model)?;
    let program = Program::new(&model.arena, &derived_outputs(&eqs))?;
    Ok(program.op_counts())
}

/// What `mechanism!` does at build time, minus the final `quote!` of the impl: parse the
/// declaration, derive the equations and every tangent (`full_tangent`: the residual's, the
/// constraint rows' and the inverse dynamics' derivatives), compile the routines
/// (`mechanism_codegen::compile`: one program per role, the parameter-only values moved
/// into the cache program), emit every body, and print the equations text. Returns the
/// number of emitted token trees (to keep the work observable).
pub fn macro_pipeline(source: &str) -> Result<usize> {
    let mut model = mechanism_codegen::parse_model_str(source)?;
    let eqs = mechanism_codegen::derive(&mut model)?;
    let tangent = mechanism_codegen::full_tangent(&mut model, &eqs)?;
    let routines = mechanism_codegen::compile(&mut model, &eqs, &tangent)?;
    let mut b = EmitBindings::new();
    b.set_prefix("v");
    b.set_math(quote!(::mechanism::math));
    for (symbol, source) in routines.sources().iter() {
        let tokens = match source {
            Source::Coordinate(i) => quote!(q[#i]),
            Source::Rate(i) => quote!(qd[#i]),
            Source::Acceleration(i) => quote!(qdd[#i]),
            Source::Parameter(k) => quote!(p[#k]),
            Source::Cache(k) => quote!(cache[#k]),
            Source::Time => quote!(t),
            Source::Multiplier(k) => quote!(lambda[#k]),
            Source::Effort(k) => quote!(effort[#k]),
        };
        b.bind(symbol, tokens);
    }
    let place = || OutputTarget::Matrix {
        name: quote!(out),
        zeroed: true,
    };
    let mut tokens = 0;
    for (_, p) in routines.iter() {
        let targets: Vec<_> = p.outputs().iter().map(|_| place()).collect();
        tokens += emit_body(p, &b, &targets)?.tokens.into_iter().count();
    }
    tokens += mechanism_codegen::equations_text(&model, &eqs).len();
    Ok(tokens)
}

/// Operation counts of one model's CSE'd programs: the five target quantities together
/// (M, C q', g, Phi, Phi_q), everything `evaluate` computes, and each quantity alone.
#[derive(Clone, Debug)]
pub struct ModelOps {
    /// M, C q', g, Phi, Phi_q in one program.
    pub five: OpCounts,
    /// The combined `evaluate` program (adds tau, Phi_t, gamma, T, Pi).
    pub evaluate: OpCounts,
    /// (name, counts) of M, C q', g, Phi, Phi_q, gamma alone.
    pub each: Vec<(&'static str, OpCounts)>,
}

/// The operation counts of the declaration `source` (see [`ModelOps`]).
pub fn model_ops(source: &str) -> Result<ModelOps> {
    let mut model = mechanism_codegen::parse_model_str(source)?;
    let e = mechanism_codegen::derive(&mut model)?;
    let arena = &model.arena;
    let ops = |ms: &[&Matrix]| Program::new(arena, ms).map(|p| p.op_counts());
    let (kin, pot) = (
        Matrix::column(vec![e.kinetic]),
        Matrix::column(vec![e.potential]),
    );
    Ok(ModelOps {
        five: ops(&five_outputs(&e))?,
        evaluate: ops(&[
            &e.mass,
            &e.coriolis_forces,
            &e.gravity,
            &e.forces,
            &e.phi,
            &e.phi_q,
            &e.phi_t,
            &e.gamma,
            &kin,
            &pot,
        ])?,
        each: vec![
            ("mass_matrix", ops(&[&e.mass])?),
            ("coriolis_forces", ops(&[&e.coriolis_forces])?),
            ("gravity", ops(&[&e.gravity])?),
            ("constraints", ops(&[&e.phi])?),
            ("constraint_jacobian", ops(&[&e.phi_q])?),
            ("constraint_gamma", ops(&[&e.gamma])?),
        ],
    })
}

/// The chain sizes compiled into this crate (files under `benches/mechanisms/`).
pub const CHAIN_SIZES: [usize; 3] = [8, 16, 32];

/// The declaration text of a chain compiled into this crate.
pub fn chain_source(n: usize) -> Option<&'static str> {
    Some(match n {
        8 => include_str!("../mechanisms/closed_chain_8.mech"),
        16 => include_str!("../mechanisms/closed_chain_16.mech"),
        32 => include_str!("../mechanisms/closed_chain_32.mech"),
        _ => return None,
    })
}

/// One benchmarked mechanism in its three forms.
pub struct Case {
    /// Short name used in benchmark ids ("seed", "four_bar", "rssr", "chain8", ...).
    pub name: &'static str,
    /// The declaration text.
    pub source: &'static str,
    /// The code emitted by `mechanism!`, as a run-time system.
    pub compiled: Box<dyn System>,
    /// Baseline (a): the interpreter route, derived at run time from `source`.
    pub interpreted: Box<dyn System>,
    /// Baseline (b): M, C q', g (and Phi_q, gamma) by num-dual at every call.
    pub autodiff: Box<dyn System>,
}

/// A [`Case`] from its compiled form; the interpreter route is derived from `source` and the
/// AD route built by `ad` with the compiled form's names and parameter values.
pub fn case(
    name: &'static str,
    source: &'static str,
    compiled: Box<dyn System>,
    ad: fn(&dyn System) -> Box<dyn System>,
) -> Case {
    let interpreted =
        Box::new(Interpreted::from_source(source).unwrap_or_else(|e| panic!("{name}: {e}")));
    let autodiff = ad(compiled.as_ref());
    Case {
        name,
        source,
        compiled,
        interpreted,
        autodiff,
    }
}

fn builtin(name: &str) -> (&'static str, Box<dyn System>) {
    let source = mechanism::builtin::builtin_source(name).expect("built-in source");
    (
        source,
        mechanism::builtin::builtin(name).expect("built-in mechanism"),
    )
}

/// The built-in cases: the seed crank-slider, the planar four-bar and the RSSR. (The chains
/// are compiled by the evaluation benchmark itself, so that the library stays light.)
pub fn builtin_cases() -> Vec<Case> {
    let (seed, seed_c) = builtin("spatial_crank_slider");
    let (four, four_c) = builtin("planar_four_bar");
    let (rssr, rssr_c) = builtin("spatial_four_bar");
    vec![
        case("seed", seed, seed_c, |s| {
            Box::new(AutoDiff::<SeedAd, 4, 3>::like(s))
        }),
        case("four_bar", four, four_c, |s| {
            Box::new(AutoDiff::<FourBarAd, 3, 2>::like(s))
        }),
        case("rssr", rssr, rssr_c, |s| {
            Box::new(AutoDiff::<RssrAd, 4, 3>::like(s))
        }),
    ]
}

/// The chain case of size `n` (8, 16 or 32) around its compiled form.
pub fn chain_case(n: usize, compiled: Box<dyn System>) -> Option<Case> {
    let source = chain_source(n)?;
    Some(match n {
        8 => case("chain8", source, compiled, |s| {
            Box::new(AutoDiff::<ChainAd<8>, 8, 2>::like(s))
        }),
        16 => case("chain16", source, compiled, |s| {
            Box::new(AutoDiff::<ChainAd<16>, 16, 2>::like(s))
        }),
        32 => case("chain32", source, compiled, |s| {
            Box::new(AutoDiff::<ChainAd<32>, 32, 2>::like(s))
        }),
        _ => return None,
    })
}

/// A consistent state of `system` (its declared assembly) with nonzero rates: q from the
/// assembly, q' = the assembled rates, or, for a system assembled at rest, a consistent
/// velocity with the first independent rate set to 1 rad/s.
pub fn state(system: &dyn System) -> (Vec<f64>, Vec<f64>) {
    let mut ind = system.info().independent.clone();
    if ind.iter().all(|i| i.velocity == 0.0)
        && let Some(first) = ind.first_mut()
    {
        first.velocity = 1.0;
    }
    let s = mechanism::assemble_from(
        system,
        0.0,
        &ind,
        &system.info().initial_guess,
        &mechanism::AssemblyOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{}: assembly failed: {e}", system.info().name));
    (s.q, s.qd)
}

/// Checks that the checked-in chain declarations are `closed_chain_source(n)`; with the
/// environment variable `MECHANISM_BLESS` set, rewrites them first.
///
/// # Panics
/// When a file is stale.
pub fn check_chain_files() {
    for n in CHAIN_SIZES {
        let path = format!(
            "{}/mechanisms/closed_chain_{n}.mech",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = mechanism_codegen::fixtures::closed_chain_source(n);
        if std::env::var_os("MECHANISM_BLESS").is_some() {
            std::fs::write(&path, &text).expect("write the chain file");
        }
        let old = std::fs::read_to_string(&path).unwrap_or_default();
        assert_eq!(old, text, "{path} is stale: rerun with MECHANISM_BLESS=1");
    }
}

fn close(a: &[f64], b: &[f64], what: &str, name: &str) {
    let scale = a.iter().chain(b).fold(1.0_f64, |s, v| s.max(v.abs()));
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-10 * scale,
            "{name} {what}: {a:?} vs {b:?}"
        );
    }
}

/// Checks that the three routes of `c` compute the same M, C q', g, tau, Phi, Phi_q, gamma,
/// T and Pi (to 1e-10 relative) at a consistent state: the baselines time the same thing.
///
/// # Panics
/// On a mismatch.
pub fn check_routes(c: &Case) {
    use mechanism::Evaluation;
    let (q, qd) = state(c.compiled.as_ref());
    let (n, m) = (q.len(), c.compiled.info().m());
    let eval = |s: &dyn System| {
        let mut e = Evaluation::zeros(n, m);
        s.evaluate(0.3, &q, &qd, &mut e);
        e
    };
    let reference = eval(c.compiled.as_ref());
    for (route, e) in [
        ("interpreted", eval(c.interpreted.as_ref())),
        ("autodiff", eval(c.autodiff.as_ref())),
    ] {
        let name = format!("{} {route}", c.name);
        let (r, e) = (&reference, &e);
        for (what, x, y) in [
            ("M", r.mass.as_slice(), e.mass.as_slice()),
            ("C q'", r.coriolis.as_slice(), e.coriolis.as_slice()),
            ("g", r.gravity.as_slice(), e.gravity.as_slice()),
            ("tau", r.forces.as_slice(), e.forces.as_slice()),
            ("Phi", r.phi.as_slice(), e.phi.as_slice()),
            ("Phi_q", r.phi_q.as_slice(), e.phi_q.as_slice()),
            ("gamma", r.gamma.as_slice(), e.gamma.as_slice()),
        ] {
            close(x, y, what, &name);
        }
        close(
            &[r.kinetic, r.potential],
            &[e.kinetic, e.potential],
            "T, Pi",
            &name,
        );
    }
}

/// CPU time this thread has run, in seconds (Linux: `/proc/thread-self/schedstat`, whose
/// first field is the time on the CPU in ns); `None` elsewhere. On a machine shared with
/// other work it is what the run itself cost, where the wall time also counts the waits
/// for a core.
pub fn thread_cpu() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// The process's peak resident memory so far in MB (`VmHWM` of `/proc/self/status`, Linux);
/// `None` elsewhere.
pub fn peak_memory_mb() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}
