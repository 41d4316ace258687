//! Two independent declarations of the same chain agree: `mechanisms/closed_chain.mech`
//! (text, compiled by the macro, X a parameter) and `mechanism_codegen::fixtures::closed_chain_model(4)`
//! (built through the arena API, X = 2 a constant), at random states. Tolerance 1e-12
//! relative to each quantity's largest entry: the two DAGs differ in form (X symbolic or
//! not, different sum orders), so they agree to rounding, not bit for bit.

use mechanism::Mechanism;
use mechanism::builtin::ClosedChain4;
use mechanism_codegen::fixtures::closed_chain_model;
use mechanism_codegen::{Id, Matrix, SymbolId, derive, eval};
use nalgebra::SVector;

#[test]
fn file_equals_the_programmatic_chain() {
    let mut model = closed_chain_model(4);
    let eqs = derive(&mut model).unwrap();
    let chain = ClosedChain4::default();
    assert_eq!(chain.X, 2.0);
    let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..20 {
        let q: Vec<f64> = (0..4).map(|_| 3.0 * next()).collect();
        let qd: Vec<f64> = (0..4).map(|_| 2.0 * next()).collect();
        let arena = &model.arena;
        let env = |k: SymbolId| -> Option<f64> {
            for (i, c) in model.coordinates.iter().enumerate() {
                if arena.as_symbol(c.q) == Some(k) {
                    return Some(q[i]);
                }
                if arena.as_symbol(c.qd) == Some(k) {
                    return Some(qd[i]);
                }
            }
            model
                .parameters
                .iter()
                .position(|p| arena.as_symbol(p.symbol) == Some(k))
                .map(|_| 9.81)
        };
        let value = |id: Id| eval(arena, id, &env).unwrap();
        let entries = |m: &Matrix| -> Vec<f64> { m.data().iter().map(|&x| value(x)).collect() };
        let (qs, qds) = (
            SVector::<f64, 4>::from_column_slice(&q),
            SVector::<f64, 4>::from_column_slice(&qd),
        );
        let e = chain.evaluate(0.0, &qs, &qds);
        // Row-major (codegen) against nalgebra's (i, j).
        let compare = |what: &str, expected: Vec<f64>, got: &dyn Fn(usize) -> f64| {
            let scale = expected.iter().fold(1e-300_f64, |s, x| s.max(x.abs()));
            for (k, x) in expected.iter().enumerate() {
                assert!(
                    (got(k) - x).abs() <= 1e-12 * scale,
                    "{what}[{k}]: {} vs {x}",
                    got(k)
                );
            }
        };
        compare("M", entries(&eqs.mass), &|k| e.mass[(k / 4, k % 4)]);
        compare("C q'", entries(&eqs.coriolis_forces), &|k| e.coriolis[k]);
        compare("g", entries(&eqs.gravity), &|k| e.gravity[k]);
        compare("Phi", entries(&eqs.phi), &|k| e.phi[k]);
        compare("Phi_q", entries(&eqs.phi_q), &|k| e.phi_q[(k / 4, k % 4)]);
        compare("gamma", entries(&eqs.gamma), &|k| e.gamma[k]);
        compare("T", vec![value(eqs.kinetic)], &|_| e.kinetic);
        compare("Pi", vec![value(eqs.potential)], &|_| e.potential);
    }
}
