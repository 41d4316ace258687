//! `stage_times FILE.mech`: the wall and CPU time of each stage the command-line tool runs on one
//! declaration (parse, derive, the routines without the tangent, the equations text), once
//! each, printed one per line (the stage that dominates a large mechanism's derivation);
//! then what an implicit integrator adds (the residual's tangent, and the routines compiled
//! with it), each with the peak resident memory and the arena's work and size so far
//! (`mechanism_codegen::Effort`). With `--equations`, the stages of `mechanism equations`
//! instead: parse, derive, the text and the constraint rows' routines (for the mobility).

use std::time::Instant;

// The command-line tool's allocator, so the stages cost what they cost there.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: stage_times FILE.mech [--equations]");
        std::process::exit(2);
    };
    let source = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        eprintln!("stage_times: {path}: {e}");
        std::process::exit(1);
    });
    let fail = |e: mechanism_codegen::Error| -> ! {
        eprintln!("stage_times: {path}: {e}");
        std::process::exit(1);
    };
    let clock = Instant::now();
    let cpu = || mechanism_bench::thread_cpu().unwrap_or(f64::NAN);
    let (mut last, mut last_cpu) = (0.0, cpu());
    let mut lap = |stage: &str, effort: mechanism_codegen::Effort| {
        let (now, now_cpu) = (clock.elapsed().as_secs_f64(), cpu());
        println!(
            "{stage:<10} {:8.3} s wall {:8.3} s CPU {:7.0} MB peak; work {:>11}, size {:>11}",
            now - last,
            now_cpu - last_cpu,
            mechanism_bench::peak_memory_mb().unwrap_or(f64::NAN),
            effort.work,
            effort.size
        );
        (last, last_cpu) = (now, now_cpu);
    };
    // The budget the command-line tool reads (`MECHANISM_MAX_SIZE` and the others).
    let budget = mechanism_codegen::Budget::from_lookup(|name| std::env::var(name).ok())
        .unwrap_or_else(|e| {
            eprintln!("stage_times: {e}");
            std::process::exit(2);
        });
    let mut model =
        mechanism_codegen::parse_model_str_with(&source, budget).unwrap_or_else(|e| fail(e));
    lap("parse", model.arena.effort());
    let eqs = mechanism_codegen::derive(&mut model).unwrap_or_else(|e| fail(e));
    lap("derive", model.arena.effort());
    if std::env::args().nth(2).as_deref() == Some("--equations") {
        // `mechanism equations`: the text, then the constraint rows alone for the mobility.
        let _ = mechanism_codegen::equations_text(&model, &eqs);
        lap("text", model.arena.effort());
        mechanism_codegen::compile_constraints(&mut model, &eqs).unwrap_or_else(|e| fail(e));
        lap("rows", model.arena.effort());
        return;
    }
    // The routines an explicit integrator's run compiles.
    let routines =
        mechanism_codegen::compile_interpreted(&mut model, &eqs, None).unwrap_or_else(|e| fail(e));
    lap("compile", model.arena.effort());
    let text = mechanism_codegen::equations_text(&model, &eqs);
    lap("text", model.arena.effort());
    // What an implicit integrator adds: the residual's tangent, and the routines with it.
    let tangent = mechanism_codegen::residual_tangent(&mut model, &eqs).unwrap_or_else(|e| fail(e));
    lap("tangent", model.arena.effort());
    let with_tangent = mechanism_codegen::compile_interpreted(&mut model, &eqs, Some(&tangent))
        .unwrap_or_else(|e| fail(e));
    lap("compile+t", model.arena.effort());
    // The fingerprints tell whether a change left the compiled programs as they were.
    println!(
        "{} routines ({} with the tangent), {} bytes of text; fingerprints {:016x} {:016x}",
        routines.iter().count(),
        with_tangent.iter().count(),
        text.len(),
        routines.fingerprint(),
        with_tangent.fingerprint()
    );
}
