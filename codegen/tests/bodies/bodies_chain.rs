//! The closed N-bar chain declared with bodies: the same M, g, Phi_q as the energy-built
//! chain of `closed_chain_model(n)`, and a derivation that stays fast at N = 32 (M formed
//! from the Jacobians, T never differentiated twice term by term).
//!
//! Tolerance 1e-11 absolute: the entries are sums of up to N = 32 products of O(1) terms in
//! a different order (rounding ~N * 1e-16 * N); a wrong lever arm is off by O(1).

use std::time::Instant;

use mechanism_codegen::fixtures::{closed_chain_arch, closed_chain_model};
use mechanism_codegen::{Equations, Model, SymbolId, derive, eval_matrix, parse_model_str};

/// The chain of `n` uniform rods (length 1, mass 1, inertia 1/12) as bodies: rod i turns by
/// rot_z(th_i), its centre is the tip T_{i-1} of rod i - 1 plus R_i (1/2, 0, 0).
fn body_chain(n: usize) -> String {
    let arch = closed_chain_arch(n);
    let mut s = format!(
        "/// Chain.\npub struct BodyChain{n};\nparameters {{ g = 9.81; X = {}; }}\ncoordinates {{ ",
        n as f64 / 2.0
    );
    for (i, a) in arch.iter().enumerate() {
        s += &format!("th{} = {a}; ", i + 1);
    }
    s += "}\nindependent { ";
    for (i, a) in arch.iter().enumerate().take(n - 2) {
        s += &format!("th{} = {a}; ", i + 1);
    }
    s += "}\ngravity = [0, -g, 0];\n";
    for i in 1..=n {
        let base = if i == 1 {
            String::new()
        } else {
            format!("T{} + ", i - 1)
        };
        s += &format!(
            "body rod{i} {{ mass = 1; orientation = rot_z(th{i}); \
             position = {base}rot_z(th{i}) * [1/2, 0, 0]; inertia = diag(0, 1/12, 1/12); \
             point T{i} = [1/2, 0, 0]; }}\n"
        );
    }
    s += &format!("joints {{ [T{n}.x, T{n}.y] = [X, 0]; }}\n");
    s
}

fn state_env(model: &Model, n: usize, seed: f64) -> impl Fn(SymbolId) -> Option<f64> + use<> {
    let mut table: Vec<(SymbolId, f64)> = model
        .parameters
        .iter()
        .filter_map(|p| model.arena.as_symbol(p.symbol).map(|s| (s, p.default)))
        .collect();
    for i in 1..=n {
        let x = (seed * i as f64).sin() * 2.0;
        let v = (seed * 1.7 * i as f64).cos() * 3.0;
        for (name, val) in [(format!("th{i}"), x), (format!("der(th{i})"), v)] {
            if let Some(s) = model.arena.lookup(&name) {
                table.push((s, val));
            }
        }
    }
    move |s| table.iter().find(|e| e.0 == s).map(|e| e.1)
}

fn compare(n: usize) {
    let mut energy = closed_chain_model(n);
    let ee: Equations = derive(&mut energy).unwrap();
    let mut bodies = parse_model_str(&body_chain(n)).unwrap();
    let be = derive(&mut bodies).unwrap();
    for seed in [0.37, 1.21] {
        let (ea, ba) = (state_env(&energy, n, seed), state_env(&bodies, n, seed));
        for (name, a, b) in [
            ("M", &ee.mass, &be.mass),
            ("g", &ee.gravity, &be.gravity),
            ("Cq'", &ee.coriolis_forces, &be.coriolis_forces),
            ("Phi_q", &ee.phi_q, &be.phi_q),
            ("gamma", &ee.gamma, &be.gamma),
        ] {
            let va = eval_matrix(&energy.arena, a, &ea).unwrap();
            let vb = eval_matrix(&bodies.arena, b, &ba).unwrap();
            for (k, (x, y)) in va.iter().zip(&vb).enumerate() {
                assert!((x - y).abs() < 1e-11, "N = {n} {name}[{k}]: {x} vs {y}");
            }
        }
    }
}

#[test]
fn body_chain_matches_the_energy_chain() {
    compare(8);
}

/// N = 32: parse + derive of the body declaration in well under the codegen target
/// (prints the time; asserts < 10 s so a debug build on a loaded 2-core machine passes, while
/// an expression blow-up, which costs minutes, fails).
#[test]
fn body_chain_32_derives_fast() {
    let text = body_chain(32);
    let start = Instant::now();
    let mut m = parse_model_str(&text).unwrap();
    let e = derive(&mut m).unwrap();
    let took = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut energy = closed_chain_model(32);
    derive(&mut energy).unwrap();
    let energy_took = start.elapsed().as_secs_f64();
    println!(
        "N = 32 chain: bodies parse + derive {took:.3} s ({} nodes); energy-built derive {energy_took:.3} s ({} nodes)",
        m.arena.len(),
        energy.arena.len()
    );
    assert_eq!((e.n, e.m), (32, 2));
    assert!(took < 10.0, "{took} s");
}

/// The same comparison at N = 32 (slower: evaluates both 32 x 32 systems).
#[test]
#[ignore]
fn body_chain_32_matches_the_energy_chain() {
    compare(32);
}
