//! `cargo run --release -p mechanism-codegen --example derivative_ops URDF [LOCKED_JOINT ...]`:
//! the operations per call of the derivative
//! programs `mechanism!` emits for a robot imported from its URDF (as `mechanism import`
//! writes it, the named joints locked), and of each form of dtau/dq, dtau/dq' the compile
//! stage chooses among (`mechanism_codegen::inverse_dynamics_derivative_forms`), each
//! compiled alone by the same passes (`Program::new`). One JSON object on stdout (benches/derivatives.py reads it):
//!
//! - `inverse_dynamics`, `mass_and_bias`, `inverse_dynamics_derivatives`: the emitted
//!   routines' programs (additions, multiplications, divisions and calls per call);
//! - `forms`: {form: operations} of each form compiled alone (without the hoisting of
//!   parameter-only values into the cache, which the emitted routine has: the emitted
//!   count can be lower than its form's);
//! - `forward_dynamics`, `forward_dynamics_derivatives`: the emitted q'' and the one
//!   program of dq''/dq, dq''/dq', M^-1 (q'' and the factorisation over M's pattern inside);
//! - `dense_route`: what the trait's default (`mechanism::fixed::forward_dynamics_derivatives`)
//!   runs for the same: `mass_and_bias`, `inverse_dynamics_derivatives` and its dense loops
//!   at run time (Cholesky, q'', M^-1 = L^-T L^-1, two n-column solves, their negation),
//!   the loops counted by formula ([`dense_ops`]).

use mechanism_codegen::{
    Program, Role, UrdfOptions, compile, derive, full_tangent, inverse_dynamics_derivative_forms,
    parse_model_str, urdf_to_mech,
};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(urdf) = args.first() else {
        eprintln!("usage: derivative_ops URDF [LOCKED_JOINT ...]");
        std::process::exit(2);
    };
    let fail = |e: &dyn std::fmt::Display| -> ! {
        eprintln!("derivative_ops: {urdf}: {e}");
        std::process::exit(1);
    };
    let xml = std::fs::read_to_string(urdf).unwrap_or_else(|e| fail(&e));
    let options = UrdfOptions {
        file_name: urdf.clone(),
        lock: args[1..].to_vec(),
        ..Default::default()
    };
    let text = urdf_to_mech(&xml, &options).unwrap_or_else(|e| fail(&e));
    let parse = || parse_model_str(&text).unwrap_or_else(|e| fail(&e));

    let mut model = parse();
    let eqs = derive(&mut model).unwrap_or_else(|e| fail(&e));
    let tangent = full_tangent(&mut model, &eqs).unwrap_or_else(|e| fail(&e));
    let routines = compile(&mut model, &eqs, &tangent).unwrap_or_else(|e| fail(&e));
    let ops = |role| {
        (routines.program(role))
            .map(|p| p.op_counts().total())
            .unwrap_or_else(|e| fail(&e))
    };
    let emitted = ops(Role::InverseDynamicsDerivatives);

    // The forms on a fresh derivation, so that each is compiled from the same arena state
    // the compile stage saw.
    let mut model = parse();
    let eqs = derive(&mut model).unwrap_or_else(|e| fail(&e));
    let forms = inverse_dynamics_derivative_forms(&mut model, &eqs).unwrap_or_else(|e| fail(&e));
    let counted: Vec<String> = forms
        .iter()
        .map(|(name, [dq, dqd])| {
            let program = Program::new(&model.arena, &[dq, dqd]).unwrap_or_else(|e| fail(&e));
            format!("\"{name}\": {}", program.op_counts().total())
        })
        .collect();
    let dense = ops(Role::MassAndBias) + emitted + dense_ops(eqs.n);
    println!(
        "{{\"n\": {}, \"inverse_dynamics\": {}, \"mass_and_bias\": {}, \
         \"inverse_dynamics_derivatives\": {emitted}, \"forms\": {{{}}}, \
         \"forward_dynamics\": {}, \"forward_dynamics_derivatives\": {}, \
         \"dense_route\": {dense}}}",
        eqs.n,
        ops(Role::InverseDynamics),
        ops(Role::MassAndBias),
        counted.join(", "),
        ops(Role::ForwardDynamics),
        ops(Role::ForwardDynamicsDerivatives),
    );
}

/// The floating-point operations of the dense loops of `mechanism::fixed`'s
/// `forward_dynamics_derivatives` for n coordinates (a multiply-add counted as two, a
/// square root or division as one, no entry skipped as zero): the Cholesky factor
/// L L^T = M, q'' = M^-1 (u - b) (n subtractions, two triangular solves), M^-1 = W^T W with
/// W = L^-1, and -M^-1 B for two n-column B (two triangular solves per column, the
/// reciprocal pivots once per row, n^2 negations each).
fn dense_ops(n: usize) -> usize {
    let cholesky: usize = (0..n).map(|j| 2 * j + 1 + (n - 1 - j) * (2 * j + 1)).sum();
    let solve = n + 2 * (n * (n - 1) + n);
    let w: usize = (0..n)
        .map(|j| 1 + (j + 1..n).map(|i| 2 * (i - j) + 1).sum::<usize>())
        .sum();
    let product: usize = (0..n).map(|i| (i + 1) * 2 * (n - i)).sum();
    let columns = 2 * (n * (n - 1) * n + n * n + n) + n * n;
    cholesky + solve + w + product + 2 * columns
}
