//! The closed planar N-bar chain: the programmatic model, its declaration
//! text, and its derived equations against an independent hand-coded Lagrangian
//! (M = sum_i J_Gi^T J_Gi + I/12 from num-dual Jacobians of the midpoints; C q' from the
//! midpoints' convective accelerations), plus the op-count budget against SymPy.
//!
//! Tolerance 1e-10 (relative, absolute below 1): sums of at most N^2 = 64 O(1) products.

use crate::common::{State, close, eval_equations};
use mechanism_codegen::fixtures::{closed_chain_arch, closed_chain_model, closed_chain_source};
use mechanism_codegen::{Program, derive, eval_matrix, parse_expr};
use num_dual::{Dual2_64, Dual64, DualNum};

const TOL: f64 = 1e-10;

/// Midpoint of rod i (0-based) of the chain at angles q.
fn midpoint<D: DualNum<Primitive = f64> + Copy>(q: &[D], i: usize) -> (D, D) {
    let mut x = q[i].cos() * 0.5;
    let mut y = q[i].sin() * 0.5;
    for qj in &q[..i] {
        x += qj.cos();
        y += qj.sin();
    }
    (x, y)
}

/// Hand-coded equations of the N-bar chain at (q, q'): (M, C q', g, Phi, Phi_q, gamma).
#[allow(clippy::type_complexity)]
fn hand_coded(
    q: &[f64],
    qd: &[f64],
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = q.len();
    let dir = |k: usize| -> Vec<Dual64> {
        (0..n)
            .map(|j| Dual64::new(q[j], if j == k { 1.0 } else { 0.0 }))
            .collect()
    };
    // jac[i][k] = d(x_Gi, y_Gi)/dq_k
    let jac: Vec<Vec<(f64, f64)>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|k| {
                    let (x, y) = midpoint(&dir(k), i);
                    (x.eps, y.eps)
                })
                .collect()
        })
        .collect();
    let along: Vec<Dual2_64> = (0..n).map(|j| Dual2_64::new(q[j], qd[j], 0.0)).collect();
    let mut mass = vec![0.0; n * n];
    let mut cq = vec![0.0; n];
    let mut g = vec![0.0; n];
    for i in 0..n {
        let (ax, ay) = midpoint(&along, i);
        for k in 0..n {
            for l in 0..n {
                mass[k * n + l] += jac[i][k].0 * jac[i][l].0 + jac[i][k].1 * jac[i][l].1;
            }
            cq[k] += jac[i][k].0 * ax.v2 + jac[i][k].1 * ay.v2;
            g[k] += 9.81 * jac[i][k].1;
        }
        mass[i * n + i] += 1.0 / 12.0;
    }
    let phi = vec![
        q.iter().map(|t| t.cos()).sum::<f64>() - n as f64 / 2.0,
        q.iter().map(|t| t.sin()).sum(),
    ];
    let mut phi_q = vec![0.0; 2 * n];
    for k in 0..n {
        phi_q[k] = -q[k].sin();
        phi_q[n + k] = q[k].cos();
    }
    let sx: Dual2_64 = along.iter().map(|t| t.cos()).sum();
    let sy: Dual2_64 = along.iter().map(|t| t.sin()).sum();
    let gamma = vec![-sx.v2, -sy.v2];
    (mass, cq, g, phi, phi_q, gamma)
}

#[test]
fn chain_of_8_matches_hand_coded_lagrangian() {
    let n = 8;
    let mut model = closed_chain_model(n);
    let eqs = derive(&mut model).unwrap();
    assert_eq!((eqs.n, eqs.m), (8, 2));
    let mut rng = crate::common::Rng(2024);
    for _ in 0..10 {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-3.1, 3.1)).collect();
        let qd: Vec<f64> = (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let ours = eval_equations(
            &model,
            &eqs,
            &State {
                q: &q,
                qd: &qd,
                t: 0.0,
                params: &[("g", 9.81)],
            },
        );
        let (mass, cq, g, phi, phi_q, gamma) = hand_coded(&q, &qd);
        let pairs = [
            ("M", &ours.mass, &mass),
            ("C q'", &ours.coriolis_forces, &cq),
            ("g", &ours.gravity, &g),
            ("Phi", &ours.phi, &phi),
            ("Phi_q", &ours.phi_q, &phi_q),
            ("gamma", &ours.gamma, &gamma),
        ];
        for (name, x, y) in pairs {
            for (k, (a, b)) in x.iter().zip(y.iter()).enumerate() {
                assert!(
                    close(*a, *b, TOL),
                    "{name}[{k}]: derived {a} vs hand-coded {b}"
                );
            }
        }
        assert!(ours.phi_t.iter().all(|v| *v == 0.0));
    }
}

#[test]
fn chain_model_shape_and_guess() {
    for n in [2, 3, 4, 7, 16] {
        let model = closed_chain_model(n);
        assert_eq!(model.name, format!("ClosedChain{n}"));
        assert_eq!(model.coordinates.len(), n);
        assert_eq!(model.constraints.len(), 2);
        assert_eq!(model.independent.len(), n - 2);
        assert_eq!(model.forces.len(), n);
        assert_eq!(model.parameters.len(), 1);
        // The arch guess closes the loop: Phi(guess) = 0.
        let a = &model.arena;
        let guess = closed_chain_arch(n);
        let table: Vec<_> = model
            .coordinates
            .iter()
            .zip(&guess)
            .map(|(c, v)| (a.as_symbol(c.q).unwrap(), *v))
            .collect();
        let env = |s| table.iter().find(|e: &&(_, f64)| e.0 == s).map(|e| e.1);
        for c in &model.constraints {
            let v = mechanism_codegen::eval(a, c.expr, &env).unwrap();
            assert!(v.abs() < 1e-12, "Phi(guess) = {v} at N = {n}");
        }
        // The last two angles differ, so they are locally determined by the others.
        assert!((guess[n - 1] - guess[n - 2]).sin().abs() > 1e-3);
    }
}

/// The declaration text and the programmatic model are the same expressions: each of
/// `kinetic`, `potential` and the constraint rows, parsed into the model's arena, is the
/// model's own node.
#[test]
fn chain_source_matches_model() {
    let n = 5;
    let mut model = closed_chain_model(n);
    let src = closed_chain_source(n);
    assert!(src.contains("pub struct ClosedChain5;") && src.contains("parameters { g = 9.81; }"));
    let section = |key: &str| -> String {
        let start = src
            .find(key)
            .unwrap_or_else(|| panic!("`{key}` in the source"))
            + key.len();
        src[start..start + src[start..].find(';').unwrap()].to_string()
    };
    let kinetic = parse_expr(&mut model.arena, &section("kinetic =")).unwrap();
    assert_eq!(kinetic, model.kinetic);
    let potential = parse_expr(&mut model.arena, &section("potential =")).unwrap();
    assert_eq!(potential, model.potential);
    let rows = section("constraints {");
    let phi1 = parse_expr(&mut model.arena, &rows).unwrap();
    assert_eq!(phi1, model.constraints[0].expr);
    let after = &src[src.find("constraints {").unwrap()..];
    let second = after.split(';').nth(1).unwrap();
    assert_eq!(
        parse_expr(&mut model.arena, second).unwrap(),
        model.constraints[1].expr
    );
    for (k, c) in model.coordinates.iter().enumerate() {
        assert!(
            src.contains(&format!("{} = {:.12};", c.name, c.guess)),
            "guess of coordinate {k}"
        );
    }
}

/// Lean expressions: ops after CSE of (M, C q', g, Phi, Phi_q, gamma) at or below SymPy's
/// (SymPy's cse leaves 293, 1013, 3605 and 13397 ops at N = 4, 8, 16, 32).
#[test]
fn chain_ops_at_or_below_sympy() {
    for (n, sympy) in [(4, 293), (8, 1013), (16, 3605), (32, 13397)] {
        let mut model = closed_chain_model(n);
        let eqs = derive(&mut model).unwrap();
        let outputs = [
            &eqs.mass,
            &eqs.coriolis_forces,
            &eqs.gravity,
            &eqs.phi,
            &eqs.phi_q,
            &eqs.gamma,
        ];
        let ops = Program::new(&model.arena, &outputs)
            .unwrap()
            .op_counts()
            .total();
        assert!(ops <= sympy, "N = {n}: {ops} ops after CSE, SymPy {sympy}");
        // And gamma for the chain is exactly [sum cos th_i th_i'^2, sum sin th_i th_i'^2].
        let a = &model.arena;
        let env = |s| {
            if a.symbol_info(s).name.starts_with("der") {
                Some(1.5)
            } else {
                Some(0.25)
            }
        };
        let gamma = eval_matrix(a, &eqs.gamma, &env).unwrap();
        assert!(
            close(gamma[0], n as f64 * 0.25f64.cos() * 2.25, 1e-12)
                && close(gamma[1], n as f64 * 0.25f64.sin() * 2.25, 1e-12)
        );
    }
}

#[test]
fn degenerate_chains_do_not_panic() {
    let mut empty = closed_chain_model(0);
    assert!(derive(&mut empty).is_err(), "no coordinates");
    assert!(closed_chain_source(0).contains("pub struct ClosedChain0;"));
    let mut one = closed_chain_model(1);
    let eqs = derive(&mut one).unwrap();
    assert_eq!((eqs.n, eqs.m), (1, 2));
    assert!(one.independent.is_empty());
}

/// The whole declaration, parsed as a model, derives the same equations as the programmatic
/// model (numerically at random states), with the same coordinates, guesses and independents.
#[test]
fn parsed_chain_source_derives_the_same_equations() {
    let n = 6;
    let mut built = closed_chain_model(n);
    let mut parsed = mechanism_codegen::parse_model_str(&closed_chain_source(n)).unwrap();
    assert_eq!(parsed.name, built.name);
    assert_eq!(parsed.independent.len(), n - 2);
    for (p, b) in parsed.coordinates.iter().zip(&built.coordinates) {
        assert_eq!(p.name, b.name);
        assert!((p.guess - b.guess).abs() < 1e-11);
    }
    let eb = derive(&mut built).unwrap();
    let ep = derive(&mut parsed).unwrap();
    let mut rng = crate::common::Rng(99);
    for _ in 0..3 {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qd: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let st = State {
            q: &q,
            qd: &qd,
            t: 0.0,
            params: &[("g", 9.81)],
        };
        let (x, y) = (
            eval_equations(&built, &eb, &st),
            eval_equations(&parsed, &ep, &st),
        );
        let pairs = [
            (&x.mass, &y.mass),
            (&x.coriolis_forces, &y.coriolis_forces),
            (&x.gravity, &y.gravity),
            (&x.phi_q, &y.phi_q),
            (&x.gamma, &y.gamma),
        ];
        for (a, b) in pairs {
            assert!(
                a.iter().zip(b).all(|(u, v)| close(*u, *v, TOL)),
                "{a:?} vs {b:?}"
            );
        }
    }
}
