//! The recursive route's two forward dynamics against each other: the articulated-body
//! algorithm and the factorisation of M (`mechanics::forward_dynamics`) share nothing but
//! the bodies, and must give the same q''.

use crate::algebra::eval::eval_many;
use crate::algebra::expr::{Id, SymbolId, SymbolKind};
use crate::mechanics::forward_dynamics::forward_dynamics;
use crate::mechanics::recursive::articulated_forward_dynamics;

/// The spatial tree of codegen's route tests: a general axis, a negative axis, a prismatic
/// joint below a fixed link, a branch.
const TREE: &str = include_str!("../../../tests/bodies/link_tree.mech");

/// q'' by both routes at 10 states with efforts, to 1e-12 of the largest |q''|: each
/// solve errs by about eps cond(M) |q''| (the two differ by below 1e-15 of it here, so the
/// margin covers cond(M) up to 1e3), and every pivot of the recursion is positive.
#[test]
fn the_articulated_body_algorithm_agrees_with_the_factorisation_of_m() {
    let mut model = crate::parse_model_str(TREE).unwrap();
    let eqs = crate::derive(&mut model).unwrap();
    let n = eqs.n;
    let effort: Vec<Id> = (0..n)
        .map(|k| model.arena.symbol(&format!("u{k}"), SymbolKind::Free))
        .collect();
    let (aba, pivots) = articulated_forward_dynamics(&mut model, &effort).unwrap();
    let order: Vec<usize> = (0..n).collect();
    let a = &mut model.arena;
    let fd = forward_dynamics(a, &eqs.mass, &eqs.bias, &effort, &order).unwrap();
    let sym = |id: Id| model.arena.as_symbol(id).unwrap();
    for k in 0..10 {
        let mut values: Vec<(SymbolId, f64)> = Vec::new();
        for (i, c) in model.coordinates.iter().enumerate() {
            let x = (7 * k + 3 * i) as f64;
            values.push((sym(c.q), 2.5 * (0.37 * x).sin()));
            values.push((sym(c.qd), 1.7 * (0.61 * x + 1.0).cos()));
            values.push((sym(effort[i]), 3.0 * (0.23 * x + 2.0).sin()));
        }
        let g = model.parameters[0].symbol;
        values.push((sym(g), 9.81));
        let env = |s: SymbolId| values.iter().find(|v| v.0 == s).map(|v| v.1);
        let arena = &model.arena;
        let ours = eval_many(arena, aba.data(), &env).unwrap();
        let theirs = eval_many(arena, fd.accelerations.data(), &env).unwrap();
        let d = eval_many(arena, pivots.data(), &env).unwrap();
        assert!(d.iter().all(|&x| x > 0.0), "positive pivots {d:?}");
        let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for (i, (x, y)) in ours.iter().zip(&theirs).enumerate() {
            assert!(
                (x - y).abs() <= 1e-12 * scale,
                "state {k}, q''[{i}]: {x} vs {y}"
            );
        }
    }
}
