//! The CSE'd program (run through the `Tape`) against the interpreter on random multi-output
//! programs; structural invariants of the program (sin/cos computed once per argument,
//! consistent op counts, restriction).

use mechanism_codegen::error::{AlgebraError, EvalError};
use std::collections::HashMap;

use crate::eval_support::{Ast, ast, build, close, dag, point, symbols};
use mechanism_codegen::internals::{Instr, UnOp};
use mechanism_codegen::{
    Arena, Error, Id, Matrix, Operand, Program, SymbolId, SymbolKind, Tape, eval, eval_matrix,
};
use proptest::prelude::*;

/// Builds the trees into an arena and splits them into two output matrices (a column and
/// a row), so that sharing across outputs is exercised.
fn outputs(es: &[Ast]) -> Option<(Arena, Matrix, Matrix)> {
    let mut a = Arena::new();
    let syms = symbols(&mut a);
    let ids: Vec<Id> = es
        .iter()
        .map(|e| build(&mut a, &syms, e))
        .collect::<Option<_>>()?;
    let h = ids.len() / 2;
    let col = Matrix::column(ids[..h].to_vec());
    let row = Matrix::new(1, ids.len() - h, ids[h..].to_vec()).unwrap();
    Some((a, col, row))
}

/// The argument operands of all sin/cos/sin_cos instructions.
fn trig_args(p: &Program) -> Vec<(Operand, &'static str)> {
    p.instructions()
        .iter()
        .filter_map(|i| match *i {
            Instr::SinCos { arg, .. } => Some((arg, "sin_cos")),
            Instr::Unary {
                op: UnOp::Sin, arg, ..
            } => Some((arg, "sin")),
            Instr::Unary {
                op: UnOp::Cos, arg, ..
            } => Some((arg, "cos")),
            _ => None,
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// CSE preserves the value: the tape of the program over all outputs equals `eval` of
    /// each entry. The two routes execute the same operations of the same DAG, possibly
    /// reassociated (sums start at a positive term, coefficients apply last, x^3 = x*x*x,
    /// x^-k = 1/x^k, x/c = (1/c)*x, tan = sin/cos), so they differ by rounding only: within the
    /// first-order bound 16 eps E of that DAG (see eval_support; 1e-13 relative or better
    /// whenever the expression is well conditioned).
    #[test]
    fn tape_equals_eval(es in proptest::collection::vec(ast(), 1..6), x in point()) {
        let Some((a, col, row)) = outputs(&es) else { return Ok(()) };
        let env = |s: SymbolId| x.get(s.index()).copied();
        let (Ok(e1), Ok(e2)) = (eval_matrix(&a, &col, &env), eval_matrix(&a, &row, &env)) else {
            return Ok(());
        };
        let p = Program::new(&a, &[&col, &row]).unwrap();
        let mut tape = Tape::new(&p);
        let mut out = vec![0.0; tape.output_len()];
        tape.eval(&x, &mut out).unwrap();
        let want: Vec<f64> = e1.into_iter().chain(e2).collect();
        let ids: Vec<Id> = col.data().iter().chain(row.data()).copied().collect();
        let mut memo = HashMap::new();
        for ((got, want), id) in out.iter().zip(&want).zip(&ids) {
            let bound = dag(&a, *id, &|s| x[s.index()], &mut memo).e;
            prop_assume!(bound.is_finite());
            prop_assert!(close(*got, *want, bound, bound), "tape {got} vs eval {want} (bound {bound})");
        }
    }

    /// sin and cos of each argument are computed once for the whole program, and every
    /// argument needing both uses one sin_cos.
    #[test]
    fn trig_of_each_argument_once(es in proptest::collection::vec(ast(), 1..6)) {
        let Some((a, col, row)) = outputs(&es) else { return Ok(()) };
        // A constant subexpression that overflows is a (tested) error; nothing to check then.
        let Ok(p) = Program::new(&a, &[&col, &row]) else { return Ok(()) };
        let args = trig_args(&p);
        for (k, (x, _)) in args.iter().enumerate() {
            prop_assert!(args[k + 1..].iter().all(|(y, _)| y != x), "two trig instructions for {x:?}: {args:?}");
        }
    }

    /// Op counts: the whole program is the sum over its instructions (a fused multiply-add
    /// counts as a multiplication and an addition); each output's count is
    /// at most the total; outputs together count shared instructions once; restricting the
    /// program to some outputs keeps their values and counts; built alone, an output has
    /// the same values within rounding.
    #[test]
    fn op_counts_and_restriction(es in proptest::collection::vec(ast(), 2..6), x in point()) {
        let Some((a, col, row)) = outputs(&es) else { return Ok(()) };
        let Ok(p) = Program::new(&a, &[&col, &row]) else { return Ok(()) };
        let total = p.op_counts();
        // One operation per instruction, two for a fused multiply-add.
        let fused = p.instructions().iter().filter(|i| matches!(i, Instr::MulAdd { .. })).count();
        prop_assert_eq!(total.total(), p.instructions().len() + fused);
        let (c0, c1) = (p.output_op_counts(0).unwrap(), p.output_op_counts(1).unwrap());
        prop_assert!(c0.total() <= total.total() && c1.total() <= total.total());
        prop_assert!(c0.total() + c1.total() >= total.total());
        prop_assert_eq!(p.op_counts_of(&[0, 1]), total);
        prop_assert_eq!(p.output_op_counts(2), None);
        let r = p.restrict(&[1]).unwrap();
        prop_assert_eq!(r.op_counts(), c1);
        prop_assert_eq!(r.outputs().len(), 1);
        // Built alone, the same output may cost fewer operations than its restriction: the
        // passes decide by the readers a value has (a product fused into the one sum that
        // reads it, factored or derived form), and the other output's readers are gone.
        // Only the values are the same.
        let alone = Program::new(&a, &[&row]).unwrap();
        let mut tp = Tape::new(&p);
        let mut t1 = Tape::new(&r);
        let mut t2 = Tape::new(&alone);
        let mut op = vec![0.0; tp.output_len()];
        let mut o1 = vec![0.0; t1.output_len()];
        let mut o2 = vec![0.0; t2.output_len()];
        if tp.eval(&x, &mut op).is_ok() {
            // Restriction keeps the very instructions: bit for bit the full program's values.
            t1.eval(&x, &mut o1).unwrap();
            prop_assert_eq!(&o1[..], &op[col.data().len()..]);
            // Built alone, sin(u) may be a lone `sin` where the full program paired it into
            // `sin_cos` (libm's two may differ in the last ulp): equal within the first-order
            // rounding bound of the DAG.
            t2.eval(&x, &mut o2).unwrap();
            let mut memo = HashMap::new();
            for ((a1, a2), id) in o1.iter().zip(&o2).zip(row.data()) {
                let bound = dag(&a, *id, &|s| x[s.index()], &mut memo).e;
                prop_assume!(bound.is_finite());
                prop_assert!(close(*a1, *a2, bound, bound), "restricted {a1} vs alone {a2} (bound {bound})");
            }
        }
    }
}

fn two_angles() -> (Arena, Id, Id) {
    let mut a = Arena::new();
    let [p, ..] = a.coordinate("th1");
    let [q, ..] = a.coordinate("th2");
    (a, p, q)
}

#[test]
fn sin_and_cos_in_different_outputs_share_one_sin_cos() {
    let (mut a, p, q) = two_angles();
    let u = a.sub(p, q);
    let s = a.sin(u);
    let c = a.cos(u);
    let sp = a.sin(p);
    let m1 = Matrix::column(vec![s, sp]);
    let m2 = Matrix::column(vec![c]);
    let prog = Program::new(&a, &[&m1, &m2]).unwrap();
    let args = trig_args(&prog);
    assert_eq!(args.len(), 2, "{args:?}");
    assert_eq!(
        args.iter().filter(|(_, k)| *k == "sin_cos").count(),
        1,
        "sin(u), cos(u) -> one sin_cos"
    );
    assert_eq!(
        args.iter().filter(|(_, k)| *k == "sin").count(),
        1,
        "sin(th1) alone stays sin"
    );
    assert_eq!(prog.op_counts().calls, 2);
    // each output alone needs the pair's one call (plus sin th1 for the first)
    assert_eq!(prog.output_op_counts(0).unwrap().calls, 2);
    assert_eq!(prog.output_op_counts(1).unwrap().calls, 1);
    // the same program restricted to the second output downgrades sin_cos to cos
    let r = prog.restrict(&[1]).unwrap();
    assert!(matches!(
        r.instructions().last(),
        Some(Instr::Unary { op: UnOp::Cos, .. })
    ));
}

#[test]
fn tan_reuses_the_sin_cos_pair() {
    let (mut a, p, _) = two_angles();
    let s = a.sin(p);
    let c = a.cos(p);
    let t = a.func(mechanism_codegen::Func::Tan, p).unwrap();
    let m = Matrix::column(vec![s, c, t]);
    let prog = Program::new(&a, &[&m]).unwrap();
    let n = prog.op_counts();
    assert_eq!(
        (n.calls, n.divs, n.total()),
        (1, 1, 2),
        "sin_cos + one division"
    );
}

#[test]
fn deep_dags_do_not_overflow() {
    let (mut a, p, _) = two_angles();
    let mut e = p;
    for _ in 0..200_000 {
        e = a.sin(e);
    }
    let prog = Program::new(&a, &[&Matrix::column(vec![e])]).unwrap();
    assert_eq!(prog.op_counts().calls, 200_000);
    let mut t = Tape::new(&prog);
    let mut out = [0.0];
    t.eval(&[0.5, 0.0, 0.0], &mut out).unwrap();
    assert_eq!(out[0], eval(&a, e, &|_| Some(0.5)).unwrap());
}

#[test]
fn constant_and_symbol_outputs_need_no_instruction() {
    let (mut a, p, _) = two_angles();
    let h = a.rational(1, 2).unwrap();
    let pi = a.pi();
    let hp = a.mul2(h, pi);
    let prog = Program::new(&a, &[&Matrix::column(vec![h, p, hp])]).unwrap();
    assert!(prog.instructions().is_empty());
    let e = &prog.outputs()[0].entries;
    assert_eq!(e[0], Operand::Const(0.5));
    assert!(matches!(e[1], Operand::Sym(_)));
    assert_eq!(e[2], Operand::Const(std::f64::consts::FRAC_PI_2));
}

#[test]
fn bad_inputs_are_errors() {
    let (a, p, _) = two_angles();
    // A malformed matrix cannot be built, so no program sees one.
    assert!(matches!(
        Matrix::new(2, 2, vec![p]),
        Err(Error::Algebra(AlgebraError::MalformedMatrix { .. }))
    ));
    let out_of_arena = Matrix::column(vec![Id::new(99_999)]);
    assert!(matches!(
        Program::new(&a, &[&out_of_arena]),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    let ok = Program::new(&a, &[&Matrix::column(vec![p])]).unwrap();
    assert!(ok.restrict(&[3]).is_err());
    let empty = Program::new(&a, &[]).unwrap();
    assert_eq!(empty.op_counts().total(), 0);
}

#[test]
fn constant_folding_rejects_non_finite_constants() {
    // exp(1000) of an exact integer stays symbolic in the arena; folding it overflows.
    let mut a = Arena::new();
    let k = a.int(1000);
    let e = a.func(mechanism_codegen::Func::Exp, k).unwrap();
    assert!(a.as_number(e).is_none());
    let err = Program::new(&a, &[&Matrix::column(vec![e])]).unwrap_err();
    assert!(
        matches!(err, Error::Eval(EvalError::NonFinite { .. })),
        "{err}"
    );
    let x = a.symbol("x", SymbolKind::Free);
    let ok = a.mul2(x, e);
    assert!(
        Program::new(&a, &[&Matrix::column(vec![ok])]).is_err(),
        "also inside a product"
    );
}
