//! Differentiation rules as exact canonical forms (one line per rule), errors, and the cost
//! guarantees (independent subtrees untouched, deep trees without recursion).

use mechanism_codegen::error::AlgebraError;
use mechanism_codegen::{Arena, Differentiator, Error, Func, Id, SymbolId, SymbolKind};

struct Fx {
    a: Arena,
    x: Id,
    y: Id,
    sx: SymbolId,
}

fn fx() -> Fx {
    let mut a = Arena::new();
    let x = a.symbol("x", SymbolKind::Free);
    let y = a.symbol("y", SymbolKind::Free);
    let sx = a.as_symbol(x).unwrap();
    Fx { a, x, y, sx }
}

/// One rule per line: (name, f(x, y), expected d f / d x), both built in the same arena.
type Case = (
    &'static str,
    fn(&mut Arena, Id, Id) -> Id,
    fn(&mut Arena, Id, Id) -> Id,
);

const CASES: &[Case] = &[
    ("constant", |a, _, y| a.mul2(y, y), |a, _, _| a.int(0)),
    ("x", |_, x, _| x, |a, _, _| a.int(1)),
    (
        "x^3 = 3 x^2",
        |a, x, _| a.powi(x, 3).unwrap(),
        |a, x, _| {
            let x2 = a.powi(x, 2).unwrap();
            let three = a.int(3);
            a.mul2(three, x2)
        },
    ),
    (
        "1/x = -x^-2",
        |a, x, _| a.powi(x, -1).unwrap(),
        |a, x, _| {
            let p = a.powi(x, -2).unwrap();
            a.neg(p)
        },
    ),
    (
        "sqrt x = 1/2 x^-1/2",
        |a, x, _| a.sqrt(x).unwrap(),
        |a, x, _| {
            let e = a.rational(-1, 2).unwrap();
            let p = a.pow(x, e).unwrap();
            let h = a.rational(1, 2).unwrap();
            a.mul2(h, p)
        },
    ),
    (
        "x y sin x: n-ary product rule",
        |a, x, y| {
            let s = a.sin(x);
            a.mul(&[x, y, s])
        },
        |a, x, y| {
            let (s, c) = (a.sin(x), a.cos(x));
            let t1 = a.mul2(y, s);
            let t2 = a.mul(&[x, y, c]);
            a.add2(t1, t2)
        },
    ),
    ("sin = cos", |a, x, _| a.sin(x), |a, x, _| a.cos(x)),
    (
        "cos = -sin",
        |a, x, _| a.cos(x),
        |a, x, _| {
            let s = a.sin(x);
            a.neg(s)
        },
    ),
    (
        "tan = 1 + tan^2",
        |a, x, _| a.func(Func::Tan, x).unwrap(),
        |a, x, _| {
            let t = a.func(Func::Tan, x).unwrap();
            let t2 = a.powi(t, 2).unwrap();
            let one = a.int(1);
            a.add2(one, t2)
        },
    ),
    (
        "exp = exp",
        |a, x, _| a.func(Func::Exp, x).unwrap(),
        |a, x, _| a.func(Func::Exp, x).unwrap(),
    ),
    (
        "ln = 1/x",
        |a, x, _| a.func(Func::Ln, x).unwrap(),
        |a, x, _| a.powi(x, -1).unwrap(),
    ),
    (
        "abs(x y) = y x y/|x y|",
        |a, x, y| {
            let p = a.mul2(x, y);
            a.func(Func::Abs, p).unwrap()
        },
        |a, x, y| {
            let p = a.mul2(x, y);
            let ab = a.func(Func::Abs, p).unwrap();
            let inv = a.powi(ab, -1).unwrap();
            a.mul(&[p, inv, y])
        },
    ),
    (
        "atan2(y, x) = -y/(x^2 + y^2)",
        |a, x, y| a.atan2(y, x),
        |a, x, y| {
            let (x2, y2) = (a.powi(x, 2).unwrap(), a.powi(y, 2).unwrap());
            let den = a.add2(x2, y2);
            let ny = a.neg(y);
            a.div(ny, den).unwrap()
        },
    ),
    (
        "y^x = y^x ln y",
        |a, x, y| a.pow(y, x).unwrap(),
        |a, x, y| {
            let p = a.pow(y, x).unwrap();
            let l = a.func(Func::Ln, y).unwrap();
            a.mul2(p, l)
        },
    ),
    (
        "x^x = x^x (ln x + 1)",
        |a, x, _| a.pow(x, x).unwrap(),
        |a, x, _| {
            let p = a.pow(x, x).unwrap();
            let l = a.func(Func::Ln, x).unwrap();
            let one = a.int(1);
            let s = a.add2(l, one);
            a.mul2(p, s)
        },
    ),
    (
        "x^y = y x^(y-1)",
        |a, x, y| a.pow(x, y).unwrap(),
        |a, x, y| {
            let m1 = a.int(-1);
            let e = a.add2(y, m1);
            let p = a.pow(x, e).unwrap();
            a.mul2(y, p)
        },
    ),
    (
        "sin^2 + cos^2 differentiates to 0",
        |a, x, _| {
            let (s, c) = (a.sin(x), a.cos(x));
            let (s2, c2) = (a.powi(s, 2).unwrap(), a.powi(c, 2).unwrap());
            let y2 = a.mul2(s2, s2);
            let sum = a.add2(s2, c2);
            a.add2(sum, y2)
        },
        |a, x, _| {
            let (s, c) = (a.sin(x), a.cos(x));
            let s3 = a.powi(s, 3).unwrap();
            let four = a.int(4);
            a.mul(&[four, s3, c])
        },
    ),
];

#[test]
fn rules_give_canonical_forms() {
    for (name, f, expected) in CASES {
        let mut t = fx();
        let e = f(&mut t.a, t.x, t.y);
        let want = expected(&mut t.a, t.x, t.y);
        let got = Differentiator::new().diff(&mut t.a, e, t.sx).unwrap();
        assert_eq!(got, want, "rule {name}");
    }
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let mut t = fx();
    let mut d = Differentiator::new();
    assert!(matches!(
        d.diff(&mut t.a, Id::new(10_000), t.sx),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    assert!(matches!(
        d.diff(&mut t.a, t.x, SymbolId::new(77)),
        Err(Error::Algebra(AlgebraError::UnknownSymbolId { .. }))
    ));
    assert!(matches!(
        d.time_derivative(&mut t.a, Id::new(10_000)),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    assert!(matches!(
        d.depends_on(&t.a, Id::new(10_000), t.sx),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    // A constant divided by 0 names the operation, as a rational or as a power of 0.
    let error = t.a.rational(3, 0).unwrap_err();
    assert!(
        matches!(&error, Error::Algebra(AlgebraError::DivisionByZero { operation }) if operation == "3/0"),
        "{error:?}"
    );
    let (zero, minus_two) = (t.a.int(0), t.a.int(-2));
    let error = t.a.pow(zero, minus_two).unwrap_err();
    assert_eq!(
        error.to_string(),
        "division by zero in the constant expression `0^-2`"
    );
    // d/dx (-2)^x needs ln(-2).
    let m2 = t.a.int(-2);
    let p = t.a.pow(m2, t.x).unwrap();
    assert!(matches!(
        d.diff(&mut t.a, p, t.sx),
        Err(Error::Algebra(AlgebraError::Domain { .. }))
    ));
    // The time derivative of an acceleration would be a third derivative.
    let [_, _, qdd] = t.a.coordinate("q");
    assert!(matches!(
        d.time_derivative(&mut t.a, qdd),
        Err(Error::Algebra(AlgebraError::ThirdDerivative { .. }))
    ));
}

#[test]
fn time_derivative_follows_links() {
    let mut a = Arena::new();
    let [q, qd, qdd] = a.coordinate("q");
    let t = a.symbol("t", SymbolKind::Time);
    let p = a.symbol("p", SymbolKind::Parameter);
    let mut d = Differentiator::new();
    // d/dt (p q' sin q + t^2) = p q'' sin q + p q'^2 cos q + 2 t
    let (s, c) = (a.sin(q), a.cos(q));
    let pq = a.mul(&[p, qd, s]);
    let t2 = a.powi(t, 2).unwrap();
    let e = a.add2(pq, t2);
    let got = d.time_derivative(&mut a, e).unwrap();
    let qd2 = a.powi(qd, 2).unwrap();
    let two = a.int(2);
    let terms = [a.mul(&[p, qdd, s]), a.mul(&[p, qd2, c]), a.mul2(two, t)];
    assert_eq!(got, a.add(&terms));
    // With q'' = 0: the first term goes.
    let conv = d.convective_derivative(&mut a, e).unwrap();
    assert_eq!(conv, a.add(&terms[1..]));
}

#[test]
fn independent_subtrees_cost_nothing() {
    let mut t = fx();
    // A big expression in y only.
    let mut e = t.y;
    for k in 1..200 {
        let c = t.a.int(k);
        let s = t.a.sin(e);
        let m = t.a.mul2(c, s);
        e = t.a.add2(m, t.y);
    }
    let zero = t.a.int(0);
    let before = t.a.len();
    let mut d = Differentiator::new();
    assert_eq!(d.diff(&mut t.a, e, t.sx).unwrap(), zero);
    assert_eq!(
        t.a.len(),
        before,
        "no node is built for an independent expression"
    );
    assert!(!d.depends_on(&t.a, e, t.sx).unwrap());
    let sy = t.a.as_symbol(t.y).unwrap();
    assert_eq!(d.symbols_of(&t.a, e).unwrap(), vec![sy]);
}

#[test]
fn deep_nesting_does_not_recurse() {
    let mut t = fx();
    let mut e = t.x;
    for _ in 0..3000 {
        e = t.a.sin(e);
    }
    let d = Differentiator::new().diff(&mut t.a, e, t.sx).unwrap();
    // d/dx sin(sin(...(x))) is the product of the 3000 cosines.
    assert!(matches!(t.a.node(d), mechanism_codegen::Node::Mul(fs) if fs.len() == 3000));
}

#[test]
fn a_smaller_arena_resets_the_caches() {
    let mut big = fx();
    let mut e = big.x;
    for _ in 0..50 {
        e = big.a.sin(e);
    }
    let mut d = Differentiator::new();
    d.diff(&mut big.a, e, big.sx).unwrap();
    let mut small = fx();
    small.a.symbol("w", SymbolKind::Free); // node 2: sin(x) is node 3 here, sin(sin(x)) in `big`
    let s = small.a.sin(small.x);
    assert_eq!(s, Id::new(3));
    assert_eq!(
        d.diff(&mut small.a, s, small.sx).unwrap(),
        small.a.cos(small.x)
    );
}
