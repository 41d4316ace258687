//! Khang's C against the Christoffel route and against brute-force definitions, for random
//! kinetic energies T = 1/2 sum_k (sum_l a_kl(q) q_l')^2 + 1/2 sum_l (1 + b_l(q)^2) q_l'^2
//! (so M = A^T A + diag(1 + b^2) is positive definite), and for the seed and the chain:
//! - Khang's C q' (the Kronecker-built matrix times q') = the lean `coriolis_forces`
//!   = the Christoffel C q' = the brute-force C_ij = sum_k dM_ij/dq_k q_k'
//!   - 1/2 sum_k dM_jk/dq_i q_k' (num-dual dM) times q';
//! - q'^T (M' - 2 C_Khang) q' = 0 (for Khang's C this quadratic form
//!   vanishes although M' - 2 C_Khang is not skew-symmetric);
//! - M' - 2 C_Christoffel is skew-symmetric;
//! - `coriolis_forces` = d/dt(dT/dq')|_{q''=0} - dT/dq by num-dual on T alone.
//!
//! Tolerance 1e-9 relative (absolute below 1), states with values above 1e4 skipped: each
//! side is a sum of at most a few hundred O(1) products evaluated in f64.

use crate::common::{
    Ast, State, ast, bare_model, build, close, eval_node, mat_vec, oracle_equations,
    try_eval_equations,
};
use mechanism_codegen::fixtures::closed_chain_model;
use mechanism_codegen::internals::{christoffel_coriolis_forces, christoffel_coriolis_matrix};
use mechanism_codegen::{Equations, Model, SymbolId, derive, eval_matrix};
use num_dual::Dual64;
use proptest::prelude::*;

const TOL: f64 = 1e-9;
const BIG: f64 = 1e4;
const N: usize = 3;

fn random_model(a_entries: &[Ast], b_entries: &[Ast]) -> Option<Model> {
    let mut a = mechanism_codegen::Arena::new();
    let coords = ["q1", "q2", "q3"].map(|n| (n, a.coordinate(n)));
    let q = coords.map(|c| c.1[0]);
    let qd = coords.map(|c| c.1[1]);
    let half = a.rational(1, 2).ok()?;
    let one = a.int(1);
    let mut terms = Vec::new();
    for k in 0..2 {
        let mut row = Vec::new();
        for l in 0..N {
            let e = build(&mut a, &a_entries[k * N + l], &q)?;
            row.push(a.mul2(e, qd[l]));
        }
        let s = a.add(&row);
        let s2 = a.mul2(s, s);
        terms.push(a.mul2(half, s2));
    }
    for l in 0..N {
        let b = build(&mut a, &b_entries[l], &q)?;
        let b2 = a.mul2(b, b);
        let w = a.add2(one, b2);
        let v2 = a.mul2(qd[l], qd[l]);
        terms.push(a.mul(&[half, w, v2]));
    }
    let kinetic = a.add(&terms);
    let potential = a.int(0);
    Some(bare_model(a, &coords, kinetic, potential, vec![]))
}

/// All the C checks at one state; `None` when the state is out of the well-conditioned range.
fn check_coriolis(
    model: &mut Model,
    eqs: &Equations,
    q: &[f64],
    qd: &[f64],
    params: &[(&str, f64)],
) -> Option<()> {
    let n = q.len();
    let st = State {
        q,
        qd,
        t: 0.3,
        params,
    };
    let ours = try_eval_equations(model, eqs, &st)?;
    if ours
        .mass
        .iter()
        .chain(&ours.coriolis_matrix)
        .chain(&ours.coriolis_forces)
        .any(|x| !x.is_finite() || x.abs() > BIG)
    {
        return None;
    }
    let oracle = oracle_equations(model, &st);
    let c_chr = christoffel_coriolis_matrix(model, eqs).unwrap();
    let cq_chr = christoffel_coriolis_forces(model, eqs).unwrap();
    let a = &model.arena;
    let table: Vec<(SymbolId, f64)> = model
        .coordinates
        .iter()
        .enumerate()
        .flat_map(|(k, c)| {
            [
                (a.as_symbol(c.q).unwrap(), q[k]),
                (a.as_symbol(c.qd).unwrap(), qd[k]),
            ]
        })
        .chain(params.iter().map(|(name, v)| (a.lookup(name).unwrap(), *v)))
        .collect();
    let env = |s: SymbolId| table.iter().find(|e| e.0 == s).map(|e| e.1);
    let c_chr = eval_matrix(a, &c_chr, &env).ok()?;
    let cq_chr = eval_matrix(a, &cq_chr, &env).ok()?;
    // num-dual dM/dq_k and M' (along q').
    let dm = |dir: &dyn Fn(usize) -> f64| -> Vec<f64> {
        let seeds: Vec<(SymbolId, Dual64)> = model
            .coordinates
            .iter()
            .enumerate()
            .flat_map(|(k, c)| {
                [
                    (a.as_symbol(c.q).unwrap(), Dual64::new(q[k], dir(k))),
                    (a.as_symbol(c.qd).unwrap(), Dual64::from_re(qd[k])),
                ]
            })
            .chain(
                params
                    .iter()
                    .map(|(name, v)| (a.lookup(name).unwrap(), Dual64::from_re(*v))),
            )
            .collect();
        let env = |s: SymbolId| seeds.iter().find(|e| e.0 == s).map(|e| e.1);
        eqs.mass
            .data()
            .iter()
            .map(|&e| eval_node(a, e, &env).unwrap().eps)
            .collect()
    };
    let dm_dq: Vec<Vec<f64>> = (0..n)
        .map(|k| dm(&|j| if j == k { 1.0 } else { 0.0 }))
        .collect();
    let mdot = dm(&|j| qd[j]);
    let mut c_brute = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            c_brute[i * n + j] = (0..n)
                .map(|k| dm_dq[k][i * n + j] * qd[k] - 0.5 * dm_dq[i][j * n + k] * qd[k])
                .sum();
        }
    }
    // num-dual's atan2 differentiates atan(y/x), undefined at x = 0: skip such oracle points.
    let mut oracle_values = c_brute
        .iter()
        .chain(&mdot)
        .chain(&oracle.coriolis_forces)
        .chain(&c_chr)
        .chain(&cq_chr);
    if oracle_values.any(|x| !x.is_finite() || x.abs() > BIG) {
        return None;
    }
    for (i, (x, y)) in ours.coriolis_matrix.iter().zip(&c_brute).enumerate() {
        assert!(close(*x, *y, TOL), "Khang C[{i}]: {x} vs brute force {y}");
    }
    let khang_cq = mat_vec(&ours.coriolis_matrix, qd);
    for i in 0..n {
        assert!(
            close(khang_cq[i], ours.coriolis_forces[i], TOL),
            "C q'[{i}]: Khang {} vs lean {}",
            khang_cq[i],
            ours.coriolis_forces[i]
        );
        assert!(
            close(cq_chr[i], ours.coriolis_forces[i], TOL),
            "C q'[{i}]: Christoffel {} vs lean {}",
            cq_chr[i],
            ours.coriolis_forces[i]
        );
        assert!(
            close(oracle.coriolis_forces[i], ours.coriolis_forces[i], TOL),
            "C q'[{i}]: oracle {} vs ours {}",
            oracle.coriolis_forces[i],
            ours.coriolis_forces[i]
        );
    }
    // q'^T (M' - 2 C_Khang) q' = 0
    let mut quad = 0.0;
    let mut scale = 0.0;
    for i in 0..n {
        for j in 0..n {
            let w = (mdot[i * n + j] - 2.0 * ours.coriolis_matrix[i * n + j]) * qd[i] * qd[j];
            quad += w;
            scale += w.abs();
        }
    }
    assert!(
        quad.abs() <= TOL * scale.max(1.0),
        "q'^T (M' - 2C) q' = {quad}"
    );
    // M' - 2 C_Christoffel is skew-symmetric (Khang's C is not, in general).
    for i in 0..n {
        for j in 0..n {
            let s =
                mdot[i * n + j] - 2.0 * c_chr[i * n + j] + mdot[j * n + i] - 2.0 * c_chr[j * n + i];
            assert!(
                s.abs() <= TOL * (1.0 + mdot[i * n + j].abs() + c_chr[i * n + j].abs()),
                "(M' - 2C)[{i},{j}] not skew: {s}"
            );
        }
    }
    Some(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, max_global_rejects: 4096, ..ProptestConfig::default() })]

    #[test]
    fn khang_and_christoffel_agree_on_random_kinetic_energies(
        ea in prop::collection::vec(ast(), 2 * N),
        eb in prop::collection::vec(ast(), N),
        q in prop::array::uniform3(-1.5f64..1.5),
        qd in prop::array::uniform3(-1.5f64..1.5),
    ) {
        let Some(mut model) = random_model(&ea, &eb) else { return Ok(()) };
        let eqs = derive(&mut model).unwrap();
        prop_assume!(check_coriolis(&mut model, &eqs, &q, &qd, &[]).is_some());
    }
}

#[test]
fn chain_khang_equals_christoffel() {
    let mut model = closed_chain_model(6);
    let eqs = derive(&mut model).unwrap();
    let mut rng = crate::common::Rng(7);
    for _ in 0..5 {
        let q: Vec<f64> = (0..6).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let qd: Vec<f64> = (0..6).map(|_| rng.uniform(-2.0, 2.0)).collect();
        check_coriolis(&mut model, &eqs, &q, &qd, &[("g", 9.81)]).expect("well conditioned");
    }
}

/// A 2-dof model whose M depends on q (a double pendulum in relative angles), so that the
/// Coriolis matrix is non-trivial and Khang's C differs from the Christoffel C while C q'
/// agrees.
#[test]
fn khang_c_is_not_christoffel_c_but_c_qdot_agrees() {
    let mut a = mechanism_codegen::Arena::new();
    let c1 = a.coordinate("a");
    let c2 = a.coordinate("b");
    // T = 1/2 (3 + 2 cos b) a'^2 + (1 + cos b) a' b' + 1/2 b'^2
    let cb = a.cos(c2[0]);
    let (one, two, three, half) = (a.int(1), a.int(2), a.int(3), a.rational(1, 2).unwrap());
    let two_cb = a.mul2(two, cb);
    let m11 = a.add2(three, two_cb);
    let m12 = a.add2(one, cb);
    let ad2 = a.mul2(c1[1], c1[1]);
    let bd2 = a.mul2(c2[1], c2[1]);
    let t = [
        a.mul(&[half, m11, ad2]),
        a.mul(&[m12, c1[1], c2[1]]),
        a.mul2(half, bd2),
    ];
    let kinetic = a.add(&t);
    let potential = a.int(0);
    let mut model = bare_model(a, &[("a", c1), ("b", c2)], kinetic, potential, vec![]);
    let eqs = derive(&mut model).unwrap();
    let (q, qd) = ([0.3, 0.9], [1.2, -0.7]);
    check_coriolis(&mut model, &eqs, &q, &qd, &[]).expect("well conditioned");
    let chr = christoffel_coriolis_matrix(&mut model, &eqs).unwrap();
    let a = &model.arena;
    let table = [
        (a.lookup("a").unwrap(), q[0]),
        (a.lookup("b").unwrap(), q[1]),
        (a.lookup("der(a)").unwrap(), qd[0]),
        (a.lookup("der(b)").unwrap(), qd[1]),
    ];
    let env = |s| table.iter().find(|e| e.0 == s).map(|e| e.1);
    let c = eqs.coriolis_matrix.as_ref().expect("the energy route's C");
    let ck = eval_matrix(a, c, &env).unwrap();
    let cc = eval_matrix(a, &chr, &env).unwrap();
    assert!(
        ck.iter().zip(&cc).any(|(x, y)| (x - y).abs() > 1e-3),
        "the two factorisations differ: {ck:?} vs {cc:?}"
    );
}
