//! `role_ops [--derived] FILE.mech...`: the arithmetic operations (additions and subtractions,
//! multiplications, divisions, function calls) of each robotics routine's program as
//! `mechanism!` compiles it (`mechanism_codegen::compile`: CSE, factoring, fusion, the
//! parameter-only values moved into the cache, which is not counted), one markdown row per
//! file: M, C q', g, C q' + g (`coriolis_forces` and `gravity` as the two programs they are,
//! and the bias C q' + g - tau in one program where the routines have it), M with the bias,
//! the inverse dynamics and the forward dynamics (M, the bias and the factorisation
//! M = L^T D L with its solve, in one program). A forward dynamics without a program of
//! its own (before it had one) is `mass_and_bias` plus the dense Cholesky factorisation
//! and solve at run time,
//! counted as n^3/6 + n^2/2 multiplications and as many additions, n square roots and
//! n^2 + n divisions and multiplications for the solve (written `+ chol`). With
//! `ROLE_OPS_DUMP=<Role>` (`Mass`, `Bias`, `InverseDynamics`, ...) it also prints that
//! role's emitted body; every role's counts go to stderr.

use mechanism_codegen::{OpCounts, Role, Routines};

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn total(routines: &Routines, role: Role) -> Option<usize> {
    routines.get(role).map(|p| p.op_counts().total())
}

fn describe(c: OpCounts) -> String {
    format!(
        "{} (+{} *{} /{} f{})",
        c.total(),
        c.adds,
        c.muls,
        c.divs,
        c.calls
    )
}

/// `--derived`: the programs of the derived M, g, bias and inverse dynamics lowered on
/// their own (`Program::new`, no parameter cache), without the tangent and the other roles:
/// for chains of hundreds of links, whose forward dynamics and tangent the macro alone
/// would compile.
fn derived(paths: &[String]) {
    println!("| mechanism | n | M | g | C q' + g | inverse dynamics |");
    println!("|---|---:|---:|---:|---:|---:|");
    for path in paths {
        let source = std::fs::read_to_string(path).expect("readable");
        let mut model = mechanism_codegen::parse_model_str(&source).expect("parses");
        let eqs = mechanism_codegen::derive(&mut model).expect("derives");
        let ops = |m: &mechanism_codegen::Matrix| {
            let p = mechanism_codegen::Program::new(&model.arena, &[m]).expect("lowers");
            p.op_counts().total()
        };
        println!(
            "| {} | {} | {} | {} | {} | {} |",
            model.name,
            eqs.n,
            ops(&eqs.mass),
            ops(&eqs.gravity),
            ops(&eqs.bias),
            ops(&eqs.inverse_dynamics)
        );
    }
}

fn main() {
    let mut paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        eprintln!("usage: role_ops [--derived] FILE.mech...");
        std::process::exit(2);
    }
    if paths[0] == "--derived" {
        paths.remove(0);
        derived(&paths);
        return;
    }
    println!(
        "| mechanism | n | M | C q' | g | C q' + g | M and bias | inverse dynamics | forward dynamics |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for path in paths {
        let fail = |e: mechanism_codegen::Error| -> ! {
            eprintln!("role_ops: {path}: {e}");
            std::process::exit(1);
        };
        let source = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            eprintln!("role_ops: {path}: {e}");
            std::process::exit(1);
        });
        let mut model = mechanism_codegen::parse_model_str(&source).unwrap_or_else(|e| fail(e));
        let eqs = mechanism_codegen::derive(&mut model).unwrap_or_else(|e| fail(e));
        let tangent =
            mechanism_codegen::residual_tangent(&mut model, &eqs).unwrap_or_else(|e| fail(e));
        let r = mechanism_codegen::compile(&mut model, &eqs, &tangent).unwrap_or_else(|e| fail(e));
        let n = eqs.n;
        let get = |role| total(&r, role).map_or("-".to_string(), |t| t.to_string());
        let (c, g) = (
            total(&r, Role::CoriolisForces).unwrap_or(0),
            total(&r, Role::Gravity).unwrap_or(0),
        );
        let bias = match total(&r, Role::Bias) {
            Some(b) => format!("{b} (two programs {c} + {g})"),
            None => format!("{} ({c} + {g})", c + g),
        };
        // The dense Cholesky of M and its two triangular solves, flop by flop.
        let chol = n * n * n / 6 + n * n / 2 + n + (n * n / 2 + n * n / 2) * 2 + n * n + n;
        let forward = match total(&r, Role::ForwardDynamics) {
            Some(f) => f.to_string(),
            None => format!("{} + chol {chol}", get(Role::MassAndBias)),
        };
        println!(
            "| {} | {n} | {} | {} | {} | {bias} | {} | {} | {forward} |",
            model.name,
            get(Role::Mass),
            c,
            g,
            get(Role::MassAndBias),
            get(Role::InverseDynamics),
        );
        if let Ok(which) = std::env::var("ROLE_OPS_DUMP") {
            for (role, _) in r.iter() {
                if format!("{role:?}") == which {
                    dump(&r, role);
                }
            }
        }
        for (role, p) in r.iter() {
            eprintln!("{:<24} {}", format!("{role:?}"), describe(p.op_counts()));
        }
    }
}

/// Prints the emitted body of `role` (with `ROLE_OPS_DUMP=Mass`, say), its inputs named
/// `q[i]`, `qd[i]`, `p[k]`, `cache[k]`, ...: to read where a routine's operations go.
fn dump(r: &Routines, role: Role) {
    use mechanism_codegen::{EmitBindings, OutputTarget, Source, emit_body};
    use quote::quote;
    let mut b = EmitBindings::new();
    b.set_prefix("v");
    b.set_math(quote!(m));
    for (symbol, source) in r.sources().iter() {
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
    let p = r.get(role).unwrap();
    let targets: Vec<_> = p
        .outputs()
        .iter()
        .map(|_| OutputTarget::Matrix {
            name: quote!(out),
            zeroed: true,
        })
        .collect();
    let body = emit_body(p, &b, &targets).unwrap().tokens;
    println!("{}", body.to_string().replace("; ", ";\n"));
}
