//! The cost of a matrix of expressions, read off the graph: what a program lowered from it
//! will compute per call, estimated without lowering it (the compile stage's choice between
//! the derived and the factored form of a routine, the mechanics' choice between two forms
//! of one quantity to differentiate).

use crate::algebra::expr::{Arena, Node, SymbolKind};
use crate::algebra::matrix::Matrix;

/// An estimate of the operations per call of `outputs` lowered from `arena`, read off the
/// graph, over the distinct nodes the outputs reach that depend on a coordinate, rate, time
/// or other non-parameter symbol (the program computes the others once per parameter set):
/// a sum or product of k varying children and some parameter-only ones costs k operations
/// (k - 1 without the parameter-only ones, which make one cached value; a coefficient of
/// -1 is a subtraction, free), a power, function or atan2 one.
pub(crate) fn graph_ops(arena: &Arena, outputs: &[&Matrix]) -> usize {
    let len = arena.len();
    let mut reached = vec![false; len];
    for m in outputs {
        for id in &m.data {
            reached[id.index()] = true;
        }
    }
    // Children precede their parents in the arena: one backward pass marks what is reached.
    for k in (0..len).rev() {
        if reached[k] {
            arena.nodes()[k].for_each_child(|c| reached[c.index()] = true);
        }
    }
    let mut varies = vec![false; len];
    let mut ops = 0;
    for (k, node) in arena.nodes().iter().enumerate() {
        if !reached[k] {
            continue;
        }
        let v = match node {
            Node::Num(_) | Node::Pi => false,
            Node::Sym(s) => arena.symbols()[s.index()].kind != SymbolKind::Parameter,
            _ => {
                let mut any = false;
                node.for_each_child(|c| any |= varies[c.index()]);
                any
            }
        };
        varies[k] = v;
        if v {
            ops += match node {
                // The parameter-only children make one cached value; a coefficient of -1
                // becomes a subtraction.
                Node::Add(t) | Node::Mul(t) => {
                    let varying = t.iter().filter(|c| varies[c.index()]).count();
                    let fixed = t.iter().any(|&c| {
                        !varies[c.index()]
                            && !matches!(arena.node(c), Node::Num(x) if x.abs().is_one())
                    });
                    (varying + usize::from(fixed)).saturating_sub(1)
                }
                // Its child's value: no instruction of its own.
                Node::Named(_) => 0,
                _ => 1,
            };
        }
    }
    ops
}
