//! Derivation time and op counts of the closed planar N-bar chain (the scaling family of the benchmarks).
//! Run with
//! `cargo test --release -p mechanism-codegen --test lagrange_chain_timing -- --ignored --nocapture`.

use std::time::Instant;

use mechanism_codegen::fixtures::closed_chain_model;
use mechanism_codegen::{Program, derive};

#[test]
#[ignore = "timing report; run in release"]
fn chain_derivation_times() {
    let sympy = [(4, 293), (8, 1013), (16, 3605), (32, 13397)];
    for n in [4, 8, 16, 32, 64] {
        let mut model = closed_chain_model(n);
        let start = Instant::now();
        let eqs = derive(&mut model).expect("chain derives");
        let derived = start.elapsed();
        let outputs = [
            &eqs.mass,
            &eqs.coriolis_forces,
            &eqs.gravity,
            &eqs.phi,
            &eqs.phi_q,
            &eqs.gamma,
        ];
        let program = Program::new(&model.arena, &outputs).expect("program");
        let total = start.elapsed();
        let ops = program.op_counts();
        let reference = sympy
            .iter()
            .find(|s| s.0 == n)
            .map_or("-".to_string(), |s| s.1.to_string());
        println!(
            "N = {n:3}: derive {:8.2} ms, derive + CSE {:8.2} ms, {} nodes, {ops} (SymPy {reference})",
            derived.as_secs_f64() * 1e3,
            total.as_secs_f64() * 1e3,
            model.arena.len(),
        );
        for (k, name) in ["M", "Cq'", "g", "Phi", "Phi_q", "gamma"]
            .iter()
            .enumerate()
        {
            if let Some(c) = program.output_op_counts(k) {
                println!("      {name:6} {c}");
            }
        }
    }
}
