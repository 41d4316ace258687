//! The interpreter (`eval`) against a direct f64 evaluation of random expression trees, and
//! its typed errors.

use mechanism_codegen::error::{AlgebraError, EvalError};
use std::cell::Cell;
use std::collections::HashMap;

use crate::eval_support::{ast, build, close, dag, direct, point, symbols};
use mechanism_codegen::internals::eval_many;
use mechanism_codegen::{Arena, Error, Func, Id, Matrix, SymbolKind, eval, eval_matrix};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// eval of the canonical DAG equals the direct evaluation of the tree it was built from,
    /// within the first-order rounding bound of both operation orders (see eval_support).
    #[test]
    fn eval_matches_direct_tree(e in ast(), x in point()) {
        let mut a = Arena::new();
        let syms = symbols(&mut a);
        let Some(id) = build(&mut a, &syms, &e) else { return Ok(()) };
        let want = direct(&e, &x);
        if !want.v.is_finite() || !want.e.is_finite() {
            return Ok(());
        }
        let env = |s: mechanism_codegen::SymbolId| x.get(s.index()).copied();
        let got = eval(&a, id, &env);
        let reference = dag(&a, id, &|s| x[s.index()], &mut HashMap::new());
        prop_assume!(reference.e.is_finite());
        let got = got.map_err(|err| TestCaseError::fail(format!("eval failed: {err} on a finite case")))?;
        prop_assert!(
            close(got, want.v, reference.e, want.e),
            "eval {got} vs direct {} (bounds {} {})", want.v, reference.e, want.e
        );
    }
}

fn arena_xy() -> (Arena, Id, Id) {
    let mut a = Arena::new();
    let x = a.symbol("x", SymbolKind::Free);
    let y = a.symbol("y", SymbolKind::Free);
    (a, x, y)
}

#[test]
fn missing_symbol_is_named() {
    let (mut a, x, y) = arena_xy();
    let e = a.add2(x, y);
    let err = eval(&a, e, &|s| (s.index() == 0).then_some(1.0)).unwrap_err();
    assert_eq!(
        err,
        Error::Eval(EvalError::MissingValue { name: "y".into() })
    );
}

#[test]
fn runtime_division_by_zero_is_an_error() {
    let (mut a, x, y) = arena_xy();
    let d = a.div(y, x).unwrap();
    let err = eval(&a, d, &|s| Some(if s.index() == 0 { 0.0 } else { 1.0 })).unwrap_err();
    assert!(
        matches!(err, Error::Eval(EvalError::NonFinite { ref operation, .. }) if operation == "division by zero"),
        "{err}"
    );
}

#[test]
fn a_quotient_of_tiny_numbers_is_evaluated_as_a_quotient() {
    // 1e-320 / 1e-320 is 1e-320 * 1e-320^-1, and 1e-320^-1 overflows (issue 29, item 16):
    // the product divides instead. Only a reciprocal that nothing brings back fails.
    let (mut a, x, y) = arena_xy();
    let q = a.div(x, y).unwrap();
    let tiny = |_| Some(1e-320);
    assert_eq!(eval(&a, q, &tiny).unwrap(), 1.0);
    let r = a.div(y, x).unwrap();
    let both = a.mul2(q, r);
    assert_eq!(eval(&a, both, &tiny).unwrap(), 1.0);
    let one = a.int(1);
    let reciprocal = a.div(one, x).unwrap();
    assert!(matches!(
        eval(&a, reciprocal, &tiny),
        Err(Error::Eval(EvalError::NonFinite { ref operation, .. })) if operation == "pow"
    ));
    let sum = a.add2(reciprocal, y);
    assert!(matches!(
        eval(&a, sum, &tiny),
        Err(Error::Eval(EvalError::NonFinite { .. }))
    ));
    let parsed = mechanism_codegen::parse_expr(&mut a, "1e-320/1e-320").unwrap();
    assert_eq!(eval(&a, parsed, &|_| None).unwrap(), 1.0);
}

#[test]
fn domain_errors_are_typed_not_nan() {
    let (mut a, x, _) = arena_xy();
    let ln = a.func(Func::Ln, x).unwrap();
    let sq = a.sqrt(x).unwrap();
    let big = a.func(Func::Exp, x).unwrap();
    let neg = |_| Some(-1.0);
    assert!(matches!(
        eval(&a, ln, &neg),
        Err(Error::Eval(EvalError::NonFinite { .. }))
    ));
    assert!(matches!(
        eval(&a, sq, &neg),
        Err(Error::Eval(EvalError::NonFinite { .. }))
    ));
    assert!(
        matches!(
            eval(&a, big, &|_| Some(1000.0)),
            Err(Error::Eval(EvalError::NonFinite { .. }))
        ),
        "exp overflow"
    );
    assert!(
        matches!(
            eval(&a, x, &|_| Some(f64::NAN)),
            Err(Error::Eval(EvalError::NonFinite { .. }))
        ),
        "NaN input"
    );
    assert_eq!(eval(&a, ln, &|_| Some(1.0)), Ok(0.0));
}

#[test]
fn invalid_ids_and_bad_matrices_are_errors() {
    let (a, x, _) = arena_xy();
    let bad = Id::new(1_000_000);
    assert!(matches!(
        eval(&a, bad, &|_| Some(1.0)),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    assert!(
        Matrix::new(2, 2, vec![x]).is_err(),
        "a malformed matrix cannot be built"
    );
    assert_eq!(eval_many(&a, &[], &|_| Some(1.0)), Ok(vec![]));
}

#[test]
fn deep_chain_does_not_overflow_the_stack() {
    // sin(sin(...sin(x)...)) nested 200_000 deep: a recursive evaluator would overflow.
    // (`eval` computes sin with `trig::sin_cos`, as the tape and the emitted code do.)
    let (mut a, x, _) = arena_xy();
    let mut e = x;
    let mut want = 0.7_f64;
    for _ in 0..200_000 {
        e = a.sin(e);
        want = mechanism_math::sin_cos(want).0;
    }
    assert_eq!(eval(&a, e, &|_| Some(0.7)), Ok(want));
}

#[test]
fn shared_nodes_are_evaluated_once() {
    // e_{k+1} = sin(e_k) + cos(e_k): a tree of 2^60 leaves, a DAG of ~180 nodes. The symbol
    // is looked up once, and the whole evaluation is immediate.
    let (mut a, x, _) = arena_xy();
    let mut e = x;
    let mut want = 0.3_f64;
    for _ in 0..60 {
        let s = a.sin(e);
        let c = a.cos(e);
        e = a.add2(s, c);
        want = want.sin() + want.cos();
    }
    let calls = Cell::new(0);
    let env = |_| {
        calls.set(calls.get() + 1);
        Some(0.3)
    };
    let got = eval(&a, e, &env).unwrap();
    assert_eq!(calls.get(), 1);
    assert!((got - want).abs() <= 1e-14, "{got} vs {want}");
}

#[test]
fn matrix_entries_share_one_walk() {
    let (mut a, x, y) = arena_xy();
    let s = a.sin(x);
    let c = a.cos(x);
    let p = a.mul2(s, y);
    let m = Matrix::new(2, 2, vec![s, c, p, x]).unwrap();
    let calls = Cell::new(0);
    let env = |sym: mechanism_codegen::SymbolId| {
        calls.set(calls.get() + 1);
        Some(if sym.index() == 0 { 0.4 } else { 3.0 })
    };
    let v = eval_matrix(&a, &m, &env).unwrap();
    let (s, c) = mechanism_math::sin_cos(0.4);
    assert_eq!(v, vec![s, c, s * 3.0, 0.4]);
    assert_eq!(calls.get(), 2, "each symbol read once for the whole matrix");
}

#[test]
fn constants_and_pi() {
    let mut a = Arena::new();
    let pi = a.pi();
    let h = a.rational(1, 3).unwrap();
    let e = a.mul2(pi, h);
    assert_eq!(eval(&a, e, &|_| None), Ok(std::f64::consts::PI / 3.0));
}
